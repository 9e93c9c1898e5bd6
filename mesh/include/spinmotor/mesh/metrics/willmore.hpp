#pragma once
// Discrete Willmore energy W = ∫ H² dA, H the mean curvature (mean of the principal curvatures), so
// W(round sphere) = 4π and W ≥ 4π on closed surfaces; Willmore's torus (R/r = √2) has W = 2π².
// Vertex-based discretisation: with the positive semi-definite cotangent Laplacian L and the mixed
// Voronoi areas A_i (cotangent_laplacian.hpp, mass_matrix.hpp), (L V)_i ≈ 2 H_i N_i A_i, so
//   W ≈ Σ_i A_i H_i² = Σ_i |(L V)_i|² / (4 A_i),
// summed over interior vertices (on a boundary vertex (L V)_i also carries the boundary's curvature
// and is not a mean-curvature normal). Units: dimensionless (scale-invariant).
#include <Eigen/Core>

namespace spinmotor {

/// Inputs: V (n×3), F (m×3). Output: W ≥ 0. Vertices referenced by no face are ignored.
/// Throws Error (from the operators) naming a degenerate face, an index out of range or a
/// non-finite coordinate.
double willmore_energy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// Inputs: V (n×3), F (m×3). Output: n pointwise values H_i² A_i (0 on boundary and unreferenced
/// vertices); their sum is willmore_energy(V, F).
Eigen::VectorXd willmore_density(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace spinmotor
