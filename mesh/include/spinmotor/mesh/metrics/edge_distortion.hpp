#pragma once
// Log edge-length distortion with the global scale removed, per unique edge (edge_topology order):
//   d_e = log(l'_e / l_e) − log(Σl' / Σl),
// l_e the rest and l'_e the deformed length. d ≡ 0 for a similarity; a deformed edge of length 0 has
// d_e = −inf.
#include <Eigen/Core>

namespace spinmotor {

/// Inputs: V_rest (n×3), F (m×3), V_def (n×3). Output: k values, one per edge of edge_topology(F).E.
/// Throws Error on mismatched sizes, an index out of range, non-finite coordinates or a rest edge of
/// zero length (naming its two vertices).
Eigen::VectorXd log_edge_distortion(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                    const Eigen::MatrixXd& V_def);

struct EdgeDistortionSummary {
  double mean_abs = 0.0;             ///< Σ l_e |d_e| / Σ l_e over non-collapsed edges (rest lengths)
  double max_abs = 0.0;              ///< max |d_e|; +inf if an edge collapsed
  double global_scale = 1.0;         ///< Σl' / Σl, the length ratio that was removed
  Eigen::Index collapsed_edges = 0;  ///< edges with d_e = −inf (excluded from mean_abs)
};

/// Inputs as log_edge_distortion. Output: the rest-length-weighted summary.
EdgeDistortionSummary edge_distortion_summary(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                              const Eigen::MatrixXd& V_def);

}  // namespace spinmotor
