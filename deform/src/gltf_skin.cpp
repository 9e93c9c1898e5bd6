// Skinning glTF rigs (gltf_skin.hpp).
#include "spinmotor/deform/gltf_skin.hpp"

#include <Eigen/LU>
#include <cmath>
#include <set>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/gltf_animation.hpp"

namespace spinmotor {

namespace {

Eigen::Matrix4d affine_inverse(const Eigen::Matrix4d& m) {
  Eigen::Matrix4d r = Eigen::Matrix4d::Identity();
  const Eigen::Matrix3d li = m.topLeftCorner<3, 3>().inverse();
  r.topLeftCorner<3, 3>() = li;
  r.topRightCorner<3, 1>() = -li * m.topRightCorner<3, 1>();
  return r;
}

/// The root joint of a skin: its skeleton node when that is one of its joints, else its first joint
/// whose joint parent is not in the skin.
int skin_root(const GltfRig& rig, const GltfSkin& s) {
  for (int e : s.joints)
    if (rig.joint_nodes[e] == s.skeleton) return e;
  for (int e : s.joints) {
    const int p = rig.joint_parents[e];
    if (p < 0 || std::find(s.joints.begin(), s.joints.end(), p) == s.joints.end()) return e;
  }
  return s.joints.front();
}

double diagonal(const Eigen::MatrixXd& V) {
  return V.rows() > 0 ? (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm() : 0.0;
}

}  // namespace

std::vector<Eigen::Matrix4d> joint_matrices(const GltfRig& rig, const std::vector<Eigen::Matrix4d>& world) {
  std::vector<Eigen::Matrix4d> out;
  out.reserve(rig.joint_nodes.size());
  for (size_t j = 0; j < rig.joint_nodes.size(); ++j)
    out.push_back(world[rig.joint_nodes[j]] * rig.inverse_bind[j]);
  return out;
}

GltfBindPose gltf_bind_pose(const GltfRig& rig) {
  const std::vector<Eigen::Matrix4d> S = joint_matrices(rig, node_world_matrices(rig, -1, 0.0));
  GltfBindPose out;
  for (const GltfSkin& s : rig.skins) out.skins.push_back(S[skin_root(rig, s)]);
  // How far each joint's rest matrix is from its skin's: the largest displacement it gives a vertex of
  // the POSITION bounding box, relative to the box's diagonal in the scene.
  const Eigen::Vector3d lo = rig.mesh.V.colwise().minCoeff(), hi = rig.mesh.V.colwise().maxCoeff();
  const double diag =
      std::max((out.skins.empty() ? 1.0 : out.skins[0].topLeftCorner<3, 3>().norm() / std::sqrt(3.0)) *
                   (hi - lo).norm(),
               1e-300);
  for (size_t j = 0; j < rig.joint_nodes.size(); ++j) {
    const Eigen::Matrix4d d = S[j] - out.skins[rig.joint_skins[j]];
    double worst = 0;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d x((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                              (c & 4) ? hi.z() : lo.z());
      worst = std::max(worst, (d.topLeftCorner<3, 3>() * x + d.topRightCorner<3, 1>()).norm() / diag);
    }
    if (worst > out.deviation) out.deviation = worst, out.joint = static_cast<int>(j);
  }
  return out;
}

Eigen::MatrixXd skin_positions(const GltfRig& rig, int anim, double t) {
  const std::vector<Eigen::Matrix4d> S = joint_matrices(rig, node_world_matrices(rig, anim, t));
  const std::vector<Eigen::VectorXd> m = morph_weights(rig, anim, t);
  Eigen::MatrixXd P = rig.mesh.V;
  for (size_t p = 0; p < rig.pieces.size(); ++p)
    for (Eigen::Index k = 0; k < rig.pieces[p].num_targets(); ++k)
      if (m[p][k] != 0.0)
        P.middleRows(rig.pieces[p].first_vertex, rig.pieces[p].vertices) +=
            m[p][k] * rig.pieces[p].targets[k];
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(P.rows(), 3);
  for (int j = 0; j < rig.weights.outerSize(); ++j) {
    const Eigen::Matrix3d l = S[j].topLeftCorner<3, 3>();
    const Eigen::Vector3d tr = S[j].topRightCorner<3, 1>();
    for (Eigen::SparseMatrix<double>::InnerIterator it(rig.weights, j); it; ++it)
      out.row(it.row()) += it.value() * (l * P.row(it.row()).transpose() + tr).transpose();
  }
  return out;
}

RigSkin rig_skin(const GltfRig& rig) {
  const int J = static_cast<int>(rig.num_joints());
  RigSkin out;
  const GltfBindPose bp = gltf_bind_pose(rig);
  out.bind = bp.skins;
  for (size_t s = 0; s < out.bind.size(); ++s) {
    if (!(std::abs(out.bind[s].topLeftCorner<3, 3>().determinant()) > 1e-300) || !out.bind[s].allFinite())
      throw Error(rig.file.string() + ": the bind matrix of skin '" + rig.skins[s].name + "' is singular");
    out.bind_inverse.push_back(affine_inverse(out.bind[s]));
  }
  out.rest = rig.mesh;
  out.targets.resize(rig.pieces.size());
  for (size_t p = 0; p < rig.pieces.size(); ++p) {
    const GltfPiece& piece = rig.pieces[p];
    const Eigen::Matrix4d& B = out.bind[piece.skin];
    const Eigen::Matrix3d L = B.topLeftCorner<3, 3>();
    auto block = out.rest.V.middleRows(piece.first_vertex, piece.vertices);
    for (Eigen::Index k = 0; k < piece.num_targets(); ++k)
      block += piece.default_weights[k] * piece.targets[k];
    block = ((block * L.transpose()).rowwise() + B.topRightCorner<3, 1>().transpose()).eval();
    for (const Eigen::MatrixXd& d : piece.targets) out.targets[p].push_back(d * L.transpose());
  }
  out.rig.skeleton.resize(J);
  std::set<std::string> used;
  std::vector<Eigen::Matrix4d> frame(J);
  for (int j = 0; j < J; ++j) {
    std::string name = rig.joint_names[j];
    if (name.empty() || used.count(name)) name.append(1, '#').append(std::to_string(j));
    used.insert(name);
    out.rig.skeleton[j].name = name;
    out.rig.skeleton[j].parent = rig.joint_parents[j];
    frame[j] =
        out.bind[rig.joint_skins[j]] * affine_inverse(rig.inverse_bind[j]);  // the joint at the bind pose
    out.rig.skeleton[j].head = frame[j].topRightCorner<3, 1>();
  }
  const double diag = diagonal(out.rest.V);
  const double tiny = 1e-9 * std::max(diag, 1e-300);
  std::vector<double> length(J, 0.0);
  // Tails from the first child joint, in joint order; leaves afterwards (they need their parent's length).
  for (int j = 0; j < J; ++j)
    for (int c = 0; c < J; ++c)
      if (rig.joint_parents[c] == j && (out.rig.skeleton[c].head - out.rig.skeleton[j].head).norm() > tiny) {
        out.rig.skeleton[j].tail = out.rig.skeleton[c].head;
        length[j] = (out.rig.skeleton[c].head - out.rig.skeleton[j].head).norm();
        break;
      }
  for (int j = 0; j < J; ++j) {
    if (length[j] > 0.0) continue;
    const int p = rig.joint_parents[j];
    const double l = p >= 0 && length[p] > 0.0 ? length[p] : 0.1 * (diag > 0.0 ? diag : 1.0);
    Eigen::Vector3d y = frame[j].block<3, 1>(0, 1);
    y = y.norm() > 0 ? Eigen::Vector3d(y.normalized()) : Eigen::Vector3d::UnitY();
    out.rig.skeleton[j].tail = out.rig.skeleton[j].head + l * y;
  }
  check_skeleton(out.rig.skeleton);
  out.rig.weights = rig.weights;
  return out;
}

std::vector<SkinDeformer::Affine> rig_joint_transforms(const GltfRig& rig, const RigSkin& skin, int anim,
                                                       double t) {
  const std::vector<Eigen::Matrix4d> S = joint_matrices(rig, node_world_matrices(rig, anim, t));
  std::vector<SkinDeformer::Affine> out(S.size());
  for (size_t j = 0; j < S.size(); ++j) out[j] = (S[j] * skin.bind_inverse[rig.joint_skins[j]]).topRows<3>();
  return out;
}

bool morphed_rest(const GltfRig& rig, const RigSkin& skin, const std::vector<Eigen::VectorXd>& weights,
                  Eigen::MatrixXd& out) {
  bool changed = false;
  for (size_t p = 0; p < rig.pieces.size() && !changed; ++p)
    changed = weights[p].size() == rig.pieces[p].default_weights.size() &&
              weights[p] != rig.pieces[p].default_weights;
  if (!changed) return false;
  out = skin.rest.V;
  for (size_t p = 0; p < rig.pieces.size(); ++p) {
    const GltfPiece& piece = rig.pieces[p];
    for (Eigen::Index k = 0; k < piece.num_targets(); ++k) {
      const double dw = weights[p][k] - piece.default_weights[k];
      if (dw != 0.0) out.middleRows(piece.first_vertex, piece.vertices) += dw * skin.targets[p][k];
    }
  }
  return true;
}

RigSkinner::RigSkinner(const GltfRig& rig, SkinBlend blend) : rig_(&rig), skin_(rig_skin(rig)) {
  SkinDeformer::Options o;
  o.blend = blend;
  o.max_influences = 0;  // every influence (Log and PivotLog keep 4)
  deformer_ = SkinDeformer::bind(skin_.rest, skin_.rig, o);
}

void RigSkinner::pose(int anim, double t, Eigen::MatrixXd& V_out) {
  const std::vector<SkinDeformer::Affine> T = rig_joint_transforms(*rig_, skin_, anim, t);
  const bool morphed = morphed_rest(*rig_, skin_, morph_weights(*rig_, anim, t), morphed_);
  try {
    deformer_.pose_affine(T, morphed ? &morphed_ : nullptr, V_out);
  } catch (const Error& e) {
    std::ostringstream s;
    s << rig_->file.string() << ": " << (anim >= 0 ? rig_->animations[anim].name : std::string("rest pose"))
      << " at t = " << t << ": " << e.what();
    throw Error(s.str(), e.kind());
  }
}

}  // namespace spinmotor
