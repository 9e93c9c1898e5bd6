#pragma once
// Running a scene: bind its deformer once, pose every frame, measure, and write the outputs.
//
// run_scene computes everything in memory (no file is touched); write_outputs then writes each
// frame's mesh, metrics JSON and colour PLY atomically (AtomicFile). If any write fails, the files
// this call already wrote are removed, so an error never leaves part of a run on disk.
//
// Metrics JSON of a frame (docs/scene.md `output.metrics`):
//   scene, mesh, deformer, vertices, faces, bind_ms, pose_ms, q_mean, q_max, area_distortion,
//   max_handle_error, frame (animations only), metrics (the full compute_metrics object, see
//   mesh/metrics/json.hpp), the deformer's own figures (e.g. "ik", "fit"); all of these describe
//   the deformer's pose (the edit). With `snap` enabled, "snap" holds the same after the conformal
//   snap (spin/conformal_snap.hpp, bound once per run): tradeoff, q_mean, q_max, area_distortion,
//   rms_edit_to_snap and max_edit_to_snap (relative to the edit's bounding-box diagonal), eigenvalue,
//   bind_ms (first frame), similarity_fit_ms, eigen_ms, poisson_ms, total_ms, metrics (full object).
//   The output mesh and colours are then the snapped mesh (docs/scene.md `output`).
// Animated scenes (`frames`) number their outputs: out/x.obj -> out/x.0000.obj, out/x.0001.obj, ...
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "spinmotor/scene/scene.hpp"

namespace spinmotor::scene {

struct FrameResult {
  Eigen::MatrixXd V;  ///< output positions (n×3): the deformation, or its snap when snap is enabled
  Eigen::MatrixXd V_unsnapped;  ///< the deformer's positions when snap is enabled (else empty)
  double pose_ms = 0;           ///< time of the deformer's pose() for this frame
  nlohmann::json metrics;       ///< the metrics document of this frame
};

struct RunResult {
  double bind_ms = 0;
  std::vector<FrameResult> frames;
  std::vector<std::string> warnings;  ///< notes for the user (printed by `deform`)
};

/// Called after the bind (frame = 0) and after each frame (frame = 1..frames) with the seconds since
/// run_scene started: the CLI prints progress lines and an ETA from it.
using RunProgress = std::function<void(std::size_t frame, std::size_t frames, double elapsed_s)>;

/// Binds and poses. Throws Error naming the JSON path of a pose entry no control has, or what the
/// deformer reports (handle, component, ...).
RunResult run_scene(const Scene& scene, const RunProgress& progress = {});

/// Where output `spec` of frame `frame` goes: relative paths against out_dir if given, else the scene
/// directory; animated scenes insert the 4-digit frame number (scene.first_frame + frame) before the
/// extension.
std::filesystem::path output_path(const Scene& scene, const std::filesystem::path& spec, int frame,
                                  const std::optional<std::filesystem::path>& out_dir);

/// Writes the outputs the scene asks for; returns the files written.
std::vector<std::filesystem::path> write_outputs(
    const Scene& scene, const RunResult& result,
    const std::optional<std::filesystem::path>& out_dir = std::nullopt);

/// Binary PLY of the deformed mesh with per-face colours of the quasi-conformal error Q (blue at
/// Q = 1 through yellow to red at Q ≥ 2, log scale). Atomic.
void write_q_colors_ply(const std::filesystem::path& path, const Mesh& rest, const Eigen::MatrixXd& V);

}  // namespace spinmotor::scene
