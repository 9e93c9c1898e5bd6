// `spinmotor info`: what this build has (version, libraries, threads).
#include <omp.h>

#include <Eigen/Core>
#include <iostream>

#include "command.hpp"
#include "spinmotor/linalg/blas_threads.hpp"

namespace {
const spinmotor::cli::RegisterCommand register_version{
    "info", "Print the version and the libraries of this build", [](CLI::App& sub) {
      sub.callback([] {
        std::cout << "spinmotor " << SPINMOTOR_VERSION << "\n"
                  << "Eigen " << EIGEN_WORLD_VERSION << '.' << EIGEN_MAJOR_VERSION << '.'
                  << EIGEN_MINOR_VERSION << "\n"
                  << "OpenMP threads " << omp_get_max_threads() << "\n"
                  << "BLAS under CHOLMOD: "
                  << (spinmotor::use_single_threaded_blas()
                          ? "OpenBLAS (one thread, see mesh/blas_threads.hpp)"
                          : "not OpenBLAS (reference or other BLAS)")
                  << "\n";
      });
    }};
}  // namespace
