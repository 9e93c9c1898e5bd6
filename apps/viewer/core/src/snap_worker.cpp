#include "spinmotor/viewer/snap_worker.hpp"

#include <chrono>
#include <memory>
#include <span>

#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace spinmotor::viewer {

namespace {

/// The cleanups a snap worker binds, kept across requests while their inputs stay the same.
struct Bound {
  std::shared_ptr<ConformalSnap> snap;
  std::shared_ptr<PinnedCleanup> pinned;  // handles pinned
  std::vector<int> pins;
  std::shared_ptr<scene::RigCleanup> rig;  // a skin's rig cleanup
  std::shared_ptr<const spinmotor::Rig> skin;
};

void run_job(const Mesh& rest, Bound& b, SnapJob& job, SnapOutcome& out) {
  const auto finish = [&](double ms) {
    out.snap_ms = ms;
    out.Q = quasi_conformal_error(rest.V, rest.F, out.V);
    out.q_mean = quasi_conformal_summary(rest.V, rest.F, out.V).q_mean;
  };
  if (job.skin) {  // the rig cleanup, bound once per skin
    if (!b.rig || b.skin != job.skin) {
      b.rig = std::make_shared<scene::RigCleanup>(
          scene::RigCleanup::bind(rest, job.skin->weights, job.skin->skeleton));
      b.skin = job.skin;
      out.bind_ms = b.rig->bind_ms();
    }
    const auto t0 = std::chrono::steady_clock::now();
    const scene::RigCleanupResult r = (*b.rig)(job.V_edit, out.V);
    out.pinned = true;
    out.pins = b.rig->pins().size();
    out.volume_ratio = r.volume_ratio;
    return finish(ms_since(t0));
  }
  if (!job.pins.empty()) {  // the pose-keeping cleanup, bound once per pin set
    if (!b.pinned || job.pins != b.pins) {
      b.pinned = std::make_shared<PinnedCleanup>(PinnedCleanup::bind(rest, job.pins));
      b.pins = job.pins;
      out.bind_ms = b.pinned->bind_ms();
    }
    const auto t0 = std::chrono::steady_clock::now();
    const PinnedCleanupResult r = b.pinned->cleanup(job.V_edit, out.V);
    out.pinned = true;
    out.pins = b.pinned->pins().size();
    out.volume_ratio = r.measure_ratio();
    return finish(ms_since(t0));
  }
  if (!b.snap) {  // bound on the first request, in the worker thread
    b.snap = std::make_shared<ConformalSnap>(rest);
    out.bind_ms = b.snap->bind_ms();
  }
  b.snap->set_tradeoff(job.tradeoff);
  const auto t0 = std::chrono::steady_clock::now();
  out.V = b.snap->snap(job.V_edit).V;
  finish(ms_since(t0));
}

}  // namespace

SnapWorker::SnapWorker(Mesh rest)
    : LatestJobWorker([rest = std::make_shared<const Mesh>(std::move(rest)), bound = Bound()](
                          SnapJob& job, std::uint64_t generation) mutable {
        return outcome_of<SnapOutcome>(generation,
                                       [&](SnapOutcome& out) { run_job(*rest, bound, job, out); });
      }) {}

}  // namespace spinmotor::viewer
