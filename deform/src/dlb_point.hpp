#pragma once
// Internal to deform/src: the linear (DLB) blend of motors applied to a point without normalizing the
// blended motor first (shared by motor_blend_field.cpp, ffd.cpp and skinning.cpp).
#include <Eigen/Core>

namespace spinmotor::detail {

/// m = the unnormalized sum Σ s_j w_j M_j (8 motor components, ga::Mot order), i.e. the dual
/// quaternion r + ε d (ga/interop.hpp layout: r = (m0, −m3, −m2, −m1), d = (−m7, −m4, −m5, −m6)),
/// standing for normalize(m). It moves p to (r p r̄ + 2 vec(d r̄)) / |r|²: the component of d along r
/// that normalization removes does not reach the point (Kavan et al. 2008 §4). A cancelled blend
/// (|r| = 0) gives a non-finite point: the caller reports it.
///
/// One formula for every caller: T is double (one vertex) or an Eigen array type (one vertex per lane,
/// the block paths of SkinDeformer and FfdDeformer); m[c] and the point's coordinates are T or
/// expressions of it, the outputs anything a T can be assigned to.
template <class T, class M, class P, class O>
[[gnu::always_inline]] inline void dlb_point_into(const M& m, const P& px, const P& py, const P& pz, O&& ox,
                                                  O&& oy, O&& oz) {
  const T w = m[0], vx = -m[3], vy = -m[2], vz = -m[1];
  const T d0 = -m[7], dx = -m[4], dy = -m[5], dz = -m[6];
  const T s2 = 2.0 / (w * w + vx * vx + vy * vy + vz * vz);
  const T ax = vy * pz - vz * py, ay = vz * px - vx * pz, az = vx * py - vy * px;  // v × p
  const T bx = vy * az - vz * ay, by = vz * ax - vx * az, bz = vx * ay - vy * ax;  // v × (v × p)
  const T cx = vy * dz - vz * dy, cy = vz * dx - vx * dz, cz = vx * dy - vy * dx;  // v × dv
  ox = px + s2 * (w * ax + bx + w * dx - d0 * vx + cx);
  oy = py + s2 * (w * ay + by + w * dy - d0 * vy + cy);
  oz = pz + s2 * (w * az + bz + w * dz - d0 * vz + cz);
}

/// dlb_point_into for one vertex.
[[gnu::always_inline]] inline Eigen::Vector3d dlb_point(const double* m, const Eigen::Vector3d& p) {
  Eigen::Vector3d q;
  dlb_point_into<double>(m, p.x(), p.y(), p.z(), q.x(), q.y(), q.z());
  return q;
}

}  // namespace spinmotor::detail
