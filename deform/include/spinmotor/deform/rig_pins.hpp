#pragma once
// Pins for the pose-keeping cleanup of a skinned pose (spin/pinned_cleanup.hpp): the vertices that one
// bone moves rigidly and that lie far enough from every blended vertex.
//
// Definitions (W is n×B, row i = the bone weights of vertex i, normalised here by the row sum):
//   dominant weight  w*(i) = max_j W(i,j) / Σ_j W(i,j);
//   blended vertex   w*(i) < threshold (more than one bone moves it noticeably: the skinning
//                    artefacts — candy wrapper, elbow collapse — live there);
//   pin              w*(i) ≥ threshold and |v_i − v_k| > margin for every blended vertex k.
// The margin leaves a ring of rigid vertices free around each blend band, so that the cleanup can
// spread the band's correction instead of creasing at the band's edge.
//
// Joint blend width. The blended vertices are grouped by their joint, the unordered pair {dominant
// bone, second bone} (largest and second largest weight; ties to the lower index). The width of a
// joint is the extent (max − min) of the projections of its blended vertices onto each of the two
// bones' rest axes (tail − head, normalised), the larger of the two: for a limb with a blend band of
// length w around the elbow it is w. default_pin_margin is a quarter of the largest joint width (one
// scalar margin for the whole rig: conservative for small joints, whose free ring is then wider than
// needed).
//
// Cost: O(n) for a surface sampled at about the margin or finer — the blended vertices are bucketed
// in a dense grid (CSR) of cell size margin/2 over the bounding box (coarsened while it would exceed
// max(4n, 2^16) cells); each candidate pin visits the cells within the margin, skipping boxes farther
// than it and accepting a non-empty box entirely within it without looking at its points. Parallel
// over vertices (OpenMP). Measured on the test's 1M-vertex arm (capsule(1, 6, 1200, 840), margin 0.5,
// shared 2-core machine): 0.5 s (the sorted-key grid with 27 cells of size margin it replaced: 2.3 s;
// tests/test_pinned_cleanup.cpp "pins_from_weights at 1M vertices", hidden).
#include <Eigen/Core>
#include <span>
#include <vector>

#include "spinmotor/deform/skinning.hpp"

namespace spinmotor {

/// The dominant weight from which one bone moves a vertex rigidly: the default pin threshold of every
/// rig cleanup (scene/rig_cleanup.hpp, a scene's "pins": "weights", Python, the Blender add-on).
inline constexpr double kRigidWeight = 0.999;
/// The dominant weight at and below which the pose attraction lets a vertex go (the middle of a joint).
inline constexpr double kAttractionLow = 0.5;

/// Inputs: V (n×3 rest positions), W (n×B weights ≥ 0, finite, every row with a positive entry),
/// threshold in (0, 1], margin ≥ 0 (0: no distance test). Output: the pins, increasing. Throws Error
/// naming the bad vertex (row) or parameter.
Eigen::VectorXi pins_from_weights(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W,
                                  double threshold = kRigidWeight, double margin = 0.0);

/// One joint's blend band (see the header comment).
struct JointBlend {
  int bone_a = -1, bone_b = -1;  ///< bone_a < bone_b
  Eigen::Index vertices = 0;     ///< blended vertices of this joint
  double width = 0;              ///< extent along the bones' axes (the larger of the two)
};

/// Inputs: V (n×3), W (n×B), bones (B, their rest head/tail give the axes), threshold as above.
/// Output: the joints with at least one blended vertex, ordered by (bone_a, bone_b). Throws as
/// pins_from_weights, and for bones.size() ≠ B.
std::vector<JointBlend> joint_blend_bands(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W,
                                          std::span<const Bone> bones, double threshold = kRigidWeight);

/// Per-bone margins: a candidate pin dominated by bone b must lie farther than margins[b] from every
/// blended vertex. Inputs as above, margins (B values ≥ 0). Output: the pins, increasing.
Eigen::VectorXi pins_from_weights(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W, double threshold,
                                  const Eigen::VectorXd& margins);

/// Per bone: a quarter of the widest blend band among the joints the bone takes part in (0 for a
/// bone in no joint) — each joint gets room in proportion to its own band, where default_pin_margin
/// gives every joint the room of the widest one (on CesiumMan it pins 50 of the 313 rigid vertices).
Eigen::VectorXd default_pin_margins(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W,
                                    std::span<const Bone> bones, double threshold = kRigidWeight);

/// Per-vertex weights of the cleanup's pose attraction (spin/pinned_cleanup.hpp, bind's `attraction`):
/// a_i = smoothstep(t), t = clamp((w*(i) − low) / (threshold − low), 0, 1) with w* the normalised dominant
/// weight: 1 where one bone moves the vertex rigidly (w* ≥ threshold), 0 where two bones share it
/// equally (w* ≤ low, the middle of a joint, where LBS collapses and the cleanup must be free), smooth
/// between. Inputs: W (n×B, as pins_from_weights), threshold in (0, 1], low in [0, threshold).
/// Output: n values in [0, 1]. Throws Error naming the bad vertex or parameter.
Eigen::VectorXd pin_attraction_from_weights(const Eigen::MatrixXd& W, double threshold = kRigidWeight,
                                            double low = kAttractionLow);

/// A quarter of the largest joint blend width (0 when no vertex is blended).
double default_pin_margin(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W, std::span<const Bone> bones,
                          double threshold = kRigidWeight);

}  // namespace spinmotor
