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

namespace spinmotor {

bool use_single_threaded_blas();

}  // namespace spinmotor
