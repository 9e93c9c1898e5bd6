#pragma once
// spinmotor/ga/constructors.hpp — points, planes, lines, spheres, rotors, translators, motors.
//
//   up(x)            null point o + x + ½|x|² inf                                  (paper §II.B)
//   down(X)          Euclidean point of a (weighted) null point: (X1, X2, X3) / X_o
//   vec(x) / to_eigen(v)    Euclidean vector <-> Eigen::Vector3d
//   rotor(axis, θ)   cos(θ/2) - sin(θ/2) I3 n̂: rotation by θ about n̂ (right hand); = Eigen AngleAxis
//   translator(t)    1 - ½ t inf: translation by t
//   motor(R, T)      T R: rotate by R, then translate by T
//   plane(n, d)      dual plane n̂ + d inf: the points with n̂·x = d
//   line(p, d)       dual line (up(p) ∧ d̂ ∧ inf)*: exp(½θ line(p, d)) rotates by θ about the line
//   sphere(c, r)     dual sphere up(c) - ½ r² inf: the points with |x - c| = r
//
// Bad input (zero axis, zero normal, zero direction, point at infinity) throws spinmotor::Error;
// spinmotor::Error lives in the mesh module, which depends on ga, not the other way round.

#include "spinmotor/core/error.hpp"
#include "spinmotor/ga/quaternion.hpp"

namespace spinmotor::ga {

[[nodiscard]] inline Vec vec(const Eigen::Vector3d& x) noexcept { return Vec(x.x(), x.y(), x.z()); }
[[nodiscard]] inline Eigen::Vector3d to_eigen(const Vec& v) { return {v[0], v[1], v[2]}; }

/// Null point o + x + ½|x|² inf.
[[nodiscard]] inline Pnt up(const Eigen::Vector3d& x) noexcept {
  return Pnt(x.x(), x.y(), x.z(), 1.0, 0.5 * x.squaredNorm());
}

/// The Euclidean point of a point X = w (o + x + ...): x = (X1, X2, X3) / X_o, X_o = -X·inf.
[[nodiscard]] inline Eigen::Vector3d down(const Pnt& p) {
  const double w = p.get<blade::o>();
  if (w == 0.0 || !std::isfinite(w))
    throw Error("ga::down: the point has zero (or non-finite) o component (point at infinity)");
  return Eigen::Vector3d(p[0], p[1], p[2]) / w;
}

/// Rotor cos(θ/2) - sin(θ/2) I3 n̂ (quaternion (cos θ/2, sin θ/2 n̂)): rotation by θ (radians) about
/// the axis (any length > 0). A zero axis is accepted only with θ = 0.
[[nodiscard]] inline Rot rotor(const Eigen::Vector3d& axis, double angle) {
  const double n = axis.norm();
  if (!(n > 0.0) || !std::isfinite(n) || !std::isfinite(angle)) {
    if (angle == 0.0 && std::isfinite(n)) return Rot(1.0, 0.0, 0.0, 0.0);
    throw Error("ga::rotor: the axis must be finite and non-zero");
  }
  const double s = std::sin(0.5 * angle) / n;
  return Rot(std::cos(0.5 * angle), s * axis.x(), s * axis.y(), s * axis.z());
}

/// Translator 1 - ½ t inf (translation by t).
[[nodiscard]] inline Trs translator(const Eigen::Vector3d& t) noexcept {
  return Trs(1.0, -0.5 * t.x(), -0.5 * t.y(), -0.5 * t.z());
}

/// The motor T R: first the rotation R, then the translation T.
[[nodiscard]] inline Mot motor(const Rot& r, const Trs& t) noexcept { return t * r; }

/// Dual plane n̂ + d inf, the points x with n̂·x = d (d = signed distance from the origin).
[[nodiscard]] inline Pln plane(const Eigen::Vector3d& normal, double d) {
  const double n = normal.norm();
  if (!(n > 0.0) || !std::isfinite(n)) throw Error("ga::plane: the normal must be finite and non-zero");
  return Pln(normal.x() / n, normal.y() / n, normal.z() / n, d);
}

/// Dual line L* = (up(p) ∧ d̂ ∧ inf) I⁻¹ through p with unit direction d̂. As a motor generator,
/// exp(½θ L*) is the rotation by θ about the line (right hand around d̂).
[[nodiscard]] inline Dll line(const Eigen::Vector3d& p, const Eigen::Vector3d& d) {
  const double n = d.norm();
  if (!(n > 0.0) || !std::isfinite(n)) throw Error("ga::line: the direction must be finite and non-zero");
  const Lin l = (up(p) ^ vec(d / n)) ^ MV<blade::ni>{1.0};
  return dual(l);
}

/// Dual sphere up(c) - ½ r² inf, the points with |x - c| = r.
[[nodiscard]] inline Sph sphere(const Eigen::Vector3d& c, double r) noexcept {
  Sph s = up(c);
  s[4] -= 0.5 * r * r;
  return s;
}

}  // namespace spinmotor::ga
