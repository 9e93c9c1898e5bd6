#pragma once
// The mean-value-weight Laplacian (Floater 2003, "Mean value coordinates", CAGD 20): positive weights
// on any triangulation (unlike cotangents), at the price of symmetry. The CGA deformation paper builds
// its harmonic fields on it (cga-mesh-deformation.txt, §VIII eq. 14; note that the paper's claim
// w_ij = w_ji does not hold for these weights).
//
//   w_ij = (tan(α_ij/2) + tan(β_ij/2)) / |x_j − x_i|,
// α_ij, β_ij the angles AT x_i of the two faces adjacent to edge ij (one face on the boundary; each
// face counts once). Same sign convention as cotangent_laplacian.hpp:
//   L(i,j) = −w_ij,   L(i,i) = Σ_j w_ij,
// so L·1 = 0 and row i belongs to vertex i. L is not symmetric (w_ij ≠ w_ji in general): solve it with
// LUSolver (lu_solver.hpp). Dividing row i by L(i,i) gives Floater's mean value coordinates λ_ij of
// x_i with respect to its one-ring; for planar interior vertices they reproduce x_i exactly
// (Σ_j λ_ij x_j = x_i), which the tests check.
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace spinmotor {

/// Inputs: V (n×3), F (m×3). Output: n×n sparse L (column-major, compressed, sorted), pattern equal to
/// that of cotangent_laplacian (diagonal always stored). Throws Error naming the first degenerate face
/// (tan(θ/2) is unbounded there), a face with an index out of range, or a non-finite vertex.
Eigen::SparseMatrix<double> mean_value_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace spinmotor
