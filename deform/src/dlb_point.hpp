#pragma once
// Internal to deform/src: the linear (DLB) blend of motors applied to a point without normalizing the
// blended motor first (shared by motor_blend_field.cpp, ffd.cpp and skinning.cpp).
#include <Eigen/Core>

namespace spinmotor::detail {

/// acc = the unnormalized sum Σ s_j w_j M_j (8 motor components, ga::Mot order), i.e. the dual
/// quaternion r + ε d (ga/interop.hpp layout: r = (m0, −m3, −m2, −m1), d = (−m7, −m4, −m5, −m6)),
/// standing for normalize(acc). It moves p to (r p r̄ + 2 vec(d r̄)) / |r|²: the component of d along r
/// that normalization removes does not reach the point (Kavan et al. 2008 §4). A cancelled blend
/// (|r| = 0) gives a non-finite point: the caller reports it.
[[gnu::always_inline]] inline Eigen::Vector3d dlb_point(const double* m, const Eigen::Vector3d& p) {
  const double w = m[0], vx = -m[3], vy = -m[2], vz = -m[1];
  const double d0 = -m[7], dx = -m[4], dy = -m[5], dz = -m[6];
  const double s2 = 2.0 / (w * w + vx * vx + vy * vy + vz * vz);
  const double ax = vy * p.z() - vz * p.y(), ay = vz * p.x() - vx * p.z(),
               az = vx * p.y() - vy * p.x();                                            // v × p
  const double bx = vy * az - vz * ay, by = vz * ax - vx * az, bz = vx * ay - vy * ax;  // v × (v × p)
  const double cx = vy * dz - vz * dy, cy = vz * dx - vx * dz, cz = vx * dy - vy * dx;  // v × dv
  return {p.x() + s2 * (w * ax + bx + w * dx - d0 * vx + cx),
          p.y() + s2 * (w * ay + by + w * dy - d0 * vy + cy),
          p.z() + s2 * (w * az + bz + w * dz - d0 * vz + cz)};
}

}  // namespace spinmotor::detail
