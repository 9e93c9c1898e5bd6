#pragma once
// Quasi-conformal error Q of a deformation with fixed connectivity (Crane et al. 2011, §6.1).
//
// For each face, let A be the linear map taking the rest triangle (in its own plane) to the deformed
// triangle (in its own plane); Q = σmax(A) / σmin(A) ≥ 1, and Q = 1 exactly when the face undergoes a
// similarity. Both triangles are expressed in orthonormal frames of their own planes, oriented by
// their own normals, so det A > 0 and A is 2×2; Q follows in closed form from A's conformal and
// anticonformal parts (no SVD): with A = [a b; c d],
//   E = ½ |(a + d, c − b)|,  G = ½ |(a − d, c + b)|,  σmax = E + G,  σmin = E − G,
//   Q = (E + G)² / det A,
// which is exact to rounding near Q = 1 (no cancellation).
// Conventions. A deformed face is *collapsed* when twice its area is at roundoff level relative to
// its longest edge (|e1×e2| ≤ 16 ε ℓ²max, the criterion of face_geometry.hpp): its Q is +inf. A
// degenerate *rest* face has no defined Q: Error naming the face.
#include <Eigen/Core>

namespace spinmotor {

/// Inputs: V_rest (n×3), F (m×3), V_def (n×3, same connectivity). Output: m values Q_f ∈ [1, +inf].
/// Throws Error on mismatched sizes, an index out of range, non-finite coordinates (naming the
/// vertex) or a degenerate rest face (naming the face).
Eigen::VectorXd quasi_conformal_error(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                      const Eigen::MatrixXd& V_def);

/// Area-weighted summary of Q.
struct QuasiConformalSummary {
  double q_mean = 1.0;               ///< Σ A_f Q_f / Σ A_f over non-collapsed faces, A_f the REST areas
  double q_max = 1.0;                ///< max Q_f; +inf if any face collapsed
  Eigen::Index worst_face = -1;      ///< a face attaining q_max (the first collapsed one if any)
  Eigen::Index collapsed_faces = 0;  ///< number of faces with Q = +inf (excluded from q_mean)
};

/// Inputs: per-face Q (m) and rest face areas (m, all > 0). Output: the summary above.
QuasiConformalSummary summarize_quasi_conformal(const Eigen::VectorXd& Q, const Eigen::VectorXd& rest_areas);

/// Inputs as quasi_conformal_error. Output: the summary of its result with rest-area weights.
QuasiConformalSummary quasi_conformal_summary(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                              const Eigen::MatrixXd& V_def);

}  // namespace spinmotor
