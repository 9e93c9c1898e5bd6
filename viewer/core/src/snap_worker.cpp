#include "spinmotor/viewer/snap_worker.hpp"

#include <chrono>
#include <exception>

#include "spinmotor/error.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/conformal_snap.hpp"

namespace spinmotor::viewer {

SnapWorker::SnapWorker(Mesh rest) : rest_(std::move(rest)), thread_([this] { loop(); }) {}

SnapWorker::~SnapWorker() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    queued_.reset();
  }
  cv_.notify_all();
  thread_.join();
}

std::uint64_t SnapWorker::request(Eigen::MatrixXd V_edit, double tradeoff) {
  std::uint64_t g;
  {
    std::lock_guard lock(mutex_);
    if (queued_) ++discarded_;  // replaced before it started
    g = ++latest_;
    queued_ = Job{g, std::move(V_edit), tradeoff};
    result_.reset();
  }
  cv_.notify_all();
  return g;
}

void SnapWorker::cancel() {
  std::lock_guard lock(mutex_);
  if (queued_) ++discarded_, queued_.reset();
  ++latest_;
  result_.reset();
  idle_cv_.notify_all();
}

std::optional<SnapOutcome> SnapWorker::take() {
  std::lock_guard lock(mutex_);
  std::optional<SnapOutcome> out = std::move(result_);
  result_.reset();
  return out;
}

bool SnapWorker::busy() const {
  std::lock_guard lock(mutex_);
  return running_ || queued_.has_value();
}

bool SnapWorker::wait_idle(double timeout_s) {
  std::unique_lock lock(mutex_);
  return idle_cv_.wait_for(lock, std::chrono::duration<double>(timeout_s),
                           [&] { return !running_ && !queued_; });
}

std::uint64_t SnapWorker::discarded() const {
  std::lock_guard lock(mutex_);
  return discarded_;
}

void SnapWorker::loop() {
  std::unique_ptr<ConformalSnap> snap;  // bound on the first request, in this thread
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      cv_.wait(lock, [&] { return stop_ || queued_.has_value(); });
      if (stop_) return;
      job = std::move(*queued_);
      queued_.reset();
      running_ = true;
    }
    SnapOutcome out;
    out.generation = job.generation;
    try {
      auto t0 = std::chrono::steady_clock::now();
      if (!snap) {
        snap = std::make_unique<ConformalSnap>(rest_);
        out.bind_ms = snap->bind_ms();
      }
      snap->set_tradeoff(job.tradeoff);
      t0 = std::chrono::steady_clock::now();
      out.V = snap->snap(job.V).V;
      out.snap_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      out.Q = quasi_conformal_error(rest_.V, rest_.F, out.V);
      out.q_mean = quasi_conformal_summary(rest_.V, rest_.F, out.V).q_mean;
    } catch (const std::exception& e) {
      out.V.resize(0, 3);
      out.error = e.what();
    }
    {
      std::lock_guard lock(mutex_);
      running_ = false;
      if (out.generation == latest_)
        result_ = std::move(out);
      else
        ++discarded_;
      if (!queued_) idle_cv_.notify_all();
    }
  }
}

}  // namespace spinmotor::viewer
