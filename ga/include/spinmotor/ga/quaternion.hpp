#pragma once
// spinmotor/ga/quaternion.hpp — the rotor sub-algebra is the project's one quaternion type.
//
// Quat = Rot stores (w, x, y, z) for q = w + x i + y j + z k with i = e32, j = e13, k = e21
// (ij = k, i² = -1). Under this isomorphism
//   Hamilton product  = geometric product  (p * q)
//   conjugate q̄       = reverse            (conj(q) = ~q)
//   |q|²              = norm2(q) = <q ~q>_0
//   q⁻¹               = inverse(q)
// and the rotor R x ~R acting on a vector is q x q̄ (Eigen::Quaterniond's convention: q * v).
// Crane 2011's similarity v ↦ conj(λ) v λ on imaginary quaternions is conj(λ) * imaginary(v) * λ.
#include <Eigen/Geometry>

#include "spinmotor/ga/products.hpp"

namespace spinmotor::ga {

using Quat = Rot;

/// The imaginary quaternion v.x i + v.y j + v.z k.
[[nodiscard]] inline Quat imaginary(const Eigen::Vector3d& v) noexcept {
  return Quat(0.0, v.x(), v.y(), v.z());
}

/// Quaternion conjugate w - x i - y j - z k (the reverse).
[[nodiscard]] inline Quat conj(const Quat& q) noexcept { return reverse(q); }

/// From Eigen's (w, x, y, z) quaternion; the component order is the same.
[[nodiscard]] inline Quat from_quaterniond(const Eigen::Quaterniond& q) noexcept {
  return Quat(q.w(), q.x(), q.y(), q.z());
}

/// To Eigen's quaternion (not normalised).
[[nodiscard]] inline Eigen::Quaterniond to_quaterniond(const Quat& q) noexcept {
  return Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z());
}

/// Rotate a vector by a unit quaternion: q v q̄ = R v ~R (no matrix; Eigen's formula
/// v + 2w (r×v) + 2 r×(r×v) with r the imaginary part).
[[nodiscard]] inline Eigen::Vector3d rotate(const Quat& q, const Eigen::Vector3d& v) {
  const Eigen::Vector3d r = q.vec();
  const Eigen::Vector3d uv = 2.0 * r.cross(v);
  return v + q.w() * uv + r.cross(uv);
}

}  // namespace spinmotor::ga
