#pragma once
// One background thread that runs the latest request only: the pattern behind the viewer's "snap to
// spin when a drag ends" and "apply the painted curvature". Every request gets a new generation and
// replaces a queued one; cancel() makes everything queued or running stale; a result whose
// generation is no longer the latest is discarded, so the UI never shows the answer to a question it
// no longer asks. Every request ends exactly once: taken, or counted in discarded() (replaced while
// queued, cancelled, finished stale, or finished but replaced before anyone took it). `compute` runs on the
// worker thread and may keep state between calls (e.g. a factorization bound on the first request); it must
// not throw (report errors in its Outcome).
//
//   LatestJobWorker<Eigen::VectorXd, Result> w([](Eigen::VectorXd& rho, std::uint64_t g) { ... });
//   w.request(rho);            // UI thread, returns at once
//   if (auto r = w.take()) ... // UI thread, every frame
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

#include "spinmotor/core/interrupt.hpp"

namespace spinmotor::viewer {

/// The body of a worker's `compute`: fills a fresh Outcome (with its generation) through body(out);
/// an exception becomes out.error with out.V emptied, since a worker's compute must not throw.
/// Outcome needs `generation`, `V` (a matrix) and `error` (a string).
template <class Outcome, class Body>
Outcome outcome_of(std::uint64_t generation, Body&& body) {
  Outcome out;
  out.generation = generation;
  try {
    body(out);
  } catch (const std::exception& e) {
    out.V.resize(0, 3);
    out.error = e.what();
  }
  return out;
}

template <class Job, class Outcome>
class LatestJobWorker {
 public:
  using Compute = std::function<Outcome(Job& job, std::uint64_t generation)>;

  explicit LatestJobWorker(Compute compute)
      : compute_(std::move(compute)), thread_([this] {
          block_stop_signals_on_this_thread();  // stop signals are the application's (core/interrupt.hpp)
          loop();
        }) {}
  /// Waits for the job in progress, if any, then stops.
  ~LatestJobWorker() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
      queued_.reset();
    }
    cv_.notify_all();
    thread_.join();
  }
  LatestJobWorker(const LatestJobWorker&) = delete;
  LatestJobWorker& operator=(const LatestJobWorker&) = delete;

  /// Queues `job`, replacing a queued one. Returns its generation.
  std::uint64_t request(Job job) {
    std::uint64_t g;
    {
      std::lock_guard lock(mutex_);
      if (queued_) ++discarded_;  // replaced before it started
      if (result_) ++discarded_;  // finished, never taken
      g = ++latest_;
      queued_.emplace(g, std::move(job));
      result_.reset();
    }
    cv_.notify_all();
    return g;
  }
  /// Makes every queued or running request stale.
  void cancel() {
    std::lock_guard lock(mutex_);
    if (queued_) ++discarded_, queued_.reset();
    if (result_) ++discarded_, result_.reset();
    ++latest_;
    idle_cv_.notify_all();
  }
  /// The result of the latest request, once (nothing while it runs, or when it was cancelled).
  std::optional<Outcome> take() {
    std::lock_guard lock(mutex_);
    std::optional<Outcome> out = std::move(result_);
    result_.reset();
    return out;
  }
  bool busy() const {
    std::lock_guard lock(mutex_);
    return running_ || queued_.has_value();
  }
  /// Blocks until nothing is queued or running (tests, headless mode). False on timeout.
  bool wait_idle(double timeout_s) {
    std::unique_lock lock(mutex_);
    return idle_cv_.wait_for(lock, std::chrono::duration<double>(timeout_s),
                             [&] { return !running_ && !queued_; });
  }
  /// Requests dropped so far: replaced while queued, cancelled, finished stale, or finished and then
  /// replaced by a newer request before take().
  std::uint64_t discarded() const {
    std::lock_guard lock(mutex_);
    return discarded_;
  }

 private:
  void loop() {
    for (;;) {
      std::pair<std::uint64_t, Job> job;
      {
        std::unique_lock lock(mutex_);
        cv_.wait(lock, [&] { return stop_ || queued_.has_value(); });
        if (stop_) return;
        job = std::move(*queued_);
        queued_.reset();
        running_ = true;
      }
      Outcome out = compute_(job.second, job.first);
      {
        std::lock_guard lock(mutex_);
        running_ = false;
        if (job.first == latest_)
          result_ = std::move(out);
        else
          ++discarded_;
        if (!queued_) idle_cv_.notify_all();
      }
    }
  }

  Compute compute_;
  mutable std::mutex mutex_;
  std::condition_variable cv_, idle_cv_;
  std::optional<std::pair<std::uint64_t, Job>> queued_;
  std::optional<Outcome> result_;
  std::uint64_t latest_ = 0, discarded_ = 0;
  bool running_ = false, stop_ = false;
  std::thread thread_;  // last: started after every other member exists
};

}  // namespace spinmotor::viewer
