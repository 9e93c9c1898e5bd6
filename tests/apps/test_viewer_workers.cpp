// The viewer core's background workers under load (issue 19): LatestJobWorker itself, SnapWorker (free
// snap and pose-keeping cleanup, rebinding when the pins change) and SpinPaintWorker. A submitting
// thread sends thousands of requests with random pauses and cancels; a reader thread polls take()
// meanwhile; the worker thread computes. Asserted, for every request:
//   - it ends exactly once: taken by the reader, or counted in discarded() (taken + discarded = sent);
//   - a taken result is the answer to the latest request at the moment it is taken (its generation,
//     and no cancel since), and is that request's answer: for the snap and paint workers, equal to a
//     reference computed on this thread from the same input (a result of another request would differ
//     by the size of the edits, ~0.1, not 1e-9).
// Where ThreadSanitizer is available and the build is not an ASan one, tests/CMakeLists.txt compiles
// this file and the two worker sources with -fsanitize=thread (test "test_viewer_workers: ..." then runs
// under TSan, halt_on_error=1, so a race fails it); in the ASan build it runs under ASan.
//
// The submitter and the reader take one mutex around request()/cancel() and around take() with its
// check, so that "the latest request" is well defined when a result is checked; the worker thread is
// not synchronised with them by anything but the worker's own locking, which is what is under test.
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <mutex>
#include <random>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/spin/boundary_prescription.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"
#include "spinmotor/spin/spin_transform.hpp"
#include "spinmotor/viewer/curvature_paint.hpp"
#include "spinmotor/viewer/latest_job_worker.hpp"
#include "spinmotor/viewer/snap_worker.hpp"

namespace test_viewer_workers {

using namespace spinmotor;
using namespace spinmotor::viewer;

#if defined(__SANITIZE_THREAD__)
// The first race ends the run with a failure (TSan's default reports and goes on, exit code 66 at the
// end), with both stacks of a lock-order inversion.
extern "C" const char* __tsan_default_options() { return "halt_on_error=1:second_deadlock_stack=1"; }
#endif

namespace {

struct Tally {
  std::uint64_t sent = 0, cancels = 0, taken = 0, wrong = 0, discarded = 0;
  std::string first_wrong;
};

// Drives `w` from a submitting thread and a polling reader thread. send(w, job) requests job number
// `job` (chosen at random in [0, pool)); check(result, job) says whether a taken result answers request
// `job`. Now and then the submitter pauses for up to `wait_ms` (a few times a job's length), so that
// jobs finish and are taken.
template <class Worker, class Outcome>
Tally stress(Worker& w, int requests, int pool, double wait_ms, std::uint64_t seed,
             const std::function<std::uint64_t(Worker&, int)>& send,
             const std::function<std::string(const Outcome&, int)>& check) {
  std::mutex ui;  // the UI thread's order: a request and its bookkeeping are one step, as are take and check
  std::uint64_t latest_generation = 0;
  int latest_job = -1;
  bool live = false;  // the latest request has not been cancelled
  Tally t;
  bool done = false;

  auto examine = [&](const std::optional<Outcome>& r) {  // with `ui` held
    if (!r) return;
    ++t.taken;
    std::string why;
    if (!live)
      why = "a result after a cancel";
    else if (r->generation != latest_generation)
      why = "generation " + std::to_string(r->generation) + " taken while " +
            std::to_string(latest_generation) + " is the latest";
    else
      why = check(*r, latest_job);
    if (!why.empty() && t.wrong++ == 0) t.first_wrong = why;
  };

  std::thread reader([&] {
    for (;;) {
      {
        std::lock_guard lock(ui);
        examine(w.take());
        if (done) return;
      }
      std::this_thread::yield();
    }
  });
  std::thread submitter([&] {
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<int> pick(0, pool - 1), percent(0, 99), pause_us(0, 400),
        wait_us(0, static_cast<int>(1000 * wait_ms));
    for (int i = 0; i < requests; ++i) {
      {
        std::lock_guard lock(ui);
        const int job = pick(rng);
        latest_generation = send(w, job);
        latest_job = job;
        live = true;
        ++t.sent;
        // A new drag starts (everything in flight is stale) on 10% of the requests, never on the last:
        // its result is always taken after wait_idle, so take() is exercised however slowly the jobs
        // run (under ASan beside another test's threads, none finished within the pauses).
        if (i + 1 < requests && percent(rng) < 10) {
          w.cancel();
          live = false;
          ++t.cancels;
        }
      }
      // Mostly a drag's rate of requests (none to 0.4 ms apart: most are replaced before they run);
      // now and then a pause in which a job can finish and be taken.
      const int p = percent(rng);
      if (p < 3)
        std::this_thread::sleep_for(std::chrono::microseconds(wait_us(rng)));
      else if (p < 28)
        std::this_thread::sleep_for(std::chrono::microseconds(pause_us(rng)));
    }
  });
  submitter.join();
  REQUIRE(w.wait_idle(600));
  {
    std::lock_guard lock(ui);
    done = true;
  }
  reader.join();
  examine(w.take());  // the last one, if nobody took it yet
  t.discarded = w.discarded();
  return t;
}

void require_accounted(const Tally& t, int requests) {
  INFO("sent " << t.sent << ", cancels " << t.cancels << ", taken " << t.taken << ", discarded "
               << t.discarded << ", first wrong: " << t.first_wrong);
  CHECK(t.sent == static_cast<std::uint64_t>(requests));
  CHECK(t.wrong == 0);
  CHECK(t.taken + t.discarded == t.sent);  // every request ends exactly once
  CHECK(t.taken > 0);                      // the reader saw results: the test exercised take()
  CHECK(t.discarded > 0);                  // and requests were dropped: it exercised replacing
}

double max_abs_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return INFINITY;
  return (a - b).cwiseAbs().maxCoeff();
}

std::string differs(const Eigen::MatrixXd& got, const Eigen::MatrixXd& want, int job) {
  const double d = max_abs_diff(got, want);
  if (d <= 1e-9) return {};
  return "job " + std::to_string(job) + " differs from its reference by " + std::to_string(d);
}

// A capsule-like ellipsoid and a twist of it about z by `turn` radians per unit height.
Mesh capsule() {
  Mesh m = icosphere(2);
  m.V.col(2) *= 2.0;
  return m;
}
Eigen::MatrixXd twisted(const Mesh& rest, double turn) {
  Eigen::MatrixXd V = rest.V;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double a = turn * rest.V(i, 2);
    V(i, 0) = std::cos(a) * rest.V(i, 0) - std::sin(a) * rest.V(i, 1);
    V(i, 1) = std::sin(a) * rest.V(i, 0) + std::cos(a) * rest.V(i, 1);
  }
  return V;
}

}  // namespace

TEST_CASE(
    "LatestJobWorker: 10000 requests, cancels and a polling reader: each ends once, only the latest shows",
    "[viewer][threads]") {
  struct Echo {
    std::uint64_t generation = 0;
    Eigen::MatrixXd V;
    std::string error;
    int job = -1;
    std::uint64_t value = 0;
  };
  auto value_of = [](int job) { return 0x9E3779B97F4A7C15ull * static_cast<std::uint64_t>(job + 1); };
  using Worker = LatestJobWorker<int, Echo>;
  Worker w([&](int& job, std::uint64_t g) {
    Echo e;
    e.generation = g;
    e.job = job;
    std::uint64_t v = value_of(job);  // some work whose length varies with the job
    for (int k = 0; k < 50 * (job % 7); ++k) v = v * 6364136223846793005ull + 1442695040888963407ull;
    e.value = v;
    return e;
  });
  auto expected = [&](int job) {
    std::uint64_t v = value_of(job);
    for (int k = 0; k < 50 * (job % 7); ++k) v = v * 6364136223846793005ull + 1442695040888963407ull;
    return v;
  };
  constexpr int kRequests = 10000;
  const Tally t = stress<Worker, Echo>(
      w, kRequests, 1000, 1.0, 1, [](Worker& w, int job) { return w.request(job); },
      [&](const Echo& e, int job) -> std::string {
        if (e.job != job || e.value != expected(job))
          return "job " + std::to_string(job) + " answered with job " + std::to_string(e.job) + "'s result";
        return {};
      });
  require_accounted(t, kRequests);
}

TEST_CASE(
    "SnapWorker: 2000 snap and pose-keeping requests (two pin sets: rebinds), cancels, a polling reader",
    "[viewer][threads]") {
  const Mesh rest = capsule();
  // The pool: three twists, each as a free snap at tradeoff 1 and 0.5, and as a pinned cleanup with
  // the caps pinned (|z| > 1.4) or only the bottom cap pinned (z < -1.4): switching pins rebinds.
  std::vector<int> caps, bottom;
  for (Eigen::Index i = 0; i < rest.V.rows(); ++i) {
    if (std::abs(rest.V(i, 2)) > 1.4) caps.push_back(static_cast<int>(i));
    if (rest.V(i, 2) < -1.4) bottom.push_back(static_cast<int>(i));
  }
  REQUIRE(caps.size() > bottom.size());
  REQUIRE(!bottom.empty());
  struct Entry {
    Eigen::MatrixXd edit;
    double tradeoff = 1;
    const std::vector<int>* pins = nullptr;
    Eigen::MatrixXd reference;
  };
  std::vector<Entry> pool;
  for (double turn : {0.2, 0.4, 0.6}) {
    const Eigen::MatrixXd edit = twisted(rest, turn);
    pool.push_back({edit, 1.0, nullptr, {}});
    pool.push_back({edit, 0.5, nullptr, {}});
    pool.push_back({edit, 1.0, &caps, {}});
    pool.push_back({edit, 1.0, &bottom, {}});
  }
  ConformalSnap snap(rest);
  PinnedCleanup clean_caps = PinnedCleanup::bind(rest, std::span<const int>(caps));
  PinnedCleanup clean_bottom = PinnedCleanup::bind(rest, std::span<const int>(bottom));
  for (Entry& e : pool) {
    if (e.pins == &caps)
      clean_caps.cleanup(e.edit, e.reference);
    else if (e.pins == &bottom)
      clean_bottom.cleanup(e.edit, e.reference);
    else {
      snap.set_tradeoff(e.tradeoff);
      e.reference = snap.snap(e.edit).V;
    }
  }
  // The references differ from one another by far more than the tolerance: a swapped result shows.
  for (std::size_t a = 0; a < pool.size(); ++a)
    for (std::size_t b = a + 1; b < pool.size(); ++b)
      REQUIRE(max_abs_diff(pool[a].reference, pool[b].reference) > 1e-3);

  SnapWorker w(rest);
  constexpr int kRequests = 2000;
  const Tally t = stress<SnapWorker, SnapOutcome>(
      w, kRequests, static_cast<int>(pool.size()), 20.0, 2,
      [&](SnapWorker& w, int job) {
        const Entry& e = pool[static_cast<std::size_t>(job)];
        return e.pins ? w.request_pinned(e.edit, *e.pins) : w.request(e.edit, e.tradeoff);
      },
      [&](const SnapOutcome& r, int job) -> std::string {
        const Entry& e = pool[static_cast<std::size_t>(job)];
        if (!r.error.empty()) return "job " + std::to_string(job) + ": " + r.error;
        if (r.pinned != (e.pins != nullptr))
          return "job " + std::to_string(job) + ": the wrong kind of cleanup";
        return differs(r.V, e.reference, job);
      });
  require_accounted(t, kRequests);
}

TEST_CASE(
    "SpinPaintWorker: 2000 curvature requests, cancels, a polling reader: results match the SpinTransform",
    "[viewer][threads]") {
  const Mesh rest = capsule();
  std::vector<Eigen::VectorXd> rhos;
  std::vector<Eigen::MatrixXd> references;
  SpinTransform spin(rest);
  for (double amount : {-1.0, 0.5, 1.0, 2.0}) {
    Eigen::VectorXd rho = Eigen::VectorXd::Zero(rest.F.rows());
    paint_rho(rest.V, rest.F, Eigen::Vector3d(0, 0, 2), 1.2, amount, rho);
    references.push_back(spin.solve(rho).V);
    rhos.push_back(std::move(rho));
  }
  for (std::size_t a = 0; a < rhos.size(); ++a)
    for (std::size_t b = a + 1; b < rhos.size(); ++b)
      REQUIRE(max_abs_diff(references[a], references[b]) > 1e-3);

  SpinPaintWorker w(rest);
  constexpr int kRequests = 2000;
  const Tally t = stress<SpinPaintWorker, PaintOutcome>(
      w, kRequests, static_cast<int>(rhos.size()), 20.0, 3,
      [&](SpinPaintWorker& w, int job) { return w.request(rhos[static_cast<std::size_t>(job)]); },
      [&](const PaintOutcome& r, int job) -> std::string {
        if (!r.error.empty()) return "job " + std::to_string(job) + ": " + r.error;
        return differs(r.V, references[static_cast<std::size_t>(job)], job);
      });
  require_accounted(t, kRequests);
}

}  // namespace test_viewer_workers
