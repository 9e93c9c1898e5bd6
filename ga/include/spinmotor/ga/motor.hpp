#pragma once
// spinmotor/ga/motor.hpp — motor normalisation, exponential, logarithm, square root, ScLERP
// (paper §II.B.1-2; closed forms after Dorst & Valkenburg, "Square root and logarithm of rigid body
// motions", and Wareham & Lasenby).
//
// A motor generator (Dll) is B = I3 ω + v∧inf with ω, v ∈ R³, i.e. Dll components
// (e12, e31, e23, e1∞, e2∞, e3∞) = (ω_z, ω_y, ω_x, v_x, v_y, v_z). With φ = |ω|, split v = v_a + v_p
// (v_a ∥ ω commutes with I3 ω, v_p ⊥ ω anticommutes; (I3 ω + v_p inf)² = -φ²):
//
//   exp(B) = cos φ + sinc φ I3 ω + [sinc φ v + c2(φ) (v·ω) ω] inf + sinc φ (v·ω) I3 inf      (E)
//
// with sinc φ = sin φ / φ and c2(φ) = (cos φ - sinc φ)/φ² (both even, smooth, evaluated by series for
// φ < 0.1, no division by small numbers). exp(I3 ω) = cos φ + sin φ I3 ω̂ rotates by -2φ about ω̂:
// the rotation by θ about a unit axis n is ω = -½θ n (B = ½θ L* for the line L through the origin
// along n, see line()); a pure translation by t is ω = 0, v = -½t. The logarithm inverts (E) component by
// component after choosing the sign of M with scalar part ≥ 0 (M and -M are the same motion, so φ ∈ [0, π/2]
// and sinc φ ≥ 2/π):
//
//   φ = atan2(|β|, s),  ω = β / sinc φ,  v·ω = q / sinc φ,  v = (u - c2(φ) (v·ω) ω) / sinc φ
//
// where M = s + I3 β + u∧inf + q I3 inf. 180° rotations (s = 0), rotor angles near 2π (s near -1),
// pure translations (β = 0, exact round trip) and screws need no special case.
#include <cmath>
#include <stdexcept>

#include "spinmotor/ga/constructors.hpp"

namespace spinmotor::ga {

namespace detail {

/// sin φ / φ as a series in x = φ² (x < 0.01: truncation below 1e-18).
constexpr double sinc_series(double x) {
  return 1.0 - x / 6.0 * (1.0 - x / 20.0 * (1.0 - x / 42.0 * (1.0 - x / 72.0 * (1.0 - x / 110.0))));
}
/// cos φ as a series in x = φ² (x < 0.01).
constexpr double cos_series(double x) {
  return 1.0 - x / 2.0 * (1.0 - x / 12.0 * (1.0 - x / 30.0 * (1.0 - x / 56.0 * (1.0 - x / 90.0))));
}
/// (cos φ - sinc φ) / φ² = Σ_{k≥1} (-1)^k 2k x^{k-1} / (2k+1)! as a series in x = φ² (x < 0.01).
constexpr double c2_series(double x) {
  return -1.0 / 3.0 *
         (1.0 - x / 10.0 * (1.0 - x / 28.0 * (1.0 - x / 54.0 * (1.0 - x / 88.0 * (1.0 - x / 130.0)))));
}
inline constexpr double kSeriesBelow = 0.01;  // use the series when φ² < this

}  // namespace detail

/// The unit motor M / sqrt(M ~M): with M ~M = α + β I3 inf, M α^{-1/2} (1 - β/(2α) I3 inf). This is the
/// dual-quaternion normalisation (rotor part unit, translation part made orthogonal to it).
/// Throws std::domain_error when the rotor part is zero (or not finite).
inline Mot normalize(const Mot& m) {
  const auto n = m * reverse(m);
  const double alpha = n.get<blade::s>(), beta = n.get<blade::e123ni>();
  if (!(alpha > 0.0) || !std::isfinite(alpha))
    throw std::domain_error("ga::normalize: the motor's rotor part is zero or not finite");
  const double a = 1.0 / std::sqrt(alpha);
  return m * MV<blade::s, blade::e123ni>{a, -0.5 * beta / alpha * a};
}

/// The motor exp(B) of a generator B = I3 ω + v∧inf, formula (E) above.
inline Mot exp(const Dll& b) {
  const double wz = b[0], wy = b[1], wx = b[2], vx = b[3], vy = b[4], vz = b[5];
  const double x = wx * wx + wy * wy + wz * wz;
  double cs, k, c2;
  if (x < detail::kSeriesBelow) {
    cs = detail::cos_series(x);
    k = detail::sinc_series(x);
    c2 = detail::c2_series(x);
  } else {
    const double phi = std::sqrt(x);
    cs = std::cos(phi);
    k = std::sin(phi) / phi;
    c2 = (cs - k) / x;
  }
  const double vw = vx * wx + vy * wy + vz * wz, cv = c2 * vw;
  return Mot(cs, k * wz, k * wy, k * wx, k * vx + cv * wx, k * vy + cv * wy, k * vz + cv * wz, k * vw);
}

/// The logarithm of a motor: the generator B with exp(B) = ±M and rotation angle 2|ω| ≤ π (the short
/// way round; M and -M give the same B). Invariant to a positive scale of M. Throws std::domain_error
/// when the rotor part of M is zero (M is not a motor).
inline Dll log(const Mot& m) {
  const double sg = std::signbit(m[0]) ? -1.0 : 1.0;  // canonical sign: scalar part ≥ 0
  const double b2 = m[1] * m[1] + m[2] * m[2] + m[3] * m[3];
  const double rho2 = m[0] * m[0] + b2;
  if (!(rho2 > 0.0) || !std::isfinite(rho2))
    throw std::domain_error("ga::log: the motor's rotor part is zero or not finite");
  const double inv = sg / std::sqrt(rho2);  // 1 exactly for a unit rotor part (pure translations)
  const double s = inv * m[0], bn = std::abs(inv) * std::sqrt(b2);
  const double phi = std::atan2(bn, s);  // in [0, π/2]
  const double x = phi * phi;
  double k, c2;
  if (x < detail::kSeriesBelow) {
    k = detail::sinc_series(x);
    c2 = detail::c2_series(x);
  } else {
    k = bn / phi;
    c2 = (s - k) / x;
  }
  const double ik = inv / k;  // k ≥ 2/π
  const double wz = ik * m[1], wy = ik * m[2], wx = ik * m[3];
  const double vw = ik * m[7], cv = c2 * vw;
  return Dll(wz, wy, wx, (inv * m[4] - cv * wx) / k, (inv * m[5] - cv * wy) / k, (inv * m[6] - cv * wz) / k);
}

/// The square root of the motion: the unit motor S along the shortest screw with S S = M when
/// <M>_0 ≥ 0 and S S = -M otherwise (the same motion). Dorst & Valkenburg: S = (1 + M)/|1 + M|.
inline Mot sqrt(const Mot& m) {
  Mot a = std::signbit(m[0]) ? -m : m;
  a[0] += 1.0;
  return normalize(a);
}

/// Screw linear interpolation a (~a b)^t along the shortest screw from a (t = 0) to ±b (t = 1).
inline Mot sclerp(const Mot& a, const Mot& b, double t) { return a * exp(t * log(reverse(a) * b)); }

/// Rotor exponential: exp(I3 ω) = cos|ω| + sinc|ω| I3 ω, the rotation by -2|ω| about ω̂.
inline Rot exp(const Biv& b) {
  const double x = b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
  double cs, k;
  if (x < detail::kSeriesBelow) {
    cs = detail::cos_series(x);
    k = detail::sinc_series(x);
  } else {
    const double phi = std::sqrt(x);
    cs = std::cos(phi);
    k = std::sin(phi) / phi;
  }
  return cast<Rot>(Sca(cs) + k * b);
}

/// Rotor logarithm (short way round, sign canonicalised like the motor log). Throws std::domain_error
/// on a zero rotor.
inline Biv log(const Rot& r) {
  const double sg = std::signbit(r.w()) ? -1.0 : 1.0;
  const double b2 = r.x() * r.x() + r.y() * r.y() + r.z() * r.z(), rho2 = r.w() * r.w() + b2;
  if (!(rho2 > 0.0) || !std::isfinite(rho2))
    throw std::domain_error("ga::log: the rotor is zero or not finite");
  const double inv = sg / std::sqrt(rho2);
  const double phi = std::atan2(std::abs(inv) * std::sqrt(b2), inv * r.w());
  const double x = phi * phi;
  const double k = x < detail::kSeriesBelow ? detail::sinc_series(x) : std::abs(inv) * std::sqrt(b2) / phi;
  return (inv / k) * cast<Biv>(r);
}

}  // namespace spinmotor::ga
