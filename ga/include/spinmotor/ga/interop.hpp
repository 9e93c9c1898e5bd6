#pragma once
// spinmotor/ga/interop.hpp — motors <-> Eigen isometries, unit dual quaternions, fast point transform.
//
// A motor M = R + U inf (R the rotor, U = u + q I3) is the unit dual quaternion q_r + ε q_d with
//   q_r = (M_s, -M_e23, -M_e31, -M_e12)         (the rotor as a quaternion, see quaternion.hpp)
//   q_d = (-M_e123∞, -M_e1∞, -M_e2∞, -M_e3∞)    (ε = -I3 inf)
// and the standard convention q_d = ½ t q_r for "rotate by q_r, then translate by t".
#include <Eigen/Geometry>
#include <cstring>
#include <string>
#include <utility>

#include "spinmotor/core/error.hpp"
#include "spinmotor/ga/motor.hpp"

namespace spinmotor::ga {

/// The rotor part of a motor as a quaternion (the real part of its dual quaternion).
SPINMOTOR_GA_PURE Quat rotor_part(const Mot& m) noexcept { return Quat(m[0], -m[3], -m[2], -m[1]); }

/// The dual part of a motor's dual quaternion, q_d = ½ t q_r.
[[nodiscard]] inline Quat dual_part(const Mot& m) noexcept { return Quat(-m[7], -m[4], -m[5], -m[6]); }

/// The translation t of a unit motor (applied after its rotation): t = 2 vec(q_d q̄_r).
SPINMOTOR_GA_PURE Eigen::Vector3d translation(const Mot& m) noexcept {
  const double w = m[0], rx = -m[3], ry = -m[2], rz = -m[1];
  const double d0 = -m[7], dx = -m[4], dy = -m[5], dz = -m[6];
  // 2 (w d - d0 r + r × d)
  return {2.0 * (w * dx - d0 * rx + ry * dz - rz * dy), 2.0 * (w * dy - d0 * ry + rz * dx - rx * dz),
          2.0 * (w * dz - d0 * rz + rx * dy - ry * dx)};
}

namespace detail {
/// Eigen::Vector3d(a, b, c), writing (a, b) with one 16-byte store. Eigen copies the first two
/// coefficients of a Vector3d as one packet; after two 8-byte stores that load cannot be forwarded from
/// the store buffer, and the stall (~10 cycles) tripled the cost of transform() in point loops.
SPINMOTOR_GA_PURE Eigen::Vector3d vector3(double a, double b, double c) noexcept {
  Eigen::Vector3d r;
#if defined(__GNUC__)
  using v2d = double __attribute__((vector_size(16)));
  const v2d ab = {a, b};
  std::memcpy(r.data(), &ab, sizeof ab);
#else
  r[0] = a;
  r[1] = b;
#endif
  r[2] = c;
  return r;
}
}  // namespace detail

/// The point M x ~M for a unit motor M: R x + t with R the rotation matrix of the rotor part and t
/// the translation, on scalars (inlined into a loop over points with a fixed M, R and t are hoisted).
SPINMOTOR_GA_PURE Eigen::Vector3d transform(const Mot& m, const Eigen::Vector3d& p) noexcept {
  const double w = m[0], x = -m[3], y = -m[2], z = -m[1];  // the rotor as a quaternion
  const Eigen::Vector3d t = translation(m);
  const double xx = x * x, yy = y * y, zz = z * z, xy = x * y, xz = x * z, yz = y * z;
  const double wx = w * x, wy = w * y, wz = w * z;
  const double px = p.x(), py = p.y(), pz = p.z();
  return detail::vector3((1.0 - 2.0 * (yy + zz)) * px + 2.0 * (xy - wz) * py + 2.0 * (xz + wy) * pz + t.x(),
                         2.0 * (xy + wz) * px + (1.0 - 2.0 * (xx + zz)) * py + 2.0 * (yz - wx) * pz + t.y(),
                         2.0 * (xz - wy) * px + 2.0 * (yz + wx) * py + (1.0 - 2.0 * (xx + yy)) * pz + t.z());
}

namespace detail {
/// transform() on SIMD lanes (Eigen arrays), one unit motor and one point per lane: m[0..7] in Mot
/// order, p and q as (x, y, z). The same arithmetic as translation() and transform().
template <int K>
SPINMOTOR_GA_INLINE void transform_lanes(const Lanes<K> (&m)[8], const Lanes<K> (&p)[3],
                                         Lanes<K> (&q)[3]) noexcept {
  const Lanes<K> w = m[0], x = -m[3], y = -m[2], z = -m[1];
  const Lanes<K> d0 = -m[7], dx = -m[4], dy = -m[5], dz = -m[6];
  const Lanes<K> tx = 2.0 * (w * dx - d0 * x + y * dz - z * dy),
                 ty = 2.0 * (w * dy - d0 * y + z * dx - x * dz),
                 tz = 2.0 * (w * dz - d0 * z + x * dy - y * dx);
  const Lanes<K> xx = x * x, yy = y * y, zz = z * z, xy = x * y, xz = x * z, yz = y * z;
  const Lanes<K> wx = w * x, wy = w * y, wz = w * z;
  q[0] = (1.0 - 2.0 * (yy + zz)) * p[0] + 2.0 * (xy - wz) * p[1] + 2.0 * (xz + wy) * p[2] + tx;
  q[1] = 2.0 * (xy + wz) * p[0] + (1.0 - 2.0 * (xx + zz)) * p[1] + 2.0 * (yz - wx) * p[2] + ty;
  q[2] = 2.0 * (xz - wy) * p[0] + 2.0 * (yz + wx) * p[1] + (1.0 - 2.0 * (xx + yy)) * p[2] + tz;
}
}  // namespace detail

/// (real, dual) unit dual quaternion of a motor, dual = ½ t real.
[[nodiscard]] inline std::pair<Eigen::Quaterniond, Eigen::Quaterniond> to_dual_quaternion(
    const Mot& m) noexcept {
  return {to_quaterniond(rotor_part(m)), to_quaterniond(dual_part(m))};
}

/// The motor of a dual quaternion real + ε dual (inverse of to_dual_quaternion; not normalised).
[[nodiscard]] inline Mot from_dual_quaternion(const Eigen::Quaterniond& real,
                                              const Eigen::Quaterniond& dual) noexcept {
  return Mot(real.w(), -real.z(), -real.y(), -real.x(), -dual.x(), -dual.y(), -dual.z(), -dual.w());
}

/// The motor of a rigid motion x ↦ L x + t. Throws spinmotor::Error when L is not a rotation
/// (|LᵀL - I| > 1e-6 or det L ≤ 0) or an entry is not finite.
[[nodiscard]] inline Mot from_isometry(const Eigen::Isometry3d& iso) {
  const Eigen::Matrix3d l = iso.linear();
  const Eigen::Vector3d t = iso.translation();
  if (!l.allFinite() || !t.allFinite()) throw Error("ga::from_isometry: non-finite entry");
  const double orth = (l.transpose() * l - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orth > 1e-6 || l.determinant() <= 0.0)
    throw Error("ga::from_isometry: the linear part is not a rotation (|LᵀL - I| = " + std::to_string(orth) +
                ", det = " + std::to_string(l.determinant()) + ")");
  const Quat r = from_quaterniond(Eigen::Quaterniond(l).normalized());
  return motor(r, translator(t));
}

/// The rigid motion of a motor (its rotor part is normalised first).
[[nodiscard]] inline Eigen::Isometry3d to_isometry(const Mot& m) {
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = to_quaterniond(rotor_part(m)).normalized().toRotationMatrix();
  iso.translation() = translation(m);
  return iso;
}

}  // namespace spinmotor::ga
