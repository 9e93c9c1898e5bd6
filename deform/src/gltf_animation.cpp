// Sampling glTF animations (gltf_animation.hpp).
#include "spinmotor/deform/gltf_animation.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "spinmotor/core/error.hpp"

namespace spinmotor {

namespace {

// Spherical linear interpolation along the shorter arc (glTF 2.0 Appendix C), normalised.
Eigen::VectorXd slerp_xyzw(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double u) {
  double d = a.dot(b);
  const double s = d < 0.0 ? -1.0 : 1.0;
  d = std::min(std::abs(d), 1.0);
  Eigen::VectorXd r;
  if (d > 1.0 - 1e-12) {
    r = (1.0 - u) * a + s * u * b;  // nearly equal: the lerp is exact to rounding
  } else {
    const double th = std::acos(d), sn = std::sin(th);
    r = std::sin((1.0 - u) * th) / sn * a + s * std::sin(u * th) / sn * b;
  }
  return r.normalized();
}

Eigen::Matrix4d trs_matrix(const Eigen::Vector3d& t, const Eigen::Quaterniond& r, const Eigen::Vector3d& s) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = r.toRotationMatrix() * s.asDiagonal();
  m.topRightCorner<3, 1>() = t;
  return m;
}

}  // namespace

void check_animation_time(const GltfRig& rig, int anim, double t) {
  if (anim < -1 || anim >= static_cast<int>(rig.animations.size()))
    throw Error(rig.file.string() + ": animation " + std::to_string(anim) + " does not exist (the file has " +
                std::to_string(rig.animations.size()) + ")");
  if (!std::isfinite(t)) throw Error(rig.file.string() + ": animation time is not finite");
}

Eigen::VectorXd sample_channel(const GltfChannel& c, double t) {
  const Eigen::Index k = c.times.size();
  const bool rot = c.path == GltfPath::Rotation;
  const bool cubic = c.interpolation == GltfInterpolation::CubicSpline;
  auto value = [&](Eigen::Index i) -> Eigen::VectorXd {
    return c.values.row(cubic ? 3 * i + 1 : i).transpose();
  };
  auto finish = [&](Eigen::VectorXd v) {
    if (rot) v.normalize();
    return v;
  };
  if (k == 1 || t <= c.times[0]) return finish(value(0));
  if (t >= c.times[k - 1]) return finish(value(k - 1));
  // The key interval [t_i, t_{i+1}) holding t.
  const Eigen::Index i = std::upper_bound(c.times.data(), c.times.data() + k, t) - c.times.data() - 1;
  const double td = c.times[i + 1] - c.times[i], u = (t - c.times[i]) / td;
  switch (c.interpolation) {
    case GltfInterpolation::Step:
      return finish(value(i));
    case GltfInterpolation::Linear:
      if (rot) return slerp_xyzw(value(i), value(i + 1), u);
      return (1.0 - u) * value(i) + u * value(i + 1);
    case GltfInterpolation::CubicSpline: {
      // Hermite spline, Appendix C: p(u) = (2u³−3u²+1) v_i + td (u³−2u²+u) b_i
      //                                  + (−2u³+3u²) v_{i+1} + td (u³−u²) a_{i+1}
      const double u2 = u * u, u3 = u2 * u;
      const Eigen::VectorXd b_i = c.values.row(3 * i + 2).transpose(),
                            a_n = c.values.row(3 * (i + 1)).transpose();
      return finish((2 * u3 - 3 * u2 + 1) * value(i) + td * (u3 - 2 * u2 + u) * b_i +
                    (-2 * u3 + 3 * u2) * value(i + 1) + td * (u3 - u2) * a_n);
    }
  }
  return finish(value(i));
}

double gltf_frame_time(const GltfAnimation& anim, int f, int n) {
  if (n <= 1) return anim.start;
  return anim.start + (anim.end - anim.start) * static_cast<double>(f) / static_cast<double>(n - 1);
}

std::vector<Eigen::Matrix4d> node_local_matrices(const GltfRig& rig, int anim, double t) {
  check_animation_time(rig, anim, t);
  const size_t N = rig.nodes.size();
  std::vector<Eigen::Vector3d> T(N), S(N);
  std::vector<Eigen::Quaterniond> R(N);
  for (size_t i = 0; i < N; ++i)
    T[i] = rig.nodes[i].translation, R[i] = rig.nodes[i].rotation, S[i] = rig.nodes[i].scale;
  if (anim >= 0)
    for (const GltfChannel& c : rig.animations[anim].channels) {
      if (c.path == GltfPath::Weights) continue;
      const Eigen::VectorXd v = sample_channel(c, t);
      if (c.path == GltfPath::Translation) T[c.node] = v.head<3>();
      if (c.path == GltfPath::Rotation) R[c.node] = Eigen::Quaterniond(v[3], v[0], v[1], v[2]);
      if (c.path == GltfPath::Scale) S[c.node] = v.head<3>();
    }
  std::vector<Eigen::Matrix4d> out(N);
  for (size_t i = 0; i < N; ++i)
    out[i] = rig.nodes[i].has_matrix ? rig.nodes[i].matrix : trs_matrix(T[i], R[i], S[i]);
  return out;
}

std::vector<Eigen::Matrix4d> node_world_matrices(const GltfRig& rig, int anim, double t) {
  const std::vector<Eigen::Matrix4d> local = node_local_matrices(rig, anim, t);
  const size_t N = rig.nodes.size();
  std::vector<Eigen::Matrix4d> world(N);
  std::vector<char> done(N, 0);
  std::vector<int> chain;
  for (size_t i = 0; i < N; ++i) {
    chain.clear();
    for (int p = static_cast<int>(i); p >= 0 && !done[p]; p = rig.nodes[p].parent) chain.push_back(p);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const int p = rig.nodes[*it].parent;
      world[*it] = p < 0 ? local[*it] : Eigen::Matrix4d(world[p] * local[*it]);
      done[*it] = 1;
    }
  }
  return world;
}

std::vector<Eigen::VectorXd> morph_weights(const GltfRig& rig, int anim, double t) {
  check_animation_time(rig, anim, t);
  std::vector<Eigen::VectorXd> out;
  out.reserve(rig.pieces.size());
  for (const GltfPiece& p : rig.pieces) out.push_back(p.default_weights);
  if (anim < 0) return out;
  for (const GltfChannel& c : rig.animations[anim].channels) {
    if (c.path != GltfPath::Weights) continue;
    for (size_t p = 0; p < rig.pieces.size(); ++p)
      if (rig.pieces[p].node == c.node) out[p] = sample_channel(c, t);
  }
  return out;
}

}  // namespace spinmotor
