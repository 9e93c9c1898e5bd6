#pragma once
// Skinning a glTF rig (spinmotor/mesh/gltf.hpp) with SkinDeformer (skinning.hpp): every blend of the
// deformer (LBS, Linear = DLB, Log, PivotLog) on a real character and its animation.
//
// The rig's skinning transforms S_j = W_mesh⁻¹ W_j IBM_j move mesh-space rest positions to posed
// positions and are the identity at the bind pose, so the deformer is bound with identity rest frames
// and posed with the motors of S_j directly (skinning.hpp: K_j = F_j ~F_j^0 = F_j). SkinDeformer
// blends rigid motions; a skinning transform that scales (by more than the tolerance) is an error
// naming the joint — skin_positions() in gltf.hpp evaluates such rigs with matrices.
//
// Accuracy: the file's matrices are float32, and exporters leave |LᵀL − I| of order 1e-6 in the
// inverse bind matrices (RiggedFigure: 2.8e-6); the motors are the nearest rigid motions, so LBS here
// differs from the matrix formula by that relative amount (measured in tests/test_gltf.cpp).
#include <Eigen/SparseCore>
#include <vector>

#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor {

/// A rig as SkinDeformer input.
struct RigSkin {
  /// J bones in the skin's joint order: unique names (the joint names; empty or repeated names get
  /// "#<j>" appended), parent = rig.joint_parents, identity rest frames, head = the joint's rest origin
  /// in mesh space, tail = the first child joint's head (or, for a leaf or a child at the same point,
  /// head + the joint's local y axis × its parent's bone length, else 10% of the mesh's bounding-box
  /// diagonal).
  std::vector<Bone> bones;
  /// n×J, rig.weights. SkinDeformer keeps the 4 largest weights of a vertex (renormalised), so a rig
  /// with more influences (JOINTS_1) is skinned with those four; skin_positions() uses all of them.
  Eigen::SparseMatrix<double> weights;
};

/// The bones and weights of a rig. Throws Error if the skeleton fails check_skeleton.
RigSkin rig_skin(const GltfRig& rig);

/// The pose motors (unit motors of the skinning transforms S_j) at time t of animation `anim` (−1: the
/// rest pose). Throws Error naming the joint when S_j is not rigid within `tolerance` (scale |s − 1|,
/// or |LᵀL/s² − I|).
std::vector<ga::Mot> rig_pose_motors(const GltfRig& rig, int anim, double t,
                                     double tolerance = kGltfScaleTolerance);

/// SkinDeformer::bind on the rig's rest mesh, bones and weights with the given blend.
SkinDeformer bind_rig(const GltfRig& rig, SkinDeformer::Blend blend);

}  // namespace spinmotor
