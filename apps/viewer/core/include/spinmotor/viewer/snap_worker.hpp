#pragma once
// "Snap to spin" off the UI thread (latest_job_worker.hpp). The viewer requests a snap of the current
// edit when a drag ends; the worker binds the ConformalSnap on the rest mesh once (first request, in
// its own thread) and snaps. A request with pins runs the pose-keeping cleanup instead
// (spin/pinned_cleanup.hpp: the pinned vertices, e.g. the handles, stay where the edit put them),
// bound once per pin set. Starting a new drag calls cancel(); a result of a request that is no
// longer the latest is discarded, so the UI never shows a snap of an edit that is not on screen.
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/scene/deformer_registry.hpp"
#include "spinmotor/viewer/latest_job_worker.hpp"

namespace spinmotor::viewer {

struct SnapOutcome {
  std::uint64_t generation = 0;
  Eigen::MatrixXd V;          ///< snapped positions (empty on error)
  Eigen::VectorXd Q;          ///< per-face quasi-conformal error of the snap against the rest mesh
  double q_mean = 0;          ///< rest-area weighted
  double bind_ms = 0;         ///< ConformalSnap or cleanup bind (when this request bound one, else 0)
  bool pinned = false;        ///< the pose-keeping cleanup ran (the request had pins or a skin)
  Eigen::Index pins = 0;      ///< pinned: the vertices kept in place
  double volume_ratio = 1.0;  ///< pinned: kept volume (closed) or area (open) / rest
  double snap_ms = 0;
  std::string error;  ///< what went wrong (spinmotor::Error message), else empty
};

struct SnapJob {
  Eigen::MatrixXd V_edit;  ///< n×3
  double tradeoff = 1.0;   ///< ∈ [0, 1] (free snap)
  std::vector<int> pins;   ///< non-empty: the pose-keeping cleanup with these vertices pinned
  /// Set: the rig cleanup of a skin (scene/rig_cleanup.hpp, the rig defaults), bound once per skin.
  std::shared_ptr<const spinmotor::Rig> skin;
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
  /// Queues the pose-keeping cleanup of V_edit with `pins` kept in place (spin/pinned_cleanup.hpp). The
  /// worker rebinds when the pins change.
  std::uint64_t request_pinned(Eigen::MatrixXd V_edit, std::vector<int> pins) {
    return request(SnapJob{std::move(V_edit), 1.0, std::move(pins), nullptr});
  }
  /// Queues the rig cleanup of a skinned pose (the one door, scene/rig_cleanup.hpp, with the rig defaults:
  /// pins and attraction from the skin's weights, every piece on its own). The worker rebinds when the
  /// skin changes.
  std::uint64_t request_rig(Eigen::MatrixXd V_edit, std::shared_ptr<const spinmotor::Rig> skin) {
    return request(SnapJob{std::move(V_edit), 1.0, {}, std::move(skin)});
  }
};

}  // namespace spinmotor::viewer
