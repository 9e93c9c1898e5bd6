#pragma once
// spinmotor/ga/blend.hpp — weighted blending of motors (paper §II.B.2: exp of the weighted sum of logs).
//
//   Blend::Log       exp(Σ w_i log M_i)                                   (the paper's blend)
//   Blend::PivotLog  exp(Σ w_i log(M_i ~M_p)) M_p, p = argmax w_i: invariant to M_i -> A M_i B
//   Blend::DLB    normalize(Σ w_i s_i M_i), s_i = sign <M_p ~M_i>_0: dual-quaternion linear blending
//                    (DLB, Kavan et al.) written for motors
//   blend_logs       exp(Σ w_i B_i) from logs computed once (many vertices, few shared motors)
//
// Log depends on the frame and on where the logs' cut locus lies: two motors that both rotate by
// nearly 180° about ±n (nearly the same motion) have logs ±(π/2) n, which average to no rotation.
// PivotLog blends in the frame of the heaviest motor (its logs are small when the motors are close)
// and DLB aligns signs; both are continuous there.
//
// Inputs: n unit motors and n weights (n ≥ 1; weights are used as given, normally a partition of
// unity). Output: a unit motor. No heap; meant for per-vertex loops. Throws spinmotor::Error (BadInput) on
// mismatched or empty spans, a non-finite weight or motor, on a motor with a zero
// rotor part, and when a DLB blend cancels (only possible with negative weights).
#include <cstddef>
#include <span>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/option_names.hpp"
#include "spinmotor/ga/motor.hpp"

namespace spinmotor::ga {

enum class Blend { Log, PivotLog, DLB };
inline constexpr OptionNames<Blend, 3> kBlendNames{
    "blend", {{{Blend::Log, "log"}, {Blend::PivotLog, "pivot-log"}, {Blend::DLB, "dlb"}}}};
constexpr const auto& option_names(Blend) { return kBlendNames; }

namespace detail {

/// Σ w_i log(M_i X) over the motors with a non-zero weight and an index other than `skip`
/// (X = 1 for Log, ~M_p for PivotLog), four logarithms at a time in SIMD lanes.
template <bool Relative>
Dll weighted_log_sum(std::span<const Mot> motors, std::span<const double> weights, const Mot& x,
                     std::size_t skip) {
  using A = Lanes<4>;
  static constexpr Mot identity(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);  // log = 0: fills unused lanes
  A acc[6] = {A::Zero(), A::Zero(), A::Zero(), A::Zero(), A::Zero(), A::Zero()};
  const std::size_t n = motors.size();
  for (std::size_t i = 0; i < n; i += 4) {
    A in[8], out[6], wl;
    if (!Relative && i + 4 <= n && skip == n && weights[i] != 0.0 && weights[i + 1] != 0.0 &&
        weights[i + 2] != 0.0 && weights[i + 3] != 0.0) {
      // four used motors (the usual case): the lanes are read straight from the motors
      static_assert(sizeof(Mot) == 8 * sizeof(double));
      const double* m = motors[i].data();
      const A sign(std::copysign(1.0, m[0]), std::copysign(1.0, m[8]), std::copysign(1.0, m[16]),
                   std::copysign(1.0, m[24]));  // the canonical sign (scalar part ≥ 0), no branches
      for (std::size_t j = 0; j < 8; ++j) in[j] = sign * A(m[j], m[8 + j], m[16 + j], m[24 + j]);
      wl = Eigen::Map<const A>(weights.data() + i);
    } else {
      // lane l holds motor i + l, or the identity past the end, at the skipped index and at a zero
      // weight (so that a zero-weight motor is never read into the arithmetic)
      const Mot* lane[4];
      [[maybe_unused]] Mot relative[4];
      double w[4];
      for (std::size_t l = 0; l < 4; ++l) {
        const std::size_t k = i + l;
        const bool used = k < n && k != skip && weights[k] != 0.0;
        w[l] = used ? weights[k] : 0.0;
        if constexpr (Relative) {
          if (used) relative[l] = motors[k] * x;
          lane[l] = used ? &relative[l] : &identity;
        } else {
          lane[l] = used ? &motors[k] : &identity;
        }
      }
      const A sign(std::copysign(1.0, (*lane[0])[0]), std::copysign(1.0, (*lane[1])[0]),
                   std::copysign(1.0, (*lane[2])[0]), std::copysign(1.0, (*lane[3])[0]));
      for (std::size_t j = 0; j < 8; ++j)
        in[j] = sign * A((*lane[0])[j], (*lane[1])[j], (*lane[2])[j], (*lane[3])[j]);
      wl = A(w[0], w[1], w[2], w[3]);
    }
    log_kernel(in, out);
    for (int j = 0; j < 6; ++j) acc[j] += wl * out[j];
  }
  const Dll sum(acc[0].sum(), acc[1].sum(), acc[2].sum(), acc[3].sum(), acc[4].sum(), acc[5].sum());
  if (!std::isfinite(sum[0] + sum[1] + sum[2] + sum[3] + sum[4] + sum[5]))
    throw Error("ga::blend: a weight or a motor is not finite");
  return sum;
}

/// The index of the largest weight (the first one on ties), without data-dependent branches.
[[nodiscard]] inline std::size_t pivot(std::span<const double> weights) noexcept {
  std::size_t p = 0;
  for (std::size_t i = 1; i < weights.size(); ++i) p = weights[i] > weights[p] ? i : p;
  return p;
}

/// DLB for motors: normalize(Σ w_i s_i M_i) with s_i the sign of <M_p ~M_i>_0 (the quaternion dot
/// product of the rotor parts), accumulated as two 4-lane halves (rotor part, translation part).
[[nodiscard]] inline Mot linear_blend(std::span<const Mot> motors, std::span<const double> weights,
                                      std::size_t p) {
  using A = Lanes<4>;
  const A rotor_p = Eigen::Map<const A>(motors[p].data());
  A lo = A::Zero(), hi = A::Zero();
  for (std::size_t i = 0; i < motors.size(); ++i) {
    const Eigen::Map<const A> mlo(motors[i].data()), mhi(motors[i].data() + 4);
    const double w = std::copysign(1.0, (rotor_p * mlo).sum()) * weights[i];  // no branch on random signs
    lo += w * mlo;
    hi += w * mhi;
  }
  Mot acc;
  Eigen::Map<A>(acc.data()) = lo;
  Eigen::Map<A>(acc.data() + 4) = hi;
  return normalize(acc);
}

}  // namespace detail

/// exp(Σ w_i B_i) for generators B_i = log(M_i) computed once: the per-vertex part of Blend::Log when
/// many vertices blend the same few motors (handles). Throws like blend().
[[nodiscard]] inline Mot blend_logs(std::span<const Dll> logs, std::span<const double> weights) {
  if (logs.empty() || weights.size() != logs.size())
    throw Error("ga::blend_logs: needs as many weights as generators, and at least one");
  Dll acc;
  for (std::size_t i = 0; i < logs.size(); ++i) acc += weights[i] * logs[i];
  if (!std::isfinite(acc[0] + acc[1] + acc[2] + acc[3] + acc[4] + acc[5]))
    throw Error("ga::blend_logs: a weight or a generator is not finite");
  return exp(acc);
}

[[nodiscard]] inline Mot blend(std::span<const Mot> motors, std::span<const double> weights, Blend mode) {
  const std::size_t n = motors.size();
  if (n == 0 || weights.size() != n)
    throw Error("ga::blend: needs as many weights as motors, and at least one motor");
  if (mode == Blend::Log) return exp(detail::weighted_log_sum<false>(motors, weights, Mot(), n));
  const std::size_t p = detail::pivot(weights);
  if (mode == Blend::PivotLog)  // log(M_p ~M_p) = 0: the pivot itself is skipped
    return exp(detail::weighted_log_sum<true>(motors, weights, reverse(motors[p]), p)) * motors[p];
  return detail::linear_blend(motors, weights, p);
}

}  // namespace spinmotor::ga
