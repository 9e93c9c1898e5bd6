#pragma once
// Wall-clock timing for the figures the tools report (bind_ms, pose_ms, progress lines).
//
//   const auto t0 = std::chrono::steady_clock::now();
//   ...;
//   report["bind_ms"] = ms_since(t0);
//
// Timings are for reports only: benchmarks (bench/) measure performance, tests never assert a time.
#include <chrono>

namespace spinmotor {

/// Milliseconds of std::chrono::steady_clock elapsed since t0.
[[nodiscard]] inline double ms_since(std::chrono::steady_clock::time_point t0) noexcept {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace spinmotor
