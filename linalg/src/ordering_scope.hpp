#pragma once
// Internal to spinmotor_linalg: OrderingScope, around every CHOLMOD call that can run METIS
// (cholmod_analyze with any ordering, cholmod_metis; cholmod_amd too, for one rule). METIS installs its
// own SIGTERM handler for the length of an ordering (core/interrupt.hpp, "Dependencies that trap stop
// signals"): the scope defers the stop signals on the calling thread (DeferStopSignals: blocked, the
// handlers put back exactly afterwards and a pending signal delivered then), and makes the threads this
// library runs block them too, so that none of them can take a stop signal into METIS's handler
// meanwhile: OpenBLAS's idle workers are joined (use_single_threaded_blas: they start again, with
// their starter's mask, at the next threaded call; not when the user has set OPENBLAS_NUM_THREADS) and,
// once per calling thread, the workers of its OpenMP team block them. A program under
// take_stop_signals() blocks them in every thread already (and joins OpenBLAS's load-time workers).
#include "spinmotor/core/interrupt.hpp"

namespace spinmotor::detail {

class OrderingScope {
 public:
  OrderingScope();
  OrderingScope(const OrderingScope&) = delete;
  OrderingScope& operator=(const OrderingScope&) = delete;

 private:
  DeferStopSignals defer_;
};

}  // namespace spinmotor::detail
