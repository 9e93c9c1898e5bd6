#include "spinmotor/linalg/blas_threads.hpp"

#include <dlfcn.h>

#include <atomic>
#include <cstdlib>
#include <mutex>

namespace spinmotor {

namespace {

using SetThreads = void (*)(int);

/// openblas_set_num_threads, or null when another BLAS is linked.
SetThreads openblas_setter() {
  static const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  return set;
}

using Shutdown = int (*)();

/// OpenBLAS's blas_thread_shutdown_ (joins its worker threads; the next threaded call starts them
/// again), or null.
Shutdown openblas_shutdown() {
  static const auto stop = reinterpret_cast<Shutdown>(dlsym(RTLD_DEFAULT, "blas_thread_shutdown_"));
  return stop;
}

/// BLAS work of this library in flight (BlasCallScope).
std::atomic<int> g_calls{0};

/// With OpenBLAS on one thread, stops its idle workers when no BLAS work of ours is in flight. A call
/// that starts after set(1) runs on its caller's thread and never reaches the workers, so only calls
/// counted in g_calls could be using them.
void park_workers(SetThreads set) {
  set(1);
  if (const Shutdown stop = openblas_shutdown(); stop && g_calls.load() == 0) stop();
}

/// openblas_setter() unless the user has set OPENBLAS_NUM_THREADS (theirs is then respected).
SetThreads managed_setter() {
  static const SetThreads set = std::getenv("OPENBLAS_NUM_THREADS") == nullptr ? openblas_setter() : nullptr;
  return set;
}

}  // namespace

bool use_single_threaded_blas() {
  static std::once_flag once;
  static bool openblas = false;
  std::call_once(once, [] {
    openblas = openblas_setter() != nullptr;
    if (const SetThreads set = managed_setter()) park_workers(set);
  });
  return openblas;
}

void join_idle_blas_workers() {
  if (const Shutdown stop = openblas_shutdown(); stop && g_calls.load() == 0) stop();
}

ScopedBlasThreads::ScopedBlasThreads(int threads) {
  if (const SetThreads set = managed_setter(); set && threads > 1) {
    set(threads);
    active_ = true;
  }
}

ScopedBlasThreads::~ScopedBlasThreads() {
  if (active_) park_workers(managed_setter());
}

BlasCallScope::BlasCallScope() noexcept { g_calls.fetch_add(1); }
BlasCallScope::~BlasCallScope() { g_calls.fetch_sub(1); }

}  // namespace spinmotor
