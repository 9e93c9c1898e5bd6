#pragma once
// Log area distortion with the global scale removed:
//   d_f = log(A'_f / A_f) − log(ΣA' / ΣA),
// A_f the rest and A'_f the deformed area of face f. d ≡ 0 for any similarity (and for any deformation
// that scales every face by the same factor); d_f > 0 where a face grew more than the mesh did.
// A collapsed deformed face (zero area, see quasi_conformal.hpp) has d_f = −inf.
#include <Eigen/Core>

namespace spinmotor {

/// Inputs: V_rest (n×3), F (m×3), V_def (n×3). Output: m values d_f (dimensionless, natural log).
/// Throws Error on mismatched sizes, an index out of range, non-finite coordinates, a degenerate rest
/// face (naming it) or a deformed mesh of zero total area.
Eigen::VectorXd log_area_distortion(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                    const Eigen::MatrixXd& V_def);

struct AreaDistortionSummary {
  double mean_abs = 0.0;             ///< Σ A_f |d_f| / Σ A_f over non-collapsed faces (rest areas)
  double max_abs = 0.0;              ///< max |d_f|; +inf if a face collapsed
  double global_scale = 1.0;         ///< ΣA' / ΣA, the area ratio that was removed
  Eigen::Index collapsed_faces = 0;  ///< faces with d_f = −inf (excluded from mean_abs)
};

/// Inputs as log_area_distortion. Output: the rest-area-weighted summary.
AreaDistortionSummary area_distortion_summary(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                              const Eigen::MatrixXd& V_def);

}  // namespace spinmotor
