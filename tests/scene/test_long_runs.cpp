// Long animations (issue 19): SceneRunner computes the frames run_scene keeps, one at a time;
// FrameWriter removes a run's files unless kept; `spinmotor deform` stopped by SIGINT or SIGTERM
// half-way through exits with 128 + signal, says on stderr how many frames are complete, and leaves on
// disk exactly frames 0 .. k−1, each with all its outputs complete (mesh, metrics, colours), and no
// temporary file.
#include <signal.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "cli_support.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/scene/run.hpp"
#include "spinmotor/scene/scene.hpp"

namespace test_long_runs {

using namespace spinmotor;
using nlohmann::json;
namespace fs = std::filesystem;
using spinmotor_test::TempDir;

namespace {

constexpr int kFrames = 2000;  // far more than a test waits for: the run is always stopped mid-way

/// A small capsule (~80 vertices) whose tip bends back and forth over kFrames frames, every output on.
fs::path write_scene(const fs::path& dir) {
  json doc = json::parse(R"({
    "mesh": {"generate": "capsule", "radius": 0.5, "length": 3, "rings": 8, "sides": 8},
    "handles": [{"name": "base", "select": {"box": {"min": [-1, -1, -1], "max": [1, 1, -0.2]}}},
                {"name": "tip", "select": {"box": {"min": [-1, -1, 3.2], "max": [1, 1, 4]}}}],
    "deformer": {"type": "surface-harmonic"},
    "output": {"mesh": "out/c.obj", "metrics": "out/c.json", "colors": "out/c_q.ply"}})");
  for (int k = 0; k < kFrames; ++k) {
    json tip = json::parse(R"({"rotate": {"axis": [1, 0, 0], "about": [0, 0, 3]}})");
    tip["rotate"]["degrees"] = 30.0 * (k % 20) / 20;
    doc["frames"].push_back({{"tip", tip}});
  }
  const fs::path p = dir / "long.json";
  std::ofstream(p) << doc.dump();
  return p;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string frame_name(const char* stem, int f, const char* ext) {
  char b[64];
  std::snprintf(b, sizeof b, "%s.%04d%s", stem, f, ext);
  return b;
}

/// Runs the scene, sends `sig` once at least 3 frames are on disk, and checks the exit code, the
/// message and every file left.
void interrupt_and_check(int sig) {
  TempDir tmp;
  const fs::path scene_file = write_scene(tmp.path);
  const scene::Scene scene = scene::load_scene(scene_file);
  const fs::path out = tmp.path / "run", frames = out / "out";
  const pid_t pid =
      spinmotor_test::spawn({SPINMOTOR_CLI, "deform", scene_file.string(), "--out-dir", out.string()},
                            tmp.path / "stdout.txt", tmp.path / "stderr.txt");
  // Wait for frame 2's metrics (each frame writes mesh, metrics, colours in that order).
  const auto t0 = std::chrono::steady_clock::now();
  while (!fs::exists(frames / frame_name("c", 2, ".json")) && !spinmotor_test::has_exited(pid) &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  REQUIRE(kill(pid, sig) == 0);
  const int code = spinmotor_test::wait_exit(pid);
  const std::string err = slurp(tmp.path / "stderr.txt");
  CAPTURE(err);
  CHECK(code == 128 + sig);

  // One line says how many frames are complete; exactly those are on disk, each whole.
  std::smatch m;
  const std::string name = sig == SIGINT ? "SIGINT" : "SIGTERM";
  REQUIRE(std::regex_search(
      err, m,
      std::regex("spinmotor: interrupted by " + name + ": deform stopped after ([0-9]+) of 2000 frames")));
  const int done = std::stoi(m[1]);
  CHECK(done >= 3);
  CHECK(done < kFrames);
  int files = 0;
  for (const auto& e : fs::directory_iterator(frames)) {
    CAPTURE(e.path());
    CHECK(e.path().extension() != ".tmp");  // AtomicFile's temporaries, removed or renamed
    ++files;
  }
  CHECK(files == 3 * done);
  for (int f = 0; f < done; ++f) {
    CAPTURE(f);
    for (const fs::path& p : {frames / frame_name("c", f, ".obj"), frames / frame_name("c_q", f, ".ply")}) {
      const Mesh mesh = read_mesh(p);  // throws on a truncated file
      CHECK(mesh.V.rows() == scene.mesh.V.rows());
      CHECK(mesh.F.rows() == scene.mesh.F.rows());
    }
    const json metrics = json::parse(slurp(frames / frame_name("c", f, ".json")));
    CHECK(metrics["frame"] == f);
    CHECK(metrics["vertices"] == scene.mesh.V.rows());
    CHECK(metrics["faces"] == scene.mesh.F.rows());
  }
  CHECK_FALSE(fs::exists(frames / frame_name("c", done, ".obj")));
}

}  // namespace

TEST_CASE("SceneRunner gives run_scene's frames one at a time, FrameWriter keeps or removes a run",
          "[scene][run]") {
  TempDir tmp;
  json doc = json::parse(slurp(write_scene(tmp.path)));
  doc["frames"].erase(doc["frames"].begin() + 5, doc["frames"].end());  // 5 frames
  doc["snap"] = {{"enabled", true}};
  const scene::Scene s = scene::parse_scene(doc, tmp.path, "five.json");
  const scene::RunResult all = scene::run_scene(s);
  scene::SceneRunner run(s);
  CHECK(run.bind_ms() > 0);
  {
    scene::FrameWriter out(s, tmp.path / "dropped");
    while (!run.done()) {
      const std::size_t f = run.frame();
      const scene::FrameResult r = run.next();
      CHECK(r.V == all.frames[f].V);  // bit for bit: the same deformer and snap, frame after frame
      CHECK(r.V_unsnapped == all.frames[f].V_unsnapped);
      CHECK(r.metrics["q_mean"] == all.frames[f].metrics["q_mean"]);
      out.write(f, r);
      for (const auto& p : out.paths(f)) CHECK(fs::exists(p));
    }
    CHECK(out.frames_written() == 5);
    CHECK_THROWS_AS(out.write(2, all.frames[2]), std::logic_error);  // in order only
  }  // not kept: every file written is removed again
  CHECK_FALSE(fs::exists(tmp.path / "dropped" / "out" / "c.0000.obj"));
  {
    scene::FrameWriter out(s, tmp.path / "kept");
    for (std::size_t f = 0; f < 2; ++f) out.write(f, all.frames[f]);
    out.keep();  // e.g. stopped after two frames
  }
  CHECK(fs::exists(tmp.path / "kept" / "out" / "c_q.0001.ply"));
  CHECK_FALSE(fs::exists(tmp.path / "kept" / "out" / "c.0002.obj"));
}

TEST_CASE("spinmotor deform stopped by SIGINT: exit 130, every frame on disk complete",
          "[scene][cli][interrupt]") {
  interrupt_and_check(SIGINT);
}

TEST_CASE("spinmotor deform stopped by SIGTERM: exit 143, every frame on disk complete",
          "[scene][cli][interrupt]") {
  interrupt_and_check(SIGTERM);
}

}  // namespace test_long_runs
