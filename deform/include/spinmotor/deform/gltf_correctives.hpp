#pragma once
// Corrective morph targets: a cleaned animation (the pose-keeping cleanup of every frame, or any other
// per-frame result) stored as a few morph targets on the skinned rig, for engines and tools that play only
// skinning and morph targets (three.js, Godot, game engines, Blender's importer).
//
// The engine computes, for vertex i of piece p (glTF 2.0 §3.7.2.2 and §3.7.3.3),
//   x_i(t) = Σ_j w_ij S_j(t) (v_i + Σ_k m_k(t) d_ik + Σ_c c_c(t) D_ic),
// the first sum over the file's own targets, the second over the correctives. For a target pose y_i(f) at
// frame time t_f the rest-frame offset that makes x_i = y_i is δ_i(f) = M_i(f)⁻¹ (y_i(f) − x_i⁰(f)), with
// M_i(f) = Σ_j w_ij L_j(t_f) (L_j the linear part of S_j) and x⁰ the skinning without correctives. Per
// piece, the 3n_p × F matrix of the δ_i(f) is truncated by its singular value decomposition
// Δ ≈ Σ_{c<K} σ_c u_c v_cᵀ: the targets are D_c = σ_c u_c and the weights c_c(t_f) = v_c(f), played
// between frames by a LINEAR weights channel. K is the smallest count whose scene-space error
// max_{i,f} |M_i(f) (δ_i(f) − δ̃_i(f))| is at most max_error × the rest surface's bounding-box diagonal
// (bounded above with |M_i(f)|_F while choosing K, measured exactly for the result), at most
// max_targets. The weights are then mapped into [0, 1] for the same sums (Blender's importer clamps
// shape-key values there): target c becomes (b_c − a_c) D_c with weight (v_c − a_c) / (b_c − a_c), [a_c, b_c]
// the range of v_c over the frames, and one more target Σ_c a_c D_c carries weight 1 on every frame, so a
// piece gets K + 1 targets. A piece whose offsets are all zero (rigid pieces, pieces the cleanup left
// alone) gets no target.
//
// Output: the rig with, per piece, its K_p targets appended ("spinmotor_corrective_NN", default weight 0)
// and one animation: the cleaned animation's joint channels as they are, and per piece with targets a
// weights channel keyed at the frame times holding the file's own morph weights there (sampled) and the
// corrective weights. Other animations are left out (their weights channels would lack the new targets).
#include <Eigen/Core>
#include <vector>

#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor {

struct CorrectiveOptions {
  double max_error = 1e-3;  ///< relative to the rest surface's bounding-box diagonal, > 0
  int max_targets = 64;     ///< per piece, ≥ 1
};

struct CorrectiveRig {
  GltfRig rig;  ///< the rig with the targets and the one animation (write it with write_gltf_rig)
  std::vector<int> targets;  ///< K_p per piece
  double max_error = 0;      ///< achieved scene-space error / diagonal (exact, every vertex and frame)
  double rms_error = 0;      ///< the same as a root mean square over vertices and frames
  bool bound_met = true;     ///< max_error ≤ options.max_error (false: max_targets was reached)
};

/// Inputs: rig, anim (index of the animation the frames sample), times (F strictly increasing),
/// frames (F poses n×3 in scene coordinates, e.g. RigPoser::pose_scene), options. Throws Error for a size
/// mismatch, a non-finite pose, non-increasing times, bad options, an animation out of range, or a vertex
/// whose blended joint matrix M_i(f) is singular.
CorrectiveRig corrective_rig(const GltfRig& rig, int anim, const std::vector<double>& times,
                             const std::vector<Eigen::MatrixXd>& frames,
                             const CorrectiveOptions& options = {});

}  // namespace spinmotor
