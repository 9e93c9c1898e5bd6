// Rig -> SkinDeformer input (see rig_skin.hpp).
#include "spinmotor/deform/rig_skin.hpp"

#include <cmath>
#include <set>
#include <sstream>

#include "spinmotor/core/error.hpp"

namespace spinmotor {

RigSkin rig_skin(const GltfRig& rig) {
  const int J = static_cast<int>(rig.num_joints());
  const std::vector<ScaledMotor> frames = joint_rest_frames(rig);
  RigSkin out;
  out.bones.resize(J);
  std::set<std::string> used;
  for (int j = 0; j < J; ++j) {
    std::string name = rig.joint_names[j];
    if (name.empty() || used.count(name)) name.append(1, '#').append(std::to_string(j));
    used.insert(name);
    out.bones[j].name = name;
    out.bones[j].parent = rig.joint_parents[j];
    out.bones[j].head = ga::translation(frames[j].motor);
  }
  const Eigen::MatrixXd& V = rig.mesh.V;
  const double diag = V.rows() > 0 ? (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm() : 1.0;
  const double tiny = 1e-9 * std::max(diag, 1e-300);
  std::vector<double> length(J, 0.0);
  // Tails from the first child joint, in joint order; leaves afterwards (they need their parent's length).
  for (int j = 0; j < J; ++j)
    for (int c = 0; c < J; ++c)
      if (rig.joint_parents[c] == j && (out.bones[c].head - out.bones[j].head).norm() > tiny) {
        out.bones[j].tail = out.bones[c].head;
        length[j] = (out.bones[c].head - out.bones[j].head).norm();
        break;
      }
  for (int j = 0; j < J; ++j) {
    if (length[j] > 0.0) continue;
    const int p = rig.joint_parents[j];
    const double l = p >= 0 && length[p] > 0.0 ? length[p] : 0.1 * (diag > 0.0 ? diag : 1.0);
    const Eigen::Vector3d y = ga::to_isometry(frames[j].motor).linear().col(1);
    out.bones[j].tail = out.bones[j].head + l * y;
  }
  check_skeleton(out.bones);
  out.weights = rig.weights;
  return out;
}

std::vector<ga::Mot> rig_pose_motors(const GltfRig& rig, int anim, double t, double tolerance) {
  const std::vector<Eigen::Matrix4d> S = skinning_matrices(rig, anim, t);
  std::vector<ga::Mot> out;
  out.reserve(S.size());
  for (size_t j = 0; j < S.size(); ++j) {
    std::ostringstream what;
    what << rig.file.string() << ": joint '" << rig.joint_names[j] << "' skinning transform at t = " << t;
    const ScaledMotor s = scaled_motor(S[j], what.str(), tolerance);
    if (std::abs(s.scale - 1.0) > tolerance) {
      what << " scales by " << s.scale
           << ": SkinDeformer blends rigid motions (use skin_positions for scaling rigs)";
      throw Error(what.str());
    }
    out.push_back(s.motor);
  }
  return out;
}

SkinDeformer bind_rig(const GltfRig& rig, SkinDeformer::Blend blend) {
  const RigSkin skin = rig_skin(rig);
  SkinDeformer::Options opt;
  opt.blend = blend;
  return SkinDeformer::bind(rig.mesh, skin.bones, skin.weights, opt);
}

}  // namespace spinmotor
