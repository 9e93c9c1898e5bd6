// `spinmotor deform SCENE.json`: run a scene file (docs/scene.md) — load and validate it, bind its deformer,
// pose every frame, write the outputs atomically, print a summary.
// Exit codes (main.cpp): 0 ok, 2 bad scene (the message names the JSON path), 3 numerical failure.
#include <cstdio>
#include <iostream>
#include <optional>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
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

void run(const DeformArgs& a) {
  using namespace spinmotor::scene;
  if (a.schema) {
    std::cout << scene_schema_text();
    return;
  }
  if (a.scene.empty())
    throw spinmotor::Error("deform: a scene file is required (spinmotor deform SCENE.json)");
  const Scene scene = load_scene(a.scene);
  // Progress on stderr once the run has taken more than a second: bind, then frames with an ETA.
  const RunResult r = run_scene(scene, [&](std::size_t f, std::size_t n, double t) {
    if (a.quiet || t < 1.0) return;
    if (f == 0)
      std::fprintf(stderr, "deform: bound in %.1f s\n", t);
    else
      std::fprintf(stderr, "deform: frame %zu/%zu, elapsed %.1f s, ETA %.1f s\n", f, n, t,
                   t / static_cast<double>(f) * static_cast<double>(n - f));
  });
  for (const auto& w : r.warnings) std::cerr << "spinmotor: warning: " << w << '\n';
  std::optional<std::filesystem::path> out_dir;
  if (!a.out_dir.empty()) out_dir = a.out_dir;
  const auto written = write_outputs(scene, r, out_dir);

  if (a.json) {
    nlohmann::json j;
    if (scene.animated) {
      j = nlohmann::json::array();
      for (const auto& f : r.frames) j.push_back(f.metrics);
    } else {
      j = r.frames.front().metrics;
    }
    std::cout << j.dump(2) << '\n';
    return;
  }
  if (a.quiet) return;
  std::cout << scene.name() << ": " << scene.deformer_type << " on " << scene.mesh.V.rows() << " vertices, "
            << scene.mesh.F.rows() << " faces, " << scene.handles.size() << " handles\n"
            << "  bind " << fmt("%.2f", r.bind_ms) << " ms\n";
  for (std::size_t f = 0; f < r.frames.size(); ++f) {
    const nlohmann::json& m = r.frames[f].metrics;
    std::cout << "  "
              << (scene.animated ? "frame " + std::to_string(scene.first_frame + f) + ": " : std::string())
              << (scene.frames[f].time ? "t = " + fmt("%.4g", *scene.frames[f].time) + " s, " : std::string())
              << "pose " << fmt("%.2f", r.frames[f].pose_ms) << " ms, Q mean " << number(m["q_mean"], "%.4f")
              << ", Q max " << number(m["q_max"], "%.4f") << ", area distortion "
              << number(m["area_distortion"], "%.4f") << ", max handle error "
              << number(m.value("max_handle_error", nlohmann::json()), "%.3g") << '\n';
    if (m.contains("ik"))
      std::cout << "  ik: " << (m["ik"]["converged"].get<bool>() ? "reached" : "not reached") << " in "
                << m["ik"]["iterations"] << " iterations, tip error " << number(m["ik"]["tip_error"], "%.3g")
                << '\n';
  }
  for (const auto& p : written) std::cout << "  wrote " << p.string() << '\n';
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
          "  spinmotor deform --schema > scene.schema.json           # the scene format (JSON Schema)");
      sub.callback([a] { run(*a); });
    }};

}  // namespace
