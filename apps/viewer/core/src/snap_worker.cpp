#include "spinmotor/viewer/snap_worker.hpp"

#include <chrono>
#include <memory>
#include <span>

#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace spinmotor::viewer {

SnapWorker::SnapWorker(Mesh rest)
    : LatestJobWorker(
          [rest = std::make_shared<const Mesh>(std::move(rest)), snap = std::shared_ptr<ConformalSnap>(),
           cleanup = std::shared_ptr<PinnedCleanup>(), cleanup_pins = std::vector<int>(), cleanup_gamma = 0.0,
           cleanup_attraction = Eigen::VectorXd()](SnapJob& job, std::uint64_t generation) mutable {
            return outcome_of<SnapOutcome>(generation, [&](SnapOutcome& out) {
              if (!job.pins.empty()) {  // the pose-keeping cleanup, bound once per pin set
                if (!cleanup || job.pins != cleanup_pins || job.pose_weight != cleanup_gamma ||
                    job.attraction.size() != cleanup_attraction.size() ||
                    job.attraction != cleanup_attraction) {
                  PinnedCleanupOptions o;
                  o.pose_weight = job.pose_weight;
                  cleanup = std::make_shared<PinnedCleanup>(PinnedCleanup::bind(
                      *rest, job.pins, o,
                      std::span<const double>(job.attraction.data(),
                                              static_cast<size_t>(job.attraction.size()))));
                  cleanup_pins = job.pins;
                  cleanup_gamma = job.pose_weight;
                  cleanup_attraction = job.attraction;
                  out.bind_ms = cleanup->bind_ms();
                }
                const auto t0 = std::chrono::steady_clock::now();
                const PinnedCleanupResult r = cleanup->cleanup(job.V_edit, out.V);
                out.snap_ms = ms_since(t0);
                out.pinned = true;
                out.volume_ratio = r.measure_ratio();
                out.Q = quasi_conformal_error(rest->V, rest->F, out.V);
                out.q_mean = quasi_conformal_summary(rest->V, rest->F, out.V).q_mean;
                return;
              }
              if (!snap) {  // bound on the first request, in the worker thread
                snap = std::make_shared<ConformalSnap>(*rest);
                out.bind_ms = snap->bind_ms();
              }
              snap->set_tradeoff(job.tradeoff);
              const auto t0 = std::chrono::steady_clock::now();
              out.V = snap->snap(job.V_edit).V;
              out.snap_ms = ms_since(t0);
              out.Q = quasi_conformal_error(rest->V, rest->F, out.V);
              out.q_mean = quasi_conformal_summary(rest->V, rest->F, out.V).q_mean;
            });
          }) {}

}  // namespace spinmotor::viewer
