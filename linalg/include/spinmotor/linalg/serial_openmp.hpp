#pragma once
// SerialOpenMPScope: CHOLMOD's OpenMP regions run as plain calls on the calling thread.
//
// SuiteSparse 5's supernodal factorization opens OpenMP regions of a fixed 4 threads
// (CHOLMOD_OMP_NUM_THREADS, compiled in) to zero and scatter into each supernode, and behind an `if`
// on the supernode's size: thousands of regions per factorization (12,873 for SpinXForm's 8k-face
// sphere, eigen and Poisson factors together). On two cores their fork/joins of four threads were a
// fifth of the 80k-vertex harmonic bind, so the factorizations run them serially (max-active-levels
// 0, a per-task setting: other threads' loops keep their teams): the bind took 250 ms against 367 ms,
// the 64-grid cage bind 3.39 s against 3.65-4.0 s. A serialized region is not free either: libgomp still
// builds a team of one and ends it at a barrier whose last arrival always issues a futex wake, a system call
// of ~1.1 µs on these paravirtualized machines (120,076 futex calls for 120,000 regions, strace; 1.14 µs a
// region with `if (0)` or with max-active-levels 0 alike). That was half of the complex factorization's time
// on that sphere (35 ms against 17 ms, docs/performance.md, "Serialized OpenMP regions").
//
// Inside a SerialOpenMPScope (per thread; nestable), this library's GOMP_parallel, the entry point
// GCC emits for `#pragma omp parallel`, calls the region's body directly when the region would run
// on one thread anyway (max-active-levels reached, or a single thread requested); every other region
// goes to libgomp's GOMP_parallel unchanged. The body then runs outside any team, exactly as an
// orphaned construct: omp_get_num_threads() is 1, omp_get_thread_num() 0, a worksharing loop takes
// the whole range and its barrier returns at once. What differs from libgomp's serialized region is
// only what the body could ask about nesting (omp_get_level() does not count it); CHOLMOD does not
// ask.
//
// The definition takes effect where the dynamic linker binds CHOLMOD's GOMP_parallel to it: in every
// program linked statically with this library (the linker exports it for libcholmod's reference). In
// the shared-library build libgomp is loaded ahead of libspinmotor_linalg and keeps the symbol, as it
// may in the Python module: correct, without the saving (serial_openmp_interposed() tells). A compiler whose
// OpenMP runtime is not libgomp does not use the symbol; the scope then only sets max-active-levels.
#include <cstdint>

namespace spinmotor {

class SerialOpenMPScope {
 public:
  SerialOpenMPScope() noexcept;
  ~SerialOpenMPScope();
  SerialOpenMPScope(const SerialOpenMPScope&) = delete;
  SerialOpenMPScope& operator=(const SerialOpenMPScope&) = delete;

 private:
  int previous_levels_;
};

/// Parallel regions this process has run as plain calls (inside a SerialOpenMPScope); for tests and
/// benchmarks. Stays 0 where the interposition does not take effect.
[[nodiscard]] std::uint64_t serial_openmp_direct_regions() noexcept;

/// Whether the process's global symbol lookup finds this library's GOMP_parallel first (what libcholmod
/// binds to). True in programs linked statically with the library; in the shared-library build
/// (BUILD_SHARED_LIBS, CI's sanitizer preset) libgomp is usually ahead of libspinmotor_linalg in the
/// load order, and libgomp's serialized regions are used instead.
[[nodiscard]] bool serial_openmp_interposed() noexcept;

}  // namespace spinmotor
