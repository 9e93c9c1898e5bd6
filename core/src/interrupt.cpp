#include "spinmotor/core/interrupt.hpp"

#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <iterator>
#include <mutex>
#include <thread>

#include "temporaries.hpp"

namespace spinmotor {

namespace {

// Written by the handler, read by the run: a lock-free atomic is async-signal-safe (C++17 [support.signal]).
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);
// InterruptGuards alive: the signal thread records a signal while there is one.
std::atomic<int> g_guards{0};
std::atomic<bool> g_taken{false};

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
constexpr std::size_t kCount = std::size(kSignals);

sigset_t stop_set() {
  sigset_t set;
  sigemptyset(&set);
  for (const int sig : kSignals) sigaddset(&set, sig);
  return set;
}

void record(int sig) noexcept {
  int none = 0;
  g_signal.compare_exchange_strong(none, sig);  // keep the first
}

extern "C" void record_signal(int sig) { record(sig); }

// The thread of take_stop_signals(): every stop signal sent to the process ends up here, whatever
// handler is installed at the time (every thread blocks them, so none is delivered to a handler).
void wait_for_stop_signals() {
  const sigset_t set = stop_set();
  for (;;) {
    int sig = 0;
    if (sigwait(&set, &sig) != 0) continue;
    if (g_guards.load() > 0) {
      record(sig);
      continue;
    }
    // What remove_temporary_files_on_signal()'s handler does (atomic_file.hpp): no temporary left, then
    // the process ends by the signal (the parent sees "killed by SIGTERM").
    detail::remove_temporaries_in_flight();
    struct sigaction dfl = {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    sigaction(sig, &dfl, nullptr);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, sig);
    pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    raise(sig);  // delivered to this thread at once: the default action ends the process
  }
}

// The handlers DeferStopSignals puts back: saved by the first guard of the process to start, restored
// by the last to end (two threads ordering at once would otherwise restore each other's METIS handler).
std::mutex g_defer_mutex;
int g_defer_depth = 0;
struct sigaction g_defer_saved[kCount];

}  // namespace

struct InterruptGuard::Saved {
  struct sigaction previous[kCount];
};

InterruptGuard::InterruptGuard() : saved_(std::make_unique<Saved>()) {
  g_signal.store(0);
  g_guards.fetch_add(1);
  struct sigaction sa = {};
  sa.sa_handler = record_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // interrupted system calls resume: a write in progress completes
  for (std::size_t i = 0; i < kCount; ++i) sigaction(kSignals[i], &sa, &saved_->previous[i]);
}

InterruptGuard::~InterruptGuard() {
  for (std::size_t i = 0; i < kCount; ++i) sigaction(kSignals[i], &saved_->previous[i], nullptr);
  g_guards.fetch_sub(1);
}

int interrupted() noexcept { return g_signal.load(); }

std::string signal_name(int signal) {
  switch (signal) {
    case SIGHUP:
      return "SIGHUP";
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    default:
      return "signal " + std::to_string(signal);
  }
}

struct DeferStopSignals::Saved {
  sigset_t mask;  // the calling thread's, before the guard
};

DeferStopSignals::DeferStopSignals() : saved_(std::make_unique<Saved>()) {
  const sigset_t set = stop_set();
  pthread_sigmask(SIG_BLOCK, &set, &saved_->mask);
  already_blocked_ = true;
  for (const int sig : kSignals) already_blocked_ = already_blocked_ && sigismember(&saved_->mask, sig) == 1;
  const std::lock_guard lock(g_defer_mutex);
  if (g_defer_depth++ == 0)
    for (std::size_t i = 0; i < kCount; ++i) sigaction(kSignals[i], nullptr, &g_defer_saved[i]);
}

DeferStopSignals::~DeferStopSignals() {
  {
    const std::lock_guard lock(g_defer_mutex);
    if (--g_defer_depth == 0)
      for (std::size_t i = 0; i < kCount; ++i) sigaction(kSignals[i], &g_defer_saved[i], nullptr);
  }
  pthread_sigmask(SIG_SETMASK, &saved_->mask, nullptr);  // a pending stop signal is delivered here
}

void block_stop_signals_on_this_thread() noexcept {
  const sigset_t set = stop_set();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

void take_stop_signals() {
  static std::once_flag once;
  std::call_once(once, [] {
    block_stop_signals_on_this_thread();
    std::thread(wait_for_stop_signals).detach();  // inherits the blocked mask; sigwait takes them
    g_taken.store(true);
  });
}

bool stop_signals_taken() noexcept { return g_taken.load(); }

}  // namespace spinmotor
