#pragma once
// "Snap to spin" off the UI thread (latest_job_worker.hpp). The viewer requests a snap of the current
// edit when a drag ends; the worker binds the ConformalSnap on the rest mesh once (first request, in
// its own thread) and snaps. A request with pins runs the pose-keeping cleanup instead
// (spin/pinned_cleanup.hpp: the pinned vertices, e.g. the handles, stay where the edit put them),
// bound once per pin set. Starting a new drag calls cancel(); a result of a request that is no
// longer the latest is discarded, so the UI never shows a snap of an edit that is not on screen.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/viewer/latest_job_worker.hpp"

namespace spinmotor::viewer {

struct SnapOutcome {
  std::uint64_t generation = 0;
  Eigen::MatrixXd V;          ///< snapped positions (empty on error)
  Eigen::VectorXd Q;          ///< per-face quasi-conformal error of the snap against the rest mesh
  double q_mean = 0;          ///< rest-area weighted
  double bind_ms = 0;         ///< ConformalSnap or PinnedCleanup bind (when this request bound one, else 0)
  bool pinned = false;        ///< the pose-keeping cleanup ran (the request had pins)
  double volume_ratio = 1.0;  ///< pinned: kept volume (closed) or area (open) / rest
  double snap_ms = 0;
  std::string error;  ///< what went wrong (spinmotor::Error message), else empty
};

struct SnapJob {
  Eigen::MatrixXd V_edit;      ///< n×3
  double tradeoff = 1.0;       ///< ∈ [0, 1] (free snap)
  std::vector<int> pins;       ///< non-empty: the pose-keeping cleanup with these vertices pinned
  double pose_weight = 0;      ///< pinned: γ of the pose attraction (PinnedCleanupOptions)
  Eigen::VectorXd attraction;  ///< pinned: per-vertex attraction weights (empty: all 1)
};

class SnapWorker : public LatestJobWorker<SnapJob, SnapOutcome> {
 public:
  explicit SnapWorker(Mesh rest);
  using LatestJobWorker::request;
  /// Queues a snap of V_edit (n×3) with `tradeoff` ∈ [0, 1]; replaces a queued one. Returns its generation.
  std::uint64_t request(Eigen::MatrixXd V_edit, double tradeoff) {
    SnapJob job;
    job.V_edit = std::move(V_edit);
    job.tradeoff = tradeoff;
    return request(std::move(job));
  }
  /// Queues the pose-keeping cleanup of V_edit with `pins` kept in place and the free vertices held
  /// near V_edit by the pose attraction (pose_weight γ, per-vertex `attraction`; spin/pinned_cleanup.hpp).
  /// The worker rebinds when the pins or the attraction change.
  std::uint64_t request_pinned(Eigen::MatrixXd V_edit, std::vector<int> pins, double pose_weight = 0,
                               Eigen::VectorXd attraction = {}) {
    return request(SnapJob{std::move(V_edit), 1.0, std::move(pins), pose_weight, std::move(attraction)});
  }
};

}  // namespace spinmotor::viewer
