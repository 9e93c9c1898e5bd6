#pragma once
// Skinning a glTF rig (mesh/gltf.hpp) as the glTF 2.0 specification defines it (§3.7.3 "Skins"): joint
// matrices S_j = W_j · IBM_j (W_j the joint node's global matrix, IBM_j its inverse bind matrix), applied to
// the POSITION data after the morph targets (§3.7.2.2), in scene coordinates; the skinned node's own
// transform is ignored. Everything here is in scene coordinates (glTF's world: +Y up for files that
// follow the spec's convention), so a character sits and moves as glTF viewers and Blender show it.
//
// Bind space. The POSITION data of a skin's pieces live in the skin's bind space, which the inverse bind
// matrices map into each joint's space; B_s, the bind matrix of skin s, maps it into the scene at the
// bind pose: B_s = S_j(rest) of the skin's root joint (the skeleton node when it is a joint, else its
// first joint without a joint parent). For every exporter tried the S_j(rest) of all joints agree (the
// file's rest pose is its bind pose); gltf_bind_pose reports how far they do not.
// The rest surface (RigSkin::rest) of piece p is B_s(p) (POSITION + Σ_k m_k d_k) with the default morph
// weights m_k, and the pose transform of joint j (world to world, identity at the bind pose) is
//   T_j(t) = S_j(t) B_s(j)⁻¹,
// so that Σ_j w_ij T_j(t) rest_i is the specification's Σ_j w_ij S_j(t) v_i at the default morph weights.
// T_j is affine: it scales where the file animates a scale or scales a node between the joints; the
// motor blends take such transforms apart (skinning.hpp, pose_affine).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor {

/// S_j = W_j · IBM_j for every joint, at the node global matrices `world` (node_world_matrices).
std::vector<Eigen::Matrix4d> joint_matrices(const GltfRig& rig, const std::vector<Eigen::Matrix4d>& world);

/// The bind matrices of the skins (see the header comment).
struct GltfBindPose {
  std::vector<Eigen::Matrix4d> skins;  ///< B_s per skin
  /// max over joints of |S_j(rest) − B_s| (largest entry of the difference applied to the rest surface,
  /// relative to its bounding-box diagonal): 0 when the rest pose is the bind pose.
  double deviation = 0;
  int joint = -1;  ///< the joint of the largest deviation (−1 when none)
};
GltfBindPose gltf_bind_pose(const GltfRig& rig);

/// The specification's skinning (§3.7.3.3) with 4×4 matrices and every influence: row i =
/// Σ_j w_ij S_j(t) (v_i + Σ_k m_k(t) d_k,i) in scene coordinates (n×3), anim −1 the rest pose.
/// Errors as node_world_matrices.
Eigen::MatrixXd skin_positions(const GltfRig& rig, int anim, double t);

/// A glTF rig as SkinDeformer input, in scene coordinates.
struct RigSkin {
  /// The rest surface (header comment): positions in scene coordinates, rig.mesh's faces and UVs.
  Mesh rest;
  /// What the skin deformers bind to (deformer.hpp): rig.skeleton, J bones in the joints' order with
  /// unique names (empty or repeated names get "#<j>" appended), parent = the file's joint_parents,
  /// identity rest frames, head = the joint's origin at the bind pose (B_s IBM_j⁻¹), tail = the first
  /// child joint's head (or, for a leaf or a child at the same point, head + the joint's y axis × its
  /// parent's bone length, else 10% of the rest surface's diagonal); rig.weights n×J, the file's.
  Rig rig;
  std::vector<Eigen::Matrix4d> bind;  ///< B_s per skin
  std::vector<Eigen::Matrix4d> bind_inverse;
  /// Per piece, its morph targets in scene coordinates (B_s's linear part applied): T_p fields of
  /// the piece's vertices × 3.
  std::vector<std::vector<Eigen::MatrixXd>> targets;
};

/// The bones, weights, bind matrices and rest surface of a rig. Throws Error if the skeleton fails
/// check_skeleton or a bind matrix is singular.
RigSkin rig_skin(const GltfRig& rig);

/// The pose transforms T_j (3×4, world to world) at time t of animation `anim` (−1: the rest pose).
std::vector<SkinDeformer::Affine> rig_joint_transforms(const GltfRig& rig, const RigSkin& skin, int anim,
                                                       double t);

/// The rest surface with the morph weights `weights` (morph_weights) instead of the defaults: n×3 into
/// `out`. Returns false (out untouched) when every piece's weights equal its defaults.
bool morphed_rest(const GltfRig& rig, const RigSkin& skin, const std::vector<Eigen::VectorXd>& weights,
                  Eigen::MatrixXd& out);

/// A rig bound to a SkinDeformer with one blend: pose(anim, t) gives the skinned surface in scene
/// coordinates (morph targets, then skinning). LBS and DLB use every influence of the file (LBS is then the
/// specification's formula); Log and PivotLog the 4 largest. The rig must outlive the skinner.
class RigSkinner {
 public:
  RigSkinner(const GltfRig& rig, SkinBlend blend);
  /// V_out (n×3) at time t of animation anim (−1: rest pose). Errors as node_world_matrices and
  /// SkinDeformer::pose_affine.
  void pose(int anim, double t, Eigen::MatrixXd& V_out);
  const RigSkin& skin() const { return skin_; }
  const SkinDeformer& deformer() const { return deformer_; }
  const GltfRig& rig() const { return *rig_; }

 private:
  const GltfRig* rig_;
  RigSkin skin_;
  SkinDeformer deformer_;
  Eigen::MatrixXd morphed_;
};

}  // namespace spinmotor
