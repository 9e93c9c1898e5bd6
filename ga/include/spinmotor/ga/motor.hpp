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
// with sinc φ = sin φ / φ and c2(φ) = (cos φ - sinc φ)/φ². exp(I3 ω) = cos φ + sin φ I3 ω̂ rotates by
// -2φ about ω̂: the rotation by θ about a unit axis n is ω = -½θ n (B = ½θ L* for the line L through
// the origin along n, see line()); a pure translation by t is ω = 0, v = -½t.
//
// The logarithm inverts (E) component by component after choosing the sign of M with scalar part
// s ≥ 0 (M and -M are the same motion, so φ ∈ [0, π/2] and sinc φ ≥ 2/π). Writing
// M = s + I3 β + u∧inf + q I3 inf (unit rotor part),
//
//   φ = atan2(|β|, s),  ω = β / sinc φ,  v·ω = q / sinc φ,  v = (u - c2(φ) (v·ω) ω) / sinc φ.
//
// The only small divisor is the φ² of c2, and c2 is only ever multiplied by (v·ω) ω, of size |v| φ²:
// its cancellation for small φ costs at most an absolute |v|·ulp. 180° rotations (s = 0), rotor
// angles near 2π (s near -1: the sign flip takes the short way), pure translations (β = 0: exact
// round trip) and screws need no special case. No acos (ill-conditioned near s = ±1), no atan2 call
// (see detail::log_kernel), no branch on the angle.
#include <array>
#include <cmath>

#include "spinmotor/core/error.hpp"
#include "spinmotor/ga/constructors.hpp"

namespace spinmotor::ga {

namespace detail {

/// Taylor coefficients in x = φ² of cos φ = Σ (-x)^k/(2k)!, sinc φ = Σ (-x)^k/(2k+1)! and
/// c2(φ) = (cos φ - sinc φ)/φ² = Σ (-1)^(k+1) (2k+2) x^k/(2k+3)!, enough terms for |φ| ≤ 1.6
/// (x ≤ 2.56: the first omitted terms are below 2e-18).
struct ExpSeries {
  std::array<double, 12> cos{};
  std::array<double, 11> sinc{}, c2{};
  constexpr ExpSeries() {
    double f = 1.0;  // f = 1/n!, n = 0, 1, 2, ...
    for (int n = 0; n <= 23; ++n) {
      if (n > 0) f /= n;
      const int k = n / 2;
      const double sign = (k % 2) ? -1.0 : 1.0;
      if (n % 2 == 0 && k < 12) cos[static_cast<std::size_t>(k)] = sign * f;
      if (n % 2 == 1 && k < 11) sinc[static_cast<std::size_t>(k)] = sign * f;
      if (n % 2 == 1 && n >= 3 && k - 1 < 11) c2[static_cast<std::size_t>(k - 1)] = sign * (n - 1) * f;
    }
  }
};
inline constexpr ExpSeries kExpSeries{};
inline constexpr double kExpSeriesMax = 2.56;

/// Σ_i c[first + 2i] y^i over i < sizeof...(I) + 1, by Horner's rule unrolled at compile time.
template <std::size_t N, std::size_t... I>
[[nodiscard]] constexpr double horner2(const std::array<double, N>& c, std::size_t first, double y,
                                       std::index_sequence<I...>) {
  constexpr std::size_t top = sizeof...(I);
  double acc = c[first + 2 * top];
  ((acc = acc * y + c[first + 2 * (top - 1 - I)]), ...);
  return acc;
}

/// c[0] + c[1] x + ... + c[N-1] x^(N-1) as two Horner chains in x² (half the latency of one).
template <std::size_t N>
[[nodiscard]] constexpr double poly(const std::array<double, N>& c, double x) {
  static_assert(N >= 2);
  const double x2 = x * x;
  return horner2(c, 0, x2, std::make_index_sequence<(N + 1) / 2 - 1>{}) +
         x * horner2(c, 1, x2, std::make_index_sequence<N / 2 - 1>{});
}

/// cos φ, sinc φ = sin φ / φ and c2(φ) from x = φ² ≥ 0: polynomials for |φ| ≤ 1.6 (no sqrt, no
/// division, no libm call: the exponential of a blended generator sits at the end of a long
/// dependency chain), std::sin and std::cos beyond.
inline void exp_coefficients(double x, double& cs, double& k, double& c2) {
  if (x <= kExpSeriesMax) {
    cs = poly(kExpSeries.cos, x);
    k = poly(kExpSeries.sinc, x);
    c2 = poly(kExpSeries.c2, x);
  } else {
    const double phi = std::sqrt(x);
    cs = std::cos(phi);
    k = std::sin(phi) / phi;
    c2 = (cs - k) / x;
  }
}

/// log_kernel works on doubles (T = double: log(const Mot&)) or on SIMD lanes, one motor per lane
/// (T = Eigen::Array4d: the four-at-a-time logarithms of blend()). It is straight-line arithmetic, so
/// Eigen vectorises every operation of the lane version.
template <int L>
using Lanes = Eigen::Array<double, L, 1>;

[[nodiscard]] inline double lane_sqrt(double x) noexcept { return std::sqrt(x); }
template <class T>
SPINMOTOR_GA_PURE auto lane_sqrt(const Eigen::ArrayBase<T>& x) noexcept {
  return x.sqrt().eval();
}
[[nodiscard]] inline bool positive_finite(double x) noexcept { return x > 0.0 && std::isfinite(x); }
template <class T>
SPINMOTOR_GA_PURE bool positive_finite(const Eigen::ArrayBase<T>& x) noexcept {
  return x.minCoeff() > 0.0 && std::isfinite(x.sum());  // a NaN or inf lane makes the sum non-finite
}

/// atan(t) / t = 1 - S(z) as a function of z = t², for |t| < 0.4375: the unreduced branch of fdlibm's
/// s_atan.c (< 1 ulp), whose minimax coefficients are used here under this notice:
///   Copyright (C) 1993 by Sun Microsystems, Inc. All rights reserved.
///   Developed at SunSoft, a Sun Microsystems, Inc. business.
///   Permission to use, copy, modify, and distribute this software is freely granted, provided that
///   this notice is preserved.
/// (Not std::atan2: it does not vectorise, and glibc's atan2 wrapper is legacy-SSE code whose AVX-SSE
/// transition stalls made the log blend 4x slower.)
template <class T>
SPINMOTOR_GA_PURE T atan_ratio(const T& z) noexcept {
  constexpr double aT[11] = {
      3.33333333333329318027e-01,  -1.99999999998764832476e-01, 1.42857142725034663711e-01,
      -1.11111104054623557880e-01, 9.09088713343650656196e-02,  -7.69187620504482999495e-02,
      6.66107313738753120669e-02,  -5.83357013379057348645e-02, 4.97687799461593236017e-02,
      -3.65315727442169155270e-02, 1.62858201153657823623e-02};
  // S = z Σ_k aT[k] z^k by Estrin's scheme (four levels of independent products: a shorter dependency
  // chain than Horner's ten, which the logarithm's latency is made of)
  const T z2 = z * z, z4 = z2 * z2, z8 = z4 * z4;
  const T c01 = aT[0] + z * aT[1], c23 = aT[2] + z * aT[3], c45 = aT[4] + z * aT[5];
  const T c67 = aT[6] + z * aT[7], c89 = aT[8] + z * aT[9];
  const T lo = (c01 + z2 * c23) + z4 * (c45 + z2 * c67);
  const T hi = c89 + z2 * aT[10];
  return 1.0 - z * (lo + z8 * hi);
}

/// The generators (Dll order) of motors given by their 8 components (Mot order) with scalar part
/// s = m[0] ≥ 0. Invariant to a positive scale of the motor. Throws spinmotor::Error when a rotor part
/// is zero or not finite. With ρ = |rotor part|, b = |β| and P = ρ + s ≥ ρ > 0, the half-angle tangents
///   tan(φ/2) = b / P,   t = tan(φ/4) = b / (P + sqrt(P² + b²)) ∈ [0, tan(π/8)]
/// put φ = 4 atan(t) in the range of fdlibm's polynomial atan(t) = t (1 - S(t²)), and
///   r = φ / b = 4 (1 - S) / (P + sqrt(P² + b²)) = 1 / (ρ sinc φ)
/// needs no division by b (nor any branch), and t enters only as t² = b² / (P + sqrt(P² + b²))², so
/// b = sqrt(b²) is never formed (the divider's square roots and divisions set the 4-lane kernel's
/// throughput: docs/performance.md, "Log blend"): ω = r β, v·ω = r q, v = r u - g (v·ω) ω with
/// g = ρ r c2(φ) = (s r - 1) / φ².
template <class T>
SPINMOTOR_GA_INLINE void log_kernel(const T (&m)[8], T (&out)[6]) {
  const T b2 = m[1] * m[1] + m[2] * m[2] + m[3] * m[3];
  const T rho2 = m[0] * m[0] + b2;
  if (!positive_finite(rho2)) throw Error("ga::log: the motor's rotor part is zero or not finite");
  const T p = lane_sqrt(rho2) + m[0];
  const T d = 1.0 / (p + lane_sqrt(p * p + b2));
  const T z = b2 * (d * d);                              // t², t = tan(φ/4)
  const T r = 4.0 * atan_ratio(z) * d;                   // φ / b
  const T g = (m[0] * r - 1.0) / (r * r * b2 + 1e-300);  // / φ²; the guard turns 0/0 into 0 at φ = 0
  out[0] = r * m[1];                                     // ω_z
  out[1] = r * m[2];                                     // ω_y
  out[2] = r * m[3];                                     // ω_x
  const T gv = g * (r * m[7]);                           // g (v·ω)
  out[3] = r * m[4] - gv * out[2];
  out[4] = r * m[5] - gv * out[1];
  out[5] = r * m[6] - gv * out[0];
}

/// Σ_k c[k] x^k by Horner's rule on SIMD lanes (Eigen arrays).
template <std::size_t N, class T>
SPINMOTOR_GA_PURE T horner_lanes(const std::array<double, N>& c, const T& x) noexcept {
  T acc = T::Constant(c[N - 1]);
  for (std::size_t k = N - 1; k-- > 0;) acc = acc * x + c[k];
  return acc;
}

/// Formula (E) on SIMD lanes, one generator per lane: b[0..5] in Dll order (ω_z, ω_y, ω_x, v_x, v_y,
/// v_z), m[0..7] in Mot order. The same arithmetic as exp(const Dll&): the series of exp_coefficients
/// for every lane when all lanes have φ ≤ 1.6, else the coefficients lane by lane (std::sin, std::cos).
template <int K>
SPINMOTOR_GA_INLINE void exp_lanes(const Lanes<K> (&b)[6], Lanes<K> (&m)[8]) noexcept {
  const Lanes<K> x = b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
  Lanes<K> cs, k, c2;
  if (x.maxCoeff() <= kExpSeriesMax) {
    cs = horner_lanes(kExpSeries.cos, x);
    k = horner_lanes(kExpSeries.sinc, x);
    c2 = horner_lanes(kExpSeries.c2, x);
  } else {
    for (int l = 0; l < K; ++l) exp_coefficients(x[l], cs[l], k[l], c2[l]);
  }
  const Lanes<K> vw = b[3] * b[2] + b[4] * b[1] + b[5] * b[0], cv = c2 * vw;
  m[0] = cs;
  m[1] = k * b[0];
  m[2] = k * b[1];
  m[3] = k * b[2];
  m[4] = k * b[3] + cv * b[2];
  m[5] = k * b[4] + cv * b[1];
  m[6] = k * b[5] + cv * b[0];
  m[7] = k * vw;
}

}  // namespace detail

/// The unit motor M / sqrt(M ~M): with M ~M = α + β I3 inf, M α^{-1/2} (1 - β/(2α) I3 inf). This is the
/// dual-quaternion normalisation (rotor part unit, translation part made orthogonal to it).
/// Throws spinmotor::Error when the rotor part is zero (or not finite).
[[nodiscard]] inline Mot normalize(const Mot& m) {
  const auto n = m * reverse(m);
  const double alpha = n.get<blade::s>(), beta = n.get<blade::e123ni>();
  if (!(alpha > 0.0) || !std::isfinite(alpha))
    throw Error("ga::normalize: the motor's rotor part is zero or not finite");
  const double a = 1.0 / std::sqrt(alpha);  // α^{-1/2}; β/(2α) α^{-1/2} = ½ β a³
  return m * MV<blade::s, blade::e123ni>{a, -0.5 * beta * (a * a * a)};
}

/// The motor exp(B) of a generator B = I3 ω + v∧inf, formula (E) above.
[[nodiscard]] inline Mot exp(const Dll& b) noexcept {
  const double wz = b[0], wy = b[1], wx = b[2], vx = b[3], vy = b[4], vz = b[5];
  double cs, k, c2;
  detail::exp_coefficients(wx * wx + wy * wy + wz * wz, cs, k, c2);
  const double vw = vx * wx + vy * wy + vz * wz, cv = c2 * vw;
  return Mot(cs, k * wz, k * wy, k * wx, k * vx + cv * wx, k * vy + cv * wy, k * vz + cv * wz, k * vw);
}

/// The logarithm of a motor: the generator B with exp(B) = ±M and rotation angle 2|ω| ≤ π (the short
/// way round; M and -M give the same B). Invariant to a positive scale of M. Throws spinmotor::Error
/// when the rotor part of M is zero (M is not a motor).
[[nodiscard]] inline Dll log(const Mot& m) {
  const double sg = std::copysign(1.0, m[0]);  // canonical sign: scalar part ≥ 0
  double in[8], out[6];
  for (std::size_t j = 0; j < 8; ++j) in[j] = sg * m[j];
  detail::log_kernel(in, out);
  return Dll(out[0], out[1], out[2], out[3], out[4], out[5]);
}

/// The square root of the motion: the unit motor S along the shortest screw with S S = M when
/// <M>_0 ≥ 0 and S S = -M otherwise (the same motion). Dorst & Valkenburg: S = (1 + M)/|1 + M|.
[[nodiscard]] inline Mot sqrt(const Mot& m) {
  Mot a = std::copysign(1.0, m[0]) * m;
  a[0] += 1.0;
  return normalize(a);
}

/// Screw linear interpolation a (~a b)^t along the shortest screw from a (t = 0) to ±b (t = 1).
[[nodiscard]] inline Mot sclerp(const Mot& a, const Mot& b, double t) {
  return a * exp(t * log(reverse(a) * b));
}

/// Rotor exponential: exp(I3 ω) = cos|ω| + sinc|ω| I3 ω, the rotation by -2|ω| about ω̂.
[[nodiscard]] inline Rot exp(const Biv& b) noexcept {
  double cs, k, c2;
  detail::exp_coefficients(b[0] * b[0] + b[1] * b[1] + b[2] * b[2], cs, k, c2);
  return cast<Rot>(Sca(cs) + k * b);
}

/// Rotor logarithm (short way round, sign canonicalised like the motor log). Throws spinmotor::Error
/// on a zero rotor.
[[nodiscard]] inline Biv log(const Rot& r) {
  const Dll b = log(Mot(r));
  return Biv(b[0], b[1], b[2]);
}

}  // namespace spinmotor::ga
