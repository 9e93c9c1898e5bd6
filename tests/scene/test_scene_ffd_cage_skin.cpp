// Scene deformer types `ffd`, `cage` and `skin` through the `spinmotor deform` binary: good scenes run
// and write their outputs (the posed controls act as named), bad cages and bad weight files exit with
// code 2, name the problem and write nothing; schema keys of docs/scene.md are accepted, typos rejected.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/scene/run.hpp"
#include "spinmotor/scene/scene.hpp"

namespace test_scene_ffd_cage_skin {

using namespace spinmotor;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    std::random_device rd;
    path = fs::temp_directory_path() /
           ("spinmotor-ffd-cage-skin-" + std::to_string(rd()) + std::to_string(rd()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

struct CliResult {
  int code = -1;
  std::string err;
};

/// `spinmotor deform DIR/scene.json EXTRA` (EXTRA: more arguments, already quoted for the shell).
CliResult deform(const fs::path& dir, const json& doc, const std::string& extra = "") {
  std::ofstream(dir / "scene.json") << doc.dump(1);
  const fs::path err = dir / "stderr.txt";
  const std::string cmd = std::string(SPINMOTOR_CLI) + " deform '" + (dir / "scene.json").string() + "' " +
                          extra + " > /dev/null 2> '" + err.string() + "'";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err);
  std::stringstream s;
  s << in.rdbuf();
  r.err = s.str();
  return r;
}

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

json ffd_scene() {
  return json::parse(R"({
    "mesh": {"generate": "tube", "radius": 0.5, "length": 4, "rings": 20, "sides": 12, "capped": true},
    "deformer": {"type": "ffd", "lattice": [2, 2, 4], "basis": "bspline", "mode": "motor",
                 "box": {"min": [-1, -1, 0], "max": [1, 1, 4]}},
    "pose": {"ffd[0,0,3]": {"rotate": {"axis": [0, 0, 1], "degrees": 90}},
             "ffd[1,1,3]": {"rotate": {"axis": [0, 0, 1], "degrees": 90}},
             "ffd[0,1,3]": {"rotate": {"axis": [0, 0, 1], "degrees": 90}},
             "ffd[1,0,3]": {"rotate": {"axis": [0, 0, 1], "degrees": 90}}},
    "output": {"mesh": "out/ffd.obj", "metrics": "out/ffd.json"}
  })");
}

json cage_scene() {
  return json::parse(R"({
    "mesh": {"generate": "torus", "R": 1, "r": 0.4, "u": 32, "v": 16},
    "deformer": {"type": "cage", "cage": "cage.obj", "coordinates": "harmonic", "grid": 24, "mode": "motor"},
    "pose": {"cage[3]": {"translate": [0.3, 0, 0]}},
    "output": {"mesh": "out/cage.obj", "metrics": "out/cage.json"}
  })");
}

/// The cage of cage_scene(): an icosphere of radius 2 without texture coordinates, as DIR/cage.obj.
Mesh write_cage(const fs::path& dir) {
  Mesh cage = icosphere(1, 2.0);
  cage.UV.resize(0, 2);
  cage.FUV.resize(0, 3);
  write_mesh(dir / "cage.obj", cage);
  return cage;
}

json skin_scene() {
  return json::parse(R"({
    "mesh": {"generate": "tube", "radius": 0.5, "length": 4, "rings": 41, "sides": 16, "capped": true},
    "skeleton": {"bones": [
      {"name": "upper", "parent": null, "head": [0, 0, 0], "tail": [0, 0, 2]},
      {"name": "lower", "parent": "upper", "head": [0, 0, 2], "tail": [0, 0, 4]}]},
    "deformer": {"type": "skin", "weights": "harmonic", "blend": "dlb"},
    "pose": {"lower": {"rotate": {"axis": [1, 0, 0], "degrees": 45, "about": [0, 0, 2]}}},
    "output": {"mesh": "out/skin.obj", "metrics": "out/skin.json"}
  })");
}

}  // namespace

TEST_CASE("ffd scene: controls posed by name, metrics count the controls", "[scene][ffd]") {
  TempDir t;
  const CliResult r = deform(t.path, ffd_scene());
  INFO(r.err);
  REQUIRE(r.code == 0);
  const Mesh out = read_mesh(t.path / "out/ffd.obj");
  const Mesh rest = tube(0.5, 4, 20, 12, true);
  REQUIRE(out.V.rows() == rest.V.rows());
  // the box's bottom face holds ring 0 (only the identity layer c = 0 acts there): it stays
  CHECK((out.V.row(0) - rest.V.row(0)).norm() < 1e-9);
  const json m = read_json(t.path / "out/ffd.json");
  CHECK(m["ffd"]["controls"] == 16);
  CHECK(m["ffd"]["outside_box"] == 0);
  // the top ring is rotated by 90° about z (all four top controls carry the same rotation)
  const Eigen::Index top = 19 * 12;
  CHECK(std::abs(out.V(top, 0) - (-rest.V(top, 1))) < 1e-9);
  CHECK(std::abs(out.V(top, 1) - rest.V(top, 0)) < 1e-9);
  // an unknown control name is an error naming it
  json bad = ffd_scene();
  bad["pose"]["ffd[2,0,0]"] = json::parse(R"({"translate": [0, 0, 1]})");
  const CliResult e = deform(t.path, bad);
  CHECK(e.code == 2);
  CHECK(e.err.find("ffd[2,0,0]") != std::string::npos);
}

TEST_CASE("cage scene: good cage runs, open or inconsistently oriented cages exit 2 without output",
          "[scene][cage]") {
  TempDir t;
  Mesh cage = write_cage(t.path);
  {
    const CliResult r = deform(t.path, cage_scene());
    INFO(r.err);
    REQUIRE(r.code == 0);
    const json m = read_json(t.path / "out/cage.json");
    CHECK(m["cage"]["vertices"] == 42);
    CHECK(m["cage"]["coordinates"] == "harmonic");
    const Mesh out = read_mesh(t.path / "out/cage.obj");
    CHECK(out.V.rows() == 32 * 16);
  }
  fs::remove_all(t.path / "out");
  Mesh open = cage;
  open.F.conservativeResize(cage.F.rows() - 1, 3);
  write_mesh(t.path / "cage.obj", open);
  CliResult r = deform(t.path, cage_scene());
  CHECK(r.code == 2);
  CHECK(r.err.find("not closed") != std::string::npos);
  CHECK(r.err.find("cage.obj") != std::string::npos);
  CHECK(!fs::exists(t.path / "out"));
  Mesh flipped = cage;
  flipped.F.row(0) = Eigen::RowVector3i(cage.F(0, 0), cage.F(0, 2), cage.F(0, 1));
  write_mesh(t.path / "cage.obj", flipped);
  r = deform(t.path, cage_scene());
  CHECK(r.code == 2);
  CHECK(r.err.find("oriented") != std::string::npos);
  CHECK(!fs::exists(t.path / "out"));
  // a mesh vertex outside the cage
  Mesh small = cage;
  small.V *= 0.6;
  write_mesh(t.path / "cage.obj", small);
  r = deform(t.path, cage_scene());
  CHECK(r.code == 2);
  CHECK(r.err.find("outside the cage") != std::string::npos);
  CHECK(!fs::exists(t.path / "out"));
}

TEST_CASE("cage scene: a bounding-box cage needs no file and moves the mesh with its corners",
          "[scene][cage]") {
  TempDir t;
  json doc = cage_scene();
  doc["deformer"]["cage"] = {{"box", {{"margin", 0.1}}}};
  doc["deformer"]["coordinates"] = "mean-value";
  doc["pose"] = json::object();
  for (int j = 0; j < 8; ++j)
    doc["pose"]["cage[" + std::to_string(j) + "]"] = {{"translate", {0.25, 0, -0.5}}};
  const CliResult r = deform(t.path, doc);
  INFO(r.err);
  REQUIRE(r.code == 0);
  const json m = read_json(t.path / "out/cage.json");
  CHECK(m["cage"]["vertices"] == 8);
  // Mean-value coordinates reproduce affine maps: all corners translated = the mesh translated.
  const Mesh rest = torus(1, 0.4, 32, 16), out = read_mesh(t.path / "out/cage.obj");
  REQUIRE(out.V.rows() == rest.V.rows());
  CHECK(((out.V - rest.V).rowwise() - Eigen::RowVector3d(0.25, 0, -0.5)).cwiseAbs().maxCoeff() <
        1e-5);  // OBJ digits
  fs::remove_all(t.path / "out");
  doc["deformer"]["cage"] = {{"box", {{"margin", -1}}}};
  const CliResult bad = deform(t.path, doc);
  CHECK(bad.code == 2);
  CHECK(bad.err.find("/deformer/cage") != std::string::npos);
  CHECK(!fs::exists(t.path / "out"));
}

TEST_CASE("skin scene: harmonic weights run, bad weight files exit 2 naming file and line", "[scene][skin]") {
  TempDir t;
  {
    const CliResult r = deform(t.path, skin_scene());
    INFO(r.err);
    REQUIRE(r.code == 0);
    const Mesh out = read_mesh(t.path / "out/skin.obj");
    const Mesh rest = tube(0.5, 4, 41, 16, true);
    CHECK((out.V.row(0) - rest.V.row(0)).norm() < 1e-12);            // ring 0: upper bone only (identity)
    CHECK((out.V.row(40 * 16) - rest.V.row(40 * 16)).norm() > 1.0);  // top ring: follows the lower bone
  }
  fs::remove_all(t.path / "out");
  const Eigen::Index n = tube(0.5, 4, 41, 16, true).V.rows();
  {  // a good text weight file
    std::ofstream f(t.path / "w.txt");
    f << "bones lower upper\n";
    for (Eigen::Index i = 0; i < n; ++i) f << (i < n / 2 ? "0 1\n" : "1 0\n");
  }
  json doc = skin_scene();
  doc["deformer"]["weights"] = "w.txt";
  REQUIRE(deform(t.path, doc).code == 0);
  fs::remove_all(t.path / "out");
  {  // a bad one: a non-number on line 4
    std::ofstream f(t.path / "w.txt");
    f << "bones lower upper\n0 1\n0 1\n0 one\n";
  }
  CliResult r = deform(t.path, doc);
  CHECK(r.code == 2);
  CHECK(r.err.find("w.txt:4:") != std::string::npos);
  CHECK(!fs::exists(t.path / "out"));
  // docs/scene.md's JSON weight file, with a negative weight
  std::ofstream(t.path / "w.json") << R"({"bones": ["upper", "lower"], "weights": [[1, -1]]})";
  doc["deformer"]["weights"] = "w.json";
  r = deform(t.path, doc);
  CHECK(r.code == 2);
  CHECK(r.err.find("w.json") != std::string::npos);
  CHECK(!fs::exists(t.path / "out"));
  // an unknown parent is named by its JSON path
  doc = skin_scene();
  doc["skeleton"]["bones"][1]["parent"] = "arm";
  r = deform(t.path, doc);
  CHECK(r.code == 2);
  CHECK(r.err.find("/skeleton/bones/1/parent") != std::string::npos);
}

TEST_CASE("ffd/cage/skin schema: docs/scene.md keys accepted, typos rejected", "[scene][schema]") {
  json doc = ffd_scene();
  doc["deformer"]["box"] = json::parse(R"({"min": [-1, -1, -0.5], "max": [1, 1, 4.5]})");
  doc["deformer"]["basis"] = "bezier";
  doc["deformer"]["mode"] = "position";
  doc.erase("output");
  REQUIRE_NOTHROW(scene::run_scene(scene::parse_scene(doc, ".", "ffd.json")));
  doc["deformer"]["lattise"] = 3;
  CHECK_THROWS_WITH(scene::parse_scene(doc, ".", "ffd.json"), Catch::Contains("/deformer"));
  json skin = skin_scene();
  skin["deformer"]["blend"] = "lbs";
  skin.erase("output");
  REQUIRE_NOTHROW(scene::run_scene(scene::parse_scene(skin, ".", "skin.json")));
  skin["deformer"]["blend"] = "dqs";
  CHECK_THROWS_WITH(scene::parse_scene(skin, ".", "skin.json"), Catch::Contains("/deformer"));
}

TEST_CASE("skin scene with mush: Delta Mush and DDM of 0 iterations are LBS, more iterations move the elbow",
          "[scene][skin][mush]") {
  auto run = [](json doc) {
    doc.erase("output");
    return scene::run_scene(scene::parse_scene(doc, ".", "mush.json")).frames.at(0).V;
  };
  json lbs = skin_scene();
  lbs["deformer"]["blend"] = "lbs";
  const Eigen::MatrixXd V_lbs = run(lbs);
  json dm = lbs;
  dm["deformer"]["mush"] = "delta-mush";
  dm["deformer"]["mush_iterations"] = 0;
  CHECK((run(dm) - V_lbs).cwiseAbs().maxCoeff() == 0.0);  // zero sweeps: the deltas are zero
  json ddm = lbs;
  ddm["deformer"].erase("blend");
  ddm["deformer"]["mush"] = "direct-delta-mush";
  ddm["deformer"]["mush_iterations"] = 0;
  CHECK((run(ddm) - V_lbs).cwiseAbs().maxCoeff() < 1e-12);  // Ψ = I: DDM reduces to LBS
  dm["deformer"]["mush_iterations"] = 10;
  const double moved = (run(dm) - V_lbs).cwiseAbs().maxCoeff();
  INFO("Delta Mush moves the LBS elbow by up to " << moved);
  CHECK(moved > 1e-4);
  for (const char* bad : {R"({"type": "skin", "mush": "blur"})", R"({"type": "skin", "mush_iterations": 3})",
                          R"({"type": "skin", "mush": "direct-delta-mush", "blend": "lbs"})"}) {
    INFO(bad);
    json doc = skin_scene();
    doc["deformer"] = json::parse(bad);
    CHECK_THROWS_WITH(scene::parse_scene(doc, ".", "bad.json").deformer_type == "skin" &&
                          !scene::run_scene(scene::parse_scene(doc, ".", "bad.json")).frames.empty(),
                      Catch::Contains("/deformer"));
  }
}

TEST_CASE("cage scene: --max-memory refuses a grid that cannot fit at once, exit 2, no output",
          "[scene][cage][memory]") {
  TempDir t;
  write_cage(t.path);
  json doc = cage_scene();
  doc["deformer"]["grid"] = 512;
  const auto t0 = std::chrono::steady_clock::now();
  const CliResult r = deform(t.path, doc, "--max-memory 4G");
  const double ms = ms_since(t0);
  INFO(r.err);
  CHECK(r.code == 2);
  CHECK(r.err.find("harmonic_cage_coordinates: grid 512 (") != std::string::npos);
  CHECK(r.err.find(" TB of memory; the limit is 4.0 GB (set by --max-memory") != std::string::npos);
  CHECK(ms < 1000);  // the refusal comes before the work (minutes), not after it
  CHECK_FALSE(fs::exists(t.path / "out"));
  // The option goes before the command too; the grid-24 scene (a few MB) fits in 64 MB, not in 1 MB.
  doc["deformer"]["grid"] = 24;
  std::ofstream(t.path / "scene.json") << doc.dump(1);
  // Built by appending: "'" + std::string&& trips GCC 12's -Wrestrict false positive (bug 105329).
  std::string cmd = SPINMOTOR_CLI;
  cmd.append(" --max-memory 64M deform '")
      .append((t.path / "scene.json").string())
      .append("' > /dev/null 2>&1");
  CHECK(std::system(cmd.c_str()) == 0);
  CHECK(fs::exists(t.path / "out/cage.obj"));
  fs::remove_all(t.path / "out");
  const CliResult small = deform(t.path, doc, "--max-memory 1M");
  CHECK(small.code == 2);
  CHECK(small.err.find("the limit is 1.0 MB") != std::string::npos);
  CHECK_FALSE(fs::exists(t.path / "out"));
  const CliResult bad = deform(t.path, doc, "--max-memory 12X");
  CHECK(bad.code == 2);
  CHECK(bad.err.find("memory size '12X'") != std::string::npos);
}

}  // namespace test_scene_ffd_cage_skin
