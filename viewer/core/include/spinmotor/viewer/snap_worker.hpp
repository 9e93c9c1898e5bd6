#pragma once
// "Snap to spin" off the UI thread. The viewer requests a snap of the current edit when a drag ends;
// the worker thread binds the ConformalSnap once (first request) and snaps. Every request gets a new
// generation; starting a new drag calls cancel(). A result whose generation is no longer the latest
// (the user moved on while it ran, or a newer request replaced a queued one) is discarded, so the UI
// never shows a snap of an edit that is not on screen.
#include <Eigen/Core>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor::viewer {

struct SnapOutcome {
  std::uint64_t generation = 0;
  Eigen::MatrixXd V;   ///< snapped positions (empty on error)
  Eigen::VectorXd Q;   ///< per-face quasi-conformal error of the snap against the rest mesh
  double q_mean = 0;   ///< rest-area weighted
  double bind_ms = 0;  ///< ConformalSnap bind (first request only, else 0)
  double snap_ms = 0;
  std::string error;  ///< what went wrong (spinmotor::Error message), else empty
};

class SnapWorker {
 public:
  explicit SnapWorker(Mesh rest);
  ~SnapWorker();  ///< waits for the snap in progress, if any, then stops
  SnapWorker(const SnapWorker&) = delete;
  SnapWorker& operator=(const SnapWorker&) = delete;

  /// Queues a snap of V_edit (n×3) with `tradeoff` ∈ [0, 1]; replaces a queued one. Returns its generation.
  std::uint64_t request(Eigen::MatrixXd V_edit, double tradeoff);
  /// Makes every queued or running request stale.
  void cancel();
  /// The result of the latest request, once (nothing while it runs or when it was cancelled).
  std::optional<SnapOutcome> take();
  bool busy() const;
  /// Blocks until no request is queued or running (tests, headless mode). False on timeout.
  bool wait_idle(double timeout_s);
  std::uint64_t discarded() const;  ///< results dropped as stale so far

 private:
  void loop();
  struct Job {
    std::uint64_t generation;
    Eigen::MatrixXd V;
    double tradeoff;
  };
  Mesh rest_;
  mutable std::mutex mutex_;
  std::condition_variable cv_, idle_cv_;
  std::optional<Job> queued_;
  std::optional<SnapOutcome> result_;
  std::uint64_t latest_ = 0, discarded_ = 0;
  bool running_ = false, stop_ = false;
  std::thread thread_;
};

}  // namespace spinmotor::viewer
