#include "spinmotor/linalg/blas_threads.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <mutex>

namespace spinmotor {

bool use_single_threaded_blas() {
  static std::once_flag once;
  static bool openblas = false;
  std::call_once(once, [] {
    using SetThreads = void (*)(int);
    const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    openblas = set != nullptr;
    if (set && std::getenv("OPENBLAS_NUM_THREADS") == nullptr) set(1);
  });
  return openblas;
}

}  // namespace spinmotor
