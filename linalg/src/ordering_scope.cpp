#include "ordering_scope.hpp"

#include <omp.h>

#include "spinmotor/linalg/blas_threads.hpp"

namespace spinmotor::detail {

namespace {

// The workers of the calling thread's OpenMP team (started by its first parallel region, kept for the
// next ones) block the stop signals from now on. A team started later with more threads has workers
// that do not.
void block_stop_signals_in_openmp_workers() {
  thread_local bool done = false;
  if (done) return;
  done = true;
#pragma omp parallel
  if (omp_get_thread_num() != 0) block_stop_signals_on_this_thread();
}

}  // namespace

OrderingScope::OrderingScope() {
  use_single_threaded_blas();
  if (!defer_.already_blocked()) block_stop_signals_in_openmp_workers();
}

}  // namespace spinmotor::detail
