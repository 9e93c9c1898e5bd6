#pragma once
// The parallel policy: when an OpenMP loop over items (vertices, faces, edges, points) runs in parallel.
//
// A parallel region costs a fork/join of a few microseconds, and far more when the cores are
// oversubscribed (a descheduled spinning thread stalls the barrier). A loop therefore goes parallel
// only when its items carry enough work in total. Items are classed by their cost, and each class
// has the item count from which it pays:
//
//   #pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend))
//
// The counts were chosen by measurement on 2 cores (bench/: bench_laplacian for assembly, bench_deform
// and bench_ffd_skin for motor blends, bench_arap for the rotation fits, bench_deform's cage bind).
#include <cstdint>

namespace spinmotor::parallel {

/// A few tens of flops per item: operator assembly (cotangents of a face), quaternion edge maps.
inline constexpr std::int64_t kAssembly = 20000;
/// A few hundred flops per item: a motor blend and sandwich per vertex (deformers' pose()).
inline constexpr std::int64_t kMotorBlend = 8192;
/// About a thousand flops per item: a 3×3 SVD / polar decomposition per vertex or face (ARAP).
inline constexpr std::int64_t kRotationFit = 4096;
/// Tens of thousands of flops per item: a sum over a whole cage per point (winding numbers, weights).
inline constexpr std::int64_t kCageSum = 256;

/// True when a loop over `items` items of the given class should run in parallel.
[[nodiscard]] constexpr bool worth(std::int64_t items, std::int64_t min_items) noexcept {
  return items >= min_items;
}

}  // namespace spinmotor::parallel
