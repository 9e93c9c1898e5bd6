#pragma once
// SkinDeformer: skinning of a rigged mesh — a skeleton of bones, per-vertex bone weights (at most 4
// per vertex kept), and a blend of the bones' motions. Follows the bind/pose contract of deformer.hpp;
// the controls are the bones.
//
// Skeleton: bones with a parent (−1 for a root; no cycles), a rest segment head → tail (used for the
//   harmonic weights and by the scene's pose inheritance) and a rest frame motor (default identity).
//   pose() takes the posed world frames F_j; bone j moves the rest mesh by K_j = F_j ~F_j^0 (so with
//   identity rest frames, F_j is directly the world-space motion of the bone, and identities give the
//   rest mesh).
// Weights (n×B, row i = the weights of vertex i): given (dense, sparse or read_skin_weights()), or
//   computed by bone_harmonic_weights(). bind keeps the Options::max_influences largest non-zero weights
//   of each row (ties: the lower bone index first; 4 by default, 0 = all; Log and PivotLog keep at most
//   4) and renormalizes them to sum 1.
// Blends of the ≤ 4 motions K_j of a vertex, weights w_j (slot 0 holds the largest weight: the pivot):
//   LBS       p' = (Σ w_j T_j) p with T_j the 3×4 matrix of K_j (linear blend skinning; collapses under
//             twist, the "candy wrapper").
//   DLB       dual-quaternion linear blending (Kavan et al. 2008): normalize(Σ s_j w_j K_j), s_j = sign <K_j
//   ~K_pivot>_0. Log       exp(Σ w_j log K_j) (CGA paper eq. 1). PivotLog  exp(Σ w_j log(K_j ~K_pivot))
//   K_pivot.
// pose(): per frame B matrices (LBS), B logs (Log), B² signs (DLB) or B² relative logs (PivotLog);
//   then per vertex its weighted terms, one normalization / exponential and one point transform, parallel
//   over vertices, no allocation.
// Affine bone transforms (pose_affine, for rigs whose joints scale: glTF's joint matrices). LBS blends
//   the 3×4 matrices A_j as they are. The motor blends split each A_j = M_j ∘ S_j into a stretch S_j
//   about the bone's rest head c_j, x ↦ c_j + P_j (x − c_j) with P_j the symmetric positive definite
//   factor of the polar decomposition L_j = R_j P_j of A_j's linear part, and the rigid motion
//   M_j: x ↦ R_j x + t_j + (L_j − R_j) c_j; the stretches are blended linearly, then the rigid motions
//   by the blend (Kavan et al. 2008, "Geometric skinning with approximate dual quaternion blending",
//   the two-phase skinning of scale and shear). Rigid A_j (P_j = I to 1e-9) skip the first phase, so a
//   rigid rig gives what pose() gives. For the motor blends an A_j with det ≤ 0 (a mirror or a
//   collapse) is an error naming the bone; LBS takes any finite A_j.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "spinmotor/deform/deformer.hpp"
#include "spinmotor/deform/harmonic_field.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

/// The world motions of all bones from those given: given[j] is used when has[j], otherwise bone j
/// keeps its parent's motion (a root with no entry: identity). Sizes B. Throws for a bad skeleton.
std::vector<ga::Mot> inherit_bone_motions(std::span<const Bone> bones, std::span<const ga::Mot> given,
                                          const std::vector<bool>& has);

/// Bone weights as surface harmonic coordinates of bone regions: vertex i belongs to the region of
/// its nearest bone segment j, unless its closest point on that segment lies within joint_fraction ×
/// the bone's length of a joint shared with another bone (the band around a joint is left free).
/// Output: n×B harmonic_coordinates(V, F, regions, weights) (a partition of unity, ≥ 0 for
/// mean-value weights). Throws Error naming a bone whose region is empty, and as harmonic_coordinates.
Eigen::MatrixXd bone_harmonic_weights(const Mesh& mesh, std::span<const Bone> bones,
                                      double joint_fraction = 0.25,
                                      HarmonicWeights weights = HarmonicWeights::MeanValue);

/// Skin weight text file (UTF-8, one record per line; '#' starts a comment; blank lines skipped):
///   bones <name_1> <name_2> ... <name_B>     first record: the bone names, in the file's column order
///   <w_1> <w_2> ... <w_B>                   then one line per vertex, in vertex order: B weights ≥ 0,
///                                           not all zero (normalized by the deformer)
/// Output: n×B weights with columns in the order of `bones` (the skeleton's order; the file must name
/// each skeleton bone exactly once). Throws Error "path:line: ..." for a missing or unknown bone name, a
/// repeated name, a wrong number of values on a line, a value that is not a number, negative or not
/// finite, an all-zero row, and "path: ..." for a file that cannot be read or has a vertex count ≠ n.
Eigen::MatrixXd read_skin_weights(const std::filesystem::path& path, std::span<const Bone> bones,
                                  Eigen::Index n);

/// The skinning blends: the motor blends of ga::Blend (same order) and linear blend skinning.
enum class SkinBlend { Log, PivotLog, DLB, LBS };
inline constexpr OptionNames<SkinBlend, 4> kSkinBlendNames{"blend",
                                                           {{{SkinBlend::LBS, "lbs"},
                                                             {SkinBlend::DLB, "dlb"},
                                                             {SkinBlend::Log, "log"},
                                                             {SkinBlend::PivotLog, "pivot-log"}}}};
constexpr const auto& option_names(SkinBlend) { return kSkinBlendNames; }

class SkinDeformer {
 public:
  using Blend = SkinBlend;

  struct Options {
    Blend blend = Blend::DLB;
    /// Influences kept per vertex (the largest; 0 = all). Log and PivotLog keep at most 4.
    int max_influences = 4;
  };
  using Affine = Eigen::Matrix<double, 3, 4>;

  SkinDeformer() = default;

  /// Inputs: rest mesh (V read), skeleton (check_skeleton), weights n×B (finite, ≥ 0, every row with a
  /// positive entry). Throws Error naming the bad vertex or bone.
  static SkinDeformer bind(const Mesh& rest, std::span<const Bone> bones, const Eigen::MatrixXd& weights,
                           const Options& options);
  static SkinDeformer bind(const Mesh& rest, std::span<const Bone> bones,
                           const Eigen::SparseMatrix<double>& weights, const Options& options);
  /// The deformer shape (deformer.hpp): rig.skeleton and rig.weights (n×B).
  static SkinDeformer bind(const Mesh& rest, const Rig& rig, const Options& options) {
    return bind(rest, rig.skeleton, rig.weights, options);
  }

  /// B posed world frames F_j (unit motors), in bone order. Output: V_out (n×3).
  void pose(std::span<const ga::Mot> frames, Eigen::MatrixXd& V_out);
  /// B affine bone transforms A_j (3×4, world to world, identity = rest; see the header comment) applied
  /// to `points` (n×3; null: the rest positions, e.g. the rest with morph targets applied). Output:
  /// V_out (n×3). Throws Error naming the bone for a non-finite transform, or det ≤ 0 (motor blends).
  void pose_affine(std::span<const Affine> transforms, const Eigen::MatrixXd* points, Eigen::MatrixXd& V_out);

  Eigen::Index vertices() const { return P_.rows(); }
  /// One control per bone (its name, anchored at its rest head): the posed world frames.
  const std::vector<Control>& controls() const { return controls_; }
  /// The kept weights as an n×B sparse matrix (≤ max_influences per row, rows sum to 1).
  Eigen::SparseMatrix<double> weights() const;
  /// The motor of vertex i for the given frames (DLB / Log / PivotLog: ga::blend reference path).
  ga::Mot vertex_motor(Eigen::Index i, std::span<const ga::Mot> frames) const;
  const Options& options() const { return options_; }

 private:
  struct Influence {
    std::array<int, 4> bone{0, 0, 0, 0};
    std::array<double, 4> w{0, 0, 0, 0};  // descending; unused slots 0
  };
  static SkinDeformer bind_rows(const Mesh& rest, std::span<const Bone> bones,
                                std::vector<std::vector<std::pair<int, double>>> rows,
                                const Options& options);
  void prepare(std::span<const ga::Mot> frames);
  void prepare_blend();  // from motions_: the blend's per-bone terms
  void blend_lbs(const Eigen::MatrixXd& P, const Eigen::Matrix<double, 3, 4>* T,
                 Eigen::MatrixXd& V_out) const;
  void blend_motors(const Eigen::MatrixXd& P, Eigen::MatrixXd& V_out) const;

  Options options_;
  std::vector<Control> controls_;
  std::vector<Bone> bones_;
  Eigen::MatrixXd P_;
  std::vector<Influence> inf_;  // the 4 largest (Log, PivotLog, the DLB pivot, vertex_motor)
  // Every kept influence (CSR by vertex): weights().
  std::vector<std::size_t> kept_begin_;
  std::vector<std::pair<int, double>> kept_;
  // By blocks of kLbsBlock consecutive vertices (LBS, DLB and the stretch phase of pose_affine, over the
  // kept influences): the bones that weigh on block k are
  // lbs_bones_[lbs_begin_[k] .. lbs_begin_[k+1]), and entry e holds those vertices' weights for bone
  // lbs_bones_[e] at lbs_w_[e·kLbsBlock ...] (0 where a vertex has no influence of that bone). pose()
  // then runs bone by bone over a block, across its vertices: contiguous, vectorised arithmetic with no
  // per-vertex gather (docs/performance.md, "LBS on small meshes").
  static constexpr Eigen::Index kLbsBlock = 128;
  std::vector<int> lbs_bones_;
  std::vector<std::size_t> lbs_begin_;
  std::vector<double> lbs_w_;
  std::vector<int> lbs_pivot_;  // DLB: the pivot bone (largest weight) shared by block k's vertices, or -1
  // per-pose scratch
  std::vector<ga::Mot> motions_;                       // K_j
  std::vector<Eigen::Matrix<double, 3, 4>> matrices_;  // LBS
  std::vector<ga::Dll> logs_;                          // Log: B; PivotLog: B²
  std::vector<double> signs_;                          // DLB: B²
  std::vector<Eigen::Matrix<double, 3, 4>> stretch_;   // pose_affine: the stretches S_j
  Eigen::MatrixXd stretched_;                          // pose_affine: the points after the stretch phase
};

}  // namespace spinmotor
