#include "spinmotor/linalg/serial_openmp.hpp"

#include <dlfcn.h>
#include <omp.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace spinmotor {
namespace {

thread_local int t_depth = 0;  // SerialOpenMPScope nesting on this thread
std::atomic<std::uint64_t> g_direct{0};

}  // namespace

SerialOpenMPScope::SerialOpenMPScope() noexcept : previous_levels_(omp_get_max_active_levels()) {
  omp_set_max_active_levels(0);  // libgomp's own serialization, also where the interposition is not bound
  ++t_depth;
}

SerialOpenMPScope::~SerialOpenMPScope() {
  --t_depth;
  omp_set_max_active_levels(previous_levels_);
}

std::uint64_t serial_openmp_direct_regions() noexcept { return g_direct.load(std::memory_order_relaxed); }

}  // namespace spinmotor

extern "C" void GOMP_parallel(void (*fn)(void*), void* data, unsigned num_threads, unsigned flags);

namespace spinmotor {

bool serial_openmp_interposed() noexcept {
  return dlsym(RTLD_DEFAULT, "GOMP_parallel") == reinterpret_cast<void*>(&GOMP_parallel);
}

}  // namespace spinmotor

// libgomp's entry point for `#pragma omp parallel` (GCC's ABI since GCC 4.9: body, its data, the
// requested thread count (0: the default; 1 for a false `if` clause), proc_bind flags).
extern "C" void GOMP_parallel(void (*fn)(void*), void* data, unsigned num_threads, unsigned flags) {
  if (spinmotor::t_depth > 0 && (num_threads == 1 || omp_get_active_level() >= omp_get_max_active_levels())) {
    spinmotor::g_direct.fetch_add(1, std::memory_order_relaxed);
    fn(data);
    return;
  }
  using Parallel = void (*)(void (*)(void*), void*, unsigned, unsigned);
  static const Parallel next = [] {
    auto* f = reinterpret_cast<Parallel>(dlsym(RTLD_NEXT, "GOMP_parallel"));
    // A region of this library itself (ordering_scope.cpp) binds here in a shared build linked with
    // -Bsymbolic-functions, where libgomp was loaded first: the process's definition is then libgomp's.
    if (const auto global = reinterpret_cast<Parallel>(dlsym(RTLD_DEFAULT, "GOMP_parallel"));
        !f && global != &GOMP_parallel)
      f = global;
    if (!f) {
      std::fputs("spinmotor: GOMP_parallel: no OpenMP runtime (libgomp) found after this library\n", stderr);
      std::abort();
    }
    return f;
  }();
  next(fn, data, num_threads, flags);
}
