#include "spinmotor/linalg/blas_threads.hpp"

#include <dlfcn.h>

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
    if (const SetThreads set = managed_setter()) set(1);
  });
  return openblas;
}

ScopedBlasThreads::ScopedBlasThreads(int threads) {
  if (const SetThreads set = managed_setter(); set && threads > 1) {
    set(threads);
    active_ = true;
  }
}

ScopedBlasThreads::~ScopedBlasThreads() {
  if (active_) managed_setter()(1);
}

}  // namespace spinmotor
