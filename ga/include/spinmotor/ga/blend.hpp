#pragma once
// spinmotor/ga/blend.hpp — weighted blending of motors (paper §II.B.2: exp of the weighted sum of logs).
//
//   Blend::Log       exp(Σ w_i log M_i)                                   (the paper's blend)
//   Blend::PivotLog  exp(Σ w_i log(M_i ~M_p)) M_p, p = argmax w_i: invariant to M_i -> A M_i B
//   Blend::Linear    normalize(Σ w_i s_i M_i), s_i = sign <M_p ~M_i>_0: dual-quaternion linear blending
//                    (DLB, Kavan et al.) written for motors
//
// Log depends on the frame and on where the logs' cut locus lies: two motors that both rotate by
// nearly 180° about ±n (nearly the same motion) have logs ±(π/2) n, which average to no rotation.
// PivotLog blends in the frame of the heaviest motor (its logs are small when the motors are close)
// and Linear aligns signs; both are continuous there.
//
// Inputs: n unit motors and n weights (n ≥ 1; weights are used as given, normally a partition of
// unity). Output: a unit motor. No heap; meant for per-vertex loops. Throws std::invalid_argument on
// mismatched or empty spans, std::domain_error when a Linear blend cancels (only possible with
// negative weights).
#include <cstddef>
#include <span>

#include "spinmotor/ga/motor.hpp"

namespace spinmotor::ga {

enum class Blend { Log, PivotLog, Linear };

inline Mot blend(std::span<const Mot> motors, std::span<const double> weights, Blend mode) {
  const std::size_t n = motors.size();
  if (n == 0 || weights.size() != n)
    throw std::invalid_argument("ga::blend: needs as many weights as motors, and at least one motor");
  std::size_t p = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (weights[i] > weights[p]) p = i;
  switch (mode) {
    case Blend::Log: {
      Dll acc;
      for (std::size_t i = 0; i < n; ++i)
        if (weights[i] != 0.0) acc += weights[i] * log(motors[i]);
      return exp(acc);
    }
    case Blend::PivotLog: {
      const Mot inv = reverse(motors[p]);
      Dll acc;
      for (std::size_t i = 0; i < n; ++i)
        if (i != p && weights[i] != 0.0) acc += weights[i] * log(motors[i] * inv);
      return exp(acc) * motors[p];
    }
    case Blend::Linear:
    default: {
      Mot acc;
      const Mot rp = reverse(motors[p]);
      for (std::size_t i = 0; i < n; ++i) {
        const double d = scalar(motors[i], rp);  // the quaternion dot product of the rotor parts
        acc += (std::signbit(d) ? -weights[i] : weights[i]) * motors[i];
      }
      return normalize(acc);
    }
  }
}

}  // namespace spinmotor::ga
