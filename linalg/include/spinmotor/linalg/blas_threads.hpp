#pragma once
// BLAS threading for the sparse Cholesky factorizations (CHOLMOD supernodal calls dgemm/dsyrk/dtrsm).
//
// The project's own loops are parallel with OpenMP and the spin transform prepares its Poisson factor
// on a second thread while the eigen matrix factors. A threaded BLAS (OpenBLAS's pthread build, which
// scripts/install-deps selects over Debian's reference BLAS) then runs its own busy-waiting threads
// on the same cores. Measured on 2 cores (bench_spin, nefertiti 100k faces, eq. 7): the factorization
// took 692 ms with the reference BLAS, 353–409 ms with OpenBLAS on one thread and 467 ms with OpenBLAS
// on two, and the inverse iterations' triangular solves 356–370 ms on one thread against 590 ms on two.
//
// use_single_threaded_blas() sets OpenBLAS to one thread (through openblas_set_num_threads, looked up
// at run time so that any BLAS can be linked) unless the user has set OPENBLAS_NUM_THREADS, which is
// then respected. Called by every CHOLMOD wrapper at bind; idempotent and thread-safe. Returns whether
// OpenBLAS was found.
//
// Setting one thread does not stop OpenBLAS's worker threads, which its pthread build starts when it
// is loaded: an idle worker spins on sched_yield for 2^28 cycles (~0.13 s here) after its start and
// after each threaded call before it sleeps. On two cores that spinning took a core from our OpenMP
// loops: `spinmotor spin` on SpinXForm's bumpy sphere used 284 ms of CPU in 154 ms (perf stat, 10
// runs), 151 ms in 123 ms with OPENBLAS_NUM_THREADS=1. So going to one thread (here, and at the end of
// every ScopedBlasThreads) also joins the workers (OpenBLAS's blas_thread_shutdown_; its next
// threaded call starts them again), unless BLAS work of this library is in flight on another thread
// (BlasCallScope), which could be using them. BLAS calls of other code in the process (numpy on the
// same OpenBLAS, in another thread) are not tracked: one that runs threaded at that instant races
// the shutdown.

//
// Large factors are the exception: a supernodal factorization with 104M nonzeros (the 1M-face spin
// transformation) took 9.2–9.4 s with OpenBLAS on two threads against 11.3–11.5 s on one, 37M nonzeros
// (400k faces) 2.9–3.7 s against 3.7–3.9 s, 8M (100k faces) 0.85–0.93 s against 0.74–0.86 s
// (docs/performance.md, "1M-face spin transformation"). What decides is the size of the dense fronts,
// which the flop count measures better than the nonzeros: the harmonic cage grid's factor (a 3D grid:
// 29M nonzeros, 4.2e10 flops) gains from two threads where a surface's 37M-nonzero factor (1.7e10)
// barely does. CholeskySolver::factorize gives its numeric factorization all cores from
// kThreadedBlasFactorFlops on (ScopedBlasThreads), the solves stay on one.
namespace spinmotor {

bool use_single_threaded_blas();

/// Joins OpenBLAS's worker threads now unless BLAS work of this library is in flight, whatever the
/// thread count (OPENBLAS_NUM_THREADS included); its next threaded call starts them again, from the
/// calling thread, whose signal mask they inherit. For a program's main() after take_stop_signals()
/// (core/interrupt.hpp): the workers OpenBLAS started when it was loaded do not block the stop signals.
/// Does nothing without OpenBLAS.
void join_idle_blas_workers();

/// Factorization work (CHOLMOD's flop count from the symbolic analysis, Common::fl; a complex entry's
/// operations counted once) from which a numeric factorization runs OpenBLAS on every core.
inline constexpr double kThreadedBlasFactorFlops = 1e10;

/// Marks BLAS work of this library in flight (every CHOLMOD and SuperLU call of the solver wrappers).
class BlasCallScope {
 public:
  BlasCallScope() noexcept;
  ~BlasCallScope();
  BlasCallScope(const BlasCallScope&) = delete;
  BlasCallScope& operator=(const BlasCallScope&) = delete;
};

/// For its lifetime, OpenBLAS runs `threads` threads (then one again). Does nothing without OpenBLAS
/// or when the user set OPENBLAS_NUM_THREADS. The setting is process-wide: another thread's BLAS calls
/// meanwhile use it too.
class ScopedBlasThreads {
 public:
  explicit ScopedBlasThreads(int threads);
  ~ScopedBlasThreads();
  ScopedBlasThreads(const ScopedBlasThreads&) = delete;
  ScopedBlasThreads& operator=(const ScopedBlasThreads&) = delete;

 private:
  bool active_ = false;
};

}  // namespace spinmotor
