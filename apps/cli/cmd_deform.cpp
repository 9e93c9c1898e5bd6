// `spinmotor deform SCENE.json`: run a scene file (docs/scene.md) — load and validate it, bind its deformer,
// pose every frame, write the outputs atomically, print a summary.
// Exit codes (main.cpp): 0 ok, 2 bad scene (the message names the JSON path), 3 numerical failure,
// 129 / 130 / 143 stopped by SIGHUP / SIGINT / SIGTERM (the frames before the signal are complete on disk).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/interrupt.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/scene/run.hpp"
#include "spinmotor/scene/scene.hpp"

namespace {

struct DeformArgs {
  std::string scene;
  std::string out_dir;
  bool json = false, quiet = false, schema = false;
};

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::string number(const nlohmann::json& j, const char* f) {
  return j.is_number() ? fmt(f, j.get<double>()) : "n/a";
}

/// --json of an animation, printed element by element as the frames complete: byte for byte what
/// nlohmann's dump(2) of the whole array prints ("[", each element indented two more spaces, "]"), without
/// holding the array. (Indenting after every newline is safe: JSON strings hold no raw newline.)
class JsonArrayPrinter {
 public:
  void push(const nlohmann::json& element) {
    std::string text = element.dump(2);
    for (std::size_t i = 0; (i = text.find('\n', i)) != std::string::npos; i += 3) text.insert(i + 1, "  ");
    std::cout << (count_++ ? ",\n  " : "[\n  ") << text;
  }
  void close() { std::cout << (count_ ? "\n]\n" : "[]\n"); }

 private:
  std::size_t count_ = 0;
};

/// The summary line of one frame (text mode).
void print_frame(const spinmotor::scene::Scene& scene, std::size_t f,
                 const spinmotor::scene::FrameResult& r) {
  const nlohmann::json& m = r.metrics;
  std::cout << "  "
            << (scene.animated ? "frame " + std::to_string(scene.first_frame + f) + ": " : std::string())
            << (scene.frames[f].time ? "t = " + fmt("%.4g", *scene.frames[f].time) + " s, " : std::string())
            << "pose " << fmt("%.2f", r.pose_ms) << " ms, Q mean " << number(m["q_mean"], "%.4f")
            << ", Q max " << number(m["q_max"], "%.4f") << ", area distortion "
            << number(m["area_distortion"], "%.4f") << ", max handle error "
            << number(m.value("max_handle_error", nlohmann::json()), "%.3g") << '\n';
  if (m.contains("ik"))
    std::cout << "  ik: " << (m["ik"]["converged"].get<bool>() ? "reached" : "not reached") << " in "
              << m["ik"]["iterations"] << " iterations, tip error " << number(m["ik"]["tip_error"], "%.3g")
              << '\n';
}

// Frame by frame: each frame is computed, written and printed before the next one, so memory stays that
// of one frame for any number of frames. A signal (SIGINT, SIGTERM, SIGHUP) stops the run between two frames:
// the frames before it are complete on disk (every output of each), the summary and the --json array
// cover exactly those frames, and the command throws cli::Interrupted (exit 128 + signal). An error
// removes every output of this run (FrameWriter), as if nothing had been written.
void run(const DeformArgs& a) {
  using namespace spinmotor::scene;
  if (a.schema) {
    std::cout << scene_schema_text();
    return;
  }
  if (a.scene.empty())
    throw spinmotor::Error("deform: a scene file is required (spinmotor deform SCENE.json)");
  const Scene scene = load_scene(a.scene);
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<std::filesystem::path> out_dir;
  if (!a.out_dir.empty()) out_dir = a.out_dir;
  FrameWriter out(scene, out_dir);
  // Progress on stderr once the run has taken more than a second: bind, then frames with an ETA.
  const std::size_t n = scene.frames.size();
  auto progress = [&](std::size_t f) {
    const double t = spinmotor::ms_since(t0) / 1000;
    if (a.quiet || t < 1.0) return;
    if (f == 0)
      std::fprintf(stderr, "deform: bound in %.1f s\n", t);
    else
      std::fprintf(stderr, "deform: frame %zu/%zu, elapsed %.1f s, ETA %.1f s\n", f, n, t,
                   t / static_cast<double>(f) * static_cast<double>(n - f));
  };
  SceneRunner run(scene);
  progress(0);
  const bool text = !a.json && !a.quiet;
  if (text)
    std::cout << scene.name() << ": " << scene.deformer_type << " on " << scene.mesh.V.rows() << " vertices, "
              << scene.mesh.F.rows() << " faces, " << scene.handles.size() << " handles\n"
              << "  bind " << fmt("%.2f", run.bind_ms()) << " ms\n";
  JsonArrayPrinter array;
  // Until here a signal kills the process as usual (nothing is on disk yet); from here it only stops the
  // loop between two frames.
  const spinmotor::InterruptGuard guard;
  while (!run.done() && !spinmotor::interrupted()) {
    const std::size_t f = run.frame();
    const FrameResult r = run.next();
    out.write(f, r);
    if (a.json && scene.animated)
      array.push(r.metrics);
    else if (a.json)
      std::cout << r.metrics.dump(2) << '\n';
    else if (text)
      print_frame(scene, f, r);
    progress(f + 1);
  }
  out.keep();
  if (a.json && scene.animated) array.close();
  if (text)
    for (std::size_t f = 0; f < out.frames_written(); ++f)
      for (const auto& p : out.paths(f)) std::cout << "  wrote " << p.string() << '\n';
  if (const int sig = spinmotor::interrupted())
    throw spinmotor::cli::Interrupted(sig, "deform stopped after " + std::to_string(out.frames_written()) +
                                               " of " + std::to_string(n) + " frames, each one complete");
}

const spinmotor::cli::RegisterCommand register_deform{
    "deform", "Run a scene file: deform a mesh with motor handles and write the posed mesh and its metrics",
    [](CLI::App& sub) {
      auto a = std::make_shared<DeformArgs>();
      sub.add_option("scene", a->scene, "Scene file (JSON, see docs/scene.md)");
      sub.add_option("--out-dir", a->out_dir,
                     "Resolve relative output paths against DIR instead of the scene's folder");
      sub.add_flag("--json", a->json, "Print the metrics as JSON on stdout (an array for animations)");
      sub.add_flag("--quiet,-q", a->quiet, "Print nothing but warnings and errors");
      sub.add_flag("--schema", a->schema, "Print the scene JSON Schema and exit");
      sub.footer(
          "Examples:\n"
          "  spinmotor deform tests/data/scenes/ik_tube.json          # IK-driven spline deformation\n"
          "  spinmotor deform pose.json --out-dir results --json     # outputs under results/, metrics on "
          "stdout\n"
          "  spinmotor deform --schema > scene.schema.json           # the scene format (JSON Schema)\n"
          "Frames are written one by one. SIGINT (Ctrl+C), SIGTERM or SIGHUP stops an animation after the\n"
          "frame in progress: the frames written are complete, exit code 128 + signal (130, 143, 129; 2 bad\n"
          "scene, 3 numerical failure: then no output of the run is left).");
      sub.callback([a] { run(*a); });
    }};

}  // namespace
