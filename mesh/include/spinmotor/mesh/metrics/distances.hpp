#pragma once
// Per-vertex distances between two embeddings of the same vertex set, optionally after the best
// alignment of the deformed positions onto the rest positions, and the similarity fit itself
// (Umeyama 1991, "Least-squares estimation of transformation parameters between two point
// patterns", eqs. 40–42).
#include <Eigen/Core>
#include <string>

#include "spinmotor/core/option_names.hpp"

namespace spinmotor {

/// x ↦ scale · R x + t, R a rotation (det R = +1), scale > 0.
struct Similarity {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  double scale = 1.0;
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  /// Applies the similarity to the rows of P (k×3).
  Eigen::MatrixXd apply(const Eigen::MatrixXd& P) const {
    return ((scale * P * R.transpose()).rowwise() + t.transpose()).eval();
  }
};

/// Inputs: src, dst (k×3, ROW i of src corresponds to row i of dst, k ≥ 1), with_scale.
/// (Named umeyama_fit, not umeyama: Eigen::umeyama takes points as COLUMNS and would be found by
/// argument-dependent lookup for Eigen arguments.)
/// Output: the similarity T minimising Σ_i |T(src_i) − dst_i|² over rotations (never reflections),
/// translations and, if with_scale, uniform scales (else scale = 1: the rigid fit). Umeyama's SVD
/// solution with the sign correction S = diag(1, 1, det(U)det(V)) (eq. 43).
/// Throws Error on mismatched sizes, no points, non-finite coordinates, or with_scale on a source
/// whose points all coincide.
Similarity umeyama_fit(const Eigen::MatrixXd& src, const Eigen::MatrixXd& dst, bool with_scale = true);

/// Which transformation to factor out before measuring distances.
enum class Alignment {
  None,         ///< compare positions as they are
  Translation,  ///< remove the best translation (match the centroids)
  Rigid,        ///< best rotation + translation (Umeyama without scale)
  Similarity,   ///< best rotation + uniform scale + translation (Umeyama)
};

inline constexpr OptionNames<Alignment, 4> kAlignmentNames{"alignment",
                                                           {{{Alignment::None, "none"},
                                                             {Alignment::Translation, "translation"},
                                                             {Alignment::Rigid, "rigid"},
                                                             {Alignment::Similarity, "similarity"}}}};
constexpr const auto& option_names(Alignment) { return kAlignmentNames; }

/// Per-vertex distances |T(V_def_i) − V_rest_i| after aligning V_def onto V_rest with the chosen T.
struct VertexDistances {
  Eigen::VectorXd d;      ///< n distances, in the units of V_rest
  double diagonal = 0.0;  ///< bounding-box diagonal of V_rest
  double rms = 0.0;       ///< sqrt(mean d²) / diagonal
  double max = 0.0;       ///< max d / diagonal
  Similarity transform;   ///< the T applied to V_def (identity for Alignment::None)
};

/// Inputs: V_rest (n×3), V_def (n×3), alignment. Output: as above. Throws Error on mismatched sizes,
/// no vertices, non-finite coordinates, or a rest bounding box of zero diagonal.
VertexDistances vertex_distances(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V_def,
                                 Alignment alignment = Alignment::None);

}  // namespace spinmotor
