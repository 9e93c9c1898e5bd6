#pragma once
// Running a scene: bind its deformer once, pose every frame, measure, and write the outputs.
//
// SceneRunner binds, then computes one frame per next() call, in memory; FrameWriter writes a frame's
// mesh, metrics JSON and colour PLY atomically (AtomicFile) and, unless told to keep them, removes the
// files it wrote when it is destroyed, so an error never leaves part of a run on disk. A long animation
// is run frame by frame through both (`spinmotor deform`): memory stays that of one frame whatever the
// number of frames, and a caller can stop between two frames with every frame written so far complete.
// run_scene and write_outputs are the same for a whole run held in memory (tests, short animations).
//
//   SceneRunner run(scene);                       // binds the deformer and the snap once
//   FrameWriter out(scene, out_dir);
//   while (!run.done() && !stop_requested()) {
//     const std::size_t f = run.frame();
//     out.write(f, run.next());                   // an exception: out's destructor removes the run's files
//   }
//   out.keep();                                   // finished, or stopped between frames: keep them
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
#include <memory>
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

/// Binds a scene's deformer (and its snap) once, then computes its frames one at a time, in order (a
/// deformer may start from the previous frame, e.g. ARAP's "initial": "previous"). Holds nothing of a
/// frame once next() has returned it. The scene must outlive the runner.
class SceneRunner {
 public:
  /// Binds. Throws Error naming the JSON path of a pose entry no control has, or what the deformer or
  /// the snap's bind reports (handle, component, ...).
  explicit SceneRunner(const Scene& scene);
  ~SceneRunner();
  SceneRunner(SceneRunner&&) noexcept;
  SceneRunner& operator=(SceneRunner&&) noexcept;

  double bind_ms() const;      ///< the deformer's bind (the snap's bind is reported by frame 0)
  std::size_t frames() const;  ///< the number of frames of the scene
  std::size_t frame() const;   ///< the index of the frame next() computes (frames() when done)
  bool done() const { return frame() == frames(); }

  /// Poses, measures and (with `snap`) snaps frame frame(), then advances. Throws Error (prefixed with
  /// the scene's name) if the deformer, the metrics or the snap fail; precondition: !done().
  FrameResult next();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A whole run in memory: every frame's positions and metrics.
struct RunResult {
  double bind_ms = 0;
  std::vector<FrameResult> frames;
};

/// Called after the bind (frame = 0) and after each frame (frame = 1..frames) with the seconds since
/// run_scene started: the CLI prints progress lines and an ETA from it.
using RunProgress = std::function<void(std::size_t frame, std::size_t frames, double elapsed_s)>;

/// Binds and poses every frame (a SceneRunner), keeping them all: memory grows with the number of
/// frames, so a long animation should use SceneRunner and FrameWriter instead. Throws as SceneRunner.
RunResult run_scene(const Scene& scene, const RunProgress& progress = {});

/// Where output `spec` of frame `frame` goes: relative paths against out_dir if given, else the scene
/// directory; animated scenes insert the 4-digit frame number (scene.first_frame + frame) before the
/// extension.
std::filesystem::path output_path(const Scene& scene, const std::filesystem::path& spec, int frame,
                                  const std::optional<std::filesystem::path>& out_dir);

/// Writes a run's outputs frame by frame, frames 0, 1, 2, ... in order, and is to a run what AtomicFile
/// is to a file: each file is written atomically, and the destructor removes every file written through
/// this object unless keep() was called (an exception unwinding past it, a failed frame), so an error
/// never leaves part of a run on disk. (Frames it overwrote are removed too: the previous run's files
/// at those paths are gone either way.) Holds no per-frame state: the files of a frame are recomputed
/// from output_path, so a run of any length costs the same memory. The scene must outlive the writer.
class FrameWriter {
 public:
  explicit FrameWriter(const Scene& scene, std::optional<std::filesystem::path> out_dir = std::nullopt);
  ~FrameWriter();  ///< removes the files of frames [0, frames_written()) unless keep() was called
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  /// Writes frame `frame`'s outputs (mesh, metrics, colours, as the scene asks); `frame` must be
  /// frames_written(). If one file fails, the frame's files written before it are removed and the
  /// Error (naming the path) is rethrown.
  void write(std::size_t frame, const FrameResult& result);
  /// The files of frame `frame`, in the order write() writes them.
  std::vector<std::filesystem::path> paths(std::size_t frame) const;
  /// Frames whose every output is on disk.
  std::size_t frames_written() const { return written_; }
  /// Keeps the files written so far: the run finished, or stopped between two frames.
  void keep() noexcept { keep_ = true; }

 private:
  const Scene& scene_;
  std::optional<std::filesystem::path> out_dir_;
  std::size_t written_ = 0;
  bool keep_ = false;
};

/// Writes the outputs of every frame of `result` (a FrameWriter); returns the files written. If any
/// write fails, the files this call already wrote are removed.
std::vector<std::filesystem::path> write_outputs(
    const Scene& scene, const RunResult& result,
    const std::optional<std::filesystem::path>& out_dir = std::nullopt);

/// Binary PLY of the deformed mesh with per-face colours of the quasi-conformal error Q (blue at
/// Q = 1 through yellow to red at Q ≥ 2, log scale). Atomic.
void write_q_colors_ply(const std::filesystem::path& path, const Mesh& rest, const Eigen::MatrixXd& V);

}  // namespace spinmotor::scene
