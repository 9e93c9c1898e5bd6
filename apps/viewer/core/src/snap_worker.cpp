#include "spinmotor/viewer/snap_worker.hpp"

#include <chrono>
#include <memory>

#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/core/stopwatch.hpp"

namespace spinmotor::viewer {

namespace {
}  // namespace

SnapWorker::SnapWorker(Mesh rest)
    : LatestJobWorker([rest = std::make_shared<const Mesh>(std::move(rest)),
                       snap = std::shared_ptr<ConformalSnap>()](SnapJob& job, std::uint64_t generation) mutable {
        return outcome_of<SnapOutcome>(generation, [&](SnapOutcome& out) {
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
