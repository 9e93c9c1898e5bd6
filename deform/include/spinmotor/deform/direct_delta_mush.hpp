#pragma once
// DirectDeltaMushDeformer: Direct Delta Mush, variant 0 (Le & Lewis, "Direct Delta Mush Skinning and
// Variants", ACM TOG 38(4), SIGGRAPH 2019): the closed form of Delta Mush as a skinning method, the
// full per-vertex rigid transform fitted to the smoothed, bone-weighted rest neighbourhood. A
// baseline for spinmotor's conformal clean-up. Follows the bind/pose contract of deformer.hpp; the
// controls are the bones, exactly as for SkinDeformer (same skeleton, weights and frames).
//
// Equations (variant 0 of the paper: the derivation of Direct Delta Mush from Delta Mush, §4 as far as
// memory serves, and the list of variants after it; implemented from memory of the published
// equations, since the paper is not in shared/papers, so no equation numbers are quoted):
//   smoothing   Ψ = ((I + τ L)⁻¹)^p  with the uniform (random-walk) Laplacian L = I − D⁻¹A (A the
//               vertex adjacency, D the valences). Each factor is applied as a solve with the
//               symmetric positive definite matrix (1+τ) D − τ A:  (I + τL) x = b ⇔ ((1+τ)D − τA) x = D b,
//               one sparse Cholesky factorization (CholeskySolver), no dense inverse. Uniform, not
//               cotangent, on purpose: (1+τ)D − τA is a diagonally dominant M-matrix, so Ψ ≥ 0
//               entrywise and its rows sum to 1, which makes every Ω below positive semi-definite, so
//               the rest pose's M (below) is a symmetric PSD covariance whose polar factor is I: the
//               rest mesh comes back to rounding. The cotangent Laplacian has positive off-diagonal
//               entries at obtuse angles, Ψ can then have negative entries, M can be indefinite and
//               its polar factor can flip.
//   bind        per vertex i and bone j the symmetric 4×4
//                 Ω_ij = Σ_k Ψ_ik w_kj [u_k − u_i; 1][u_k − u_i; 1]ᵀ     (10 numbers)
//               computed as 10·B columns Ψ (w_j ∘ [1, y, y yᵀ]) of smoothed moments (y = coordinates
//               about the mesh's bounding-box centre, then shifted to u_i). The paper writes Ω with
//               [u_k; 1]; taking the moments about u_i is the same fit (below) with the translations
//               kept small, so that nothing cancels at the scale of the mesh's position. Pairs (i, j)
//               whose mass Σ_k Ψ_ik w_kj is ≤ prune are dropped (Ψ's rows sum to 1, so the masses of a
//               vertex sum to 1).
//   pose        with M_j = [R_j | t_j] the bone motions K_j = F_j ~F_j^0 (as SkinDeformer):
//                 Q_i = Σ_j M_j Ω_ij = [[Q3, q], [pᵀ, s]],  p̄ = p/s,  q̄ = q/s,
//                 M = Q3/s − q̄ p̄ᵀ,  R = the rotation of M's polar decomposition (a proper rotation
//                 also when det M < 0: SVD M = U Σ Vᵀ, R = U diag(1, 1, det(U Vᵀ)) Vᵀ),
//                 t = q̄ − R p̄,  u'_i = R·0 + t = q̄ − R p̄   (u_i is the origin of Ω_ij's coordinates).
//               The paper's u'_i = R u_i + t is this in world coordinates. With c_j = M_j u_i (vertex i
//               moved by bone j), c_ref the c_j of the vertex's first kept pair and δ_j = c_j − c_ref,
//                 q̄ = c_ref + (Σ R_j m_j + Σ δ_j s_j)/s,
//                 M = Σ R_j S_j/s + Σ δ_j m_jᵀ/s − (q̄ − c_ref) p̄ᵀ,
//               algebraically Q3/s − q̄ p̄ᵀ, but without the product of two large terms: one common
//               motion of all bones gives δ = 0 exactly.
// With p = 0 iterations Ψ = I, p̄ = 0 and the result is LBS.
//
// pose(): B bone matrices, then per vertex its kept pairs (≈ the bones within the smoothing's reach),
// one closest-rotation fit (ga::closest_rotation, Horn's method); parallel over vertices (OpenMP, from
// parallel::kMotorBlend vertices on), no allocation after the first call (tested).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <span>
#include <vector>

#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

class DirectDeltaMushDeformer {
 public:
  struct Options {
    int iterations = 10;  ///< p ≥ 0: the number of implicit smoothing factors
    double tau = 1.0;     ///< τ > 0: the implicit step (τ = λ/(1−λ) damps the mode of eigenvalue 1 as
                          ///< much as one explicit Delta Mush sweep of step λ: τ = 1 ↔ λ = 0.5)
    double prune = 1e-7;  ///< drop (vertex, bone) pairs of mass ≤ prune, in [0, 1)
  };

  DirectDeltaMushDeformer() = default;

  /// Inputs: rest mesh (finite, manifold, every vertex in a face, ≥ 1 face), skeleton and weights as
  /// SkinDeformer::bind (the same ≤ 4 kept, renormalized weights per vertex). Throws Error naming the
  /// bad vertex, edge or bone, or the bad option.
  static DirectDeltaMushDeformer bind(const Mesh& rest, std::span<const Bone> bones,
                                      const Eigen::MatrixXd& weights, const Options& options);
  static DirectDeltaMushDeformer bind(const Mesh& rest, std::span<const Bone> bones,
                                      const Eigen::SparseMatrix<double>& weights, const Options& options);
  /// The deformer shape (deformer.hpp): rig.skeleton and rig.weights (n×B).
  static DirectDeltaMushDeformer bind(const Mesh& rest, const Rig& rig, const Options& options) {
    return bind(rest, rig.skeleton, rig.weights, options);
  }

  /// B posed world frames F_j (unit motors), in bone order. Output: V_out (n×3). Throws Error for a
  /// wrong frame count or a bad frame, naming the bone.
  void pose(std::span<const ga::Mot> frames, Eigen::MatrixXd& V_out);

  Eigen::Index vertices() const { return P_.rows(); }
  /// One control per bone (its name, anchored at its rest head), as SkinDeformer.
  const std::vector<Control>& controls() const { return controls_; }
  /// Number of kept (vertex, bone) pairs (the storage: 10 doubles each).
  Eigen::Index pairs() const { return static_cast<Eigen::Index>(omega_.size()); }
  /// Ω_ij of a kept pair as the full 4×4 matrix (coordinates about u_i), zero when (i, j) was dropped.
  Eigen::Matrix4d omega(Eigen::Index i, int j) const;
  /// The kept skinning weights (n×B, ≤ 4 per row, rows sum to 1).
  const Eigen::SparseMatrix<double>& weights() const { return W_; }
  const Options& options() const { return options_; }

 private:
  // Ω_ij packed: s, m (3), S (6: xx, xy, xz, yy, yz, zz), moments about u_i
  using Packed = std::array<double, 10>;
  static DirectDeltaMushDeformer finish(const Mesh& rest, std::span<const Bone> bones,
                                        const SkinDeformer& skin, const Options& options);

  Options options_;
  std::vector<Bone> bones_;
  std::vector<Control> controls_;
  Eigen::MatrixXd P_;                           // rest positions
  Eigen::SparseMatrix<double> W_;               // kept weights
  std::vector<int> offset_;                     // pairs of vertex i: [offset_[i], offset_[i+1])
  std::vector<int> bone_;                       // bone of each pair
  std::vector<Packed> omega_;                   // Ω of each pair
  std::vector<Eigen::Matrix<double, 3, 4>> T_;  // per-pose scratch: bone matrices
};

}  // namespace spinmotor
