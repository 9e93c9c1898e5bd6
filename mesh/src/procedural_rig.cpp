// The procedural rigged limb (procedural_rig.hpp).
#include "spinmotor/mesh/procedural_rig.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace spinmotor {

namespace {

/// Rotation keys 0 → angle → 0 about `axis` at 0, d/2, d (x y z w rows).
GltfChannel rotation_channel(int node, const Eigen::Vector3d& axis, double degrees, double duration) {
  GltfChannel c;
  c.node = node;
  c.path = GltfPath::Rotation;
  c.interpolation = GltfInterpolation::Linear;
  c.times.resize(3);
  c.times << 0.0, duration / 2, duration;
  c.values.resize(3, 4);
  for (int k = 0; k < 3; ++k) {
    const double a = (k == 1 ? degrees : 0.0) * std::numbers::pi / 180.0;
    const Eigen::Quaterniond q(Eigen::AngleAxisd(a, axis));
    c.values.row(k) << q.x(), q.y(), q.z(), q.w();
  }
  return c;
}

}  // namespace

GltfRig limb_rig(const LimbRigOptions& o) {
  auto bad = [](const std::string& what) { return Error("limb_rig: " + what); };
  if (!(o.radius > 0) || !std::isfinite(o.radius)) throw bad("radius must be positive");
  if (!(o.length > 0) || !std::isfinite(o.length)) throw bad("length must be positive");
  if (o.joints < 2) throw bad("joints must be at least 2");
  if (!(o.blend > 0 && o.blend <= 1)) throw bad("blend must lie in (0, 1]");
  if (!(std::abs(o.bend_degrees) < 180) || !(std::abs(o.twist_degrees) < 180))
    throw bad("bend_degrees and twist_degrees must lie in (−180, 180)");
  if (!(o.duration > 0) || !std::isfinite(o.duration)) throw bad("duration must be positive");

  GltfRig rig;
  rig.mesh = capsule(o.radius, o.length, o.rings, o.sides);
  rig.mesh_name = "limb";
  const Eigen::Index n = rig.mesh.V.rows();
  rig.file_vertices = n;
  rig.file_to_surface = Eigen::VectorXi::LinSpaced(n, 0, static_cast<int>(n - 1));

  const int J = o.joints;
  const double s = o.length / J, h = o.blend * s / 2;
  // Nodes 0..J−1: the joint chain; node J: the mesh node (a root).
  rig.nodes.resize(J + 1);
  for (int k = 0; k < J; ++k) {
    GltfNode& g = rig.nodes[k];
    g.name = "joint" + std::to_string(k);
    g.parent = k - 1;
    if (k > 0) g.translation = Eigen::Vector3d(0, 0, s);
    rig.joint_nodes.push_back(k);
    rig.joint_names.push_back(g.name);
    rig.joint_parents.push_back(k - 1);
    ScaledMotor local;
    if (k > 0) local.motor = ga::translator(Eigen::Vector3d(0, 0, s));
    rig.joint_rest_local.push_back(local);
    Eigen::Matrix4d ibm = Eigen::Matrix4d::Identity();
    ibm(2, 3) = -k * s;
    rig.inverse_bind.push_back(ibm);
  }
  rig.nodes[J].name = "limb";
  rig.mesh_node = J;

  std::vector<Eigen::Triplet<double>> w;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double z = rig.mesh.V(i, 2);
    const int seg = std::clamp(static_cast<int>(std::floor(z / s)), 0, J - 1);
    // The inner joint whose band holds z, if any (bands do not overlap for blend ≤ 1).
    int joint = -1;
    for (int k = 1; k < J; ++k)
      if (std::abs(z - k * s) < h) joint = k;
    if (joint < 0) {
      w.emplace_back(static_cast<int>(i), seg, 1.0);
      continue;
    }
    const double u = std::clamp((z - joint * s + h) / (2 * h), 0.0, 1.0), a = u * u * (3 - 2 * u);
    if (a > 0) w.emplace_back(static_cast<int>(i), joint, a);
    if (a < 1) w.emplace_back(static_cast<int>(i), joint - 1, 1 - a);
  }
  rig.weights.resize(n, J);
  rig.weights.setFromTriplets(w.begin(), w.end());

  GltfAnimation bend{"bend", 0.0, o.duration, {}}, twist{"twist", 0.0, o.duration, {}};
  for (int k = 1; k < J; ++k)
    bend.channels.push_back(rotation_channel(k, Eigen::Vector3d::UnitX(), o.bend_degrees, o.duration));
  twist.channels.push_back(rotation_channel(J - 1, Eigen::Vector3d::UnitZ(), o.twist_degrees, o.duration));
  rig.animations = {bend, twist};
  return rig;
}

}  // namespace spinmotor
