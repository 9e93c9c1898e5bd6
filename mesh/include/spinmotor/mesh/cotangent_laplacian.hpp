#pragma once
// The cotangent Laplacian (Pinkall & Polthier 1993; Meyer et al. 2003, eq. 8), the stiffness matrix of
// piecewise-linear finite elements.
//
// Sign convention: POSITIVE semi-definite.
//   L(i,j) = −½ (cot α_ij + cot β_ij)   for an edge ij (α, β the angles opposite the edge; one term on
//                                        a boundary edge, more than two on a non-manifold edge),
//   L(i,i) = −Σ_j L(i,j),               0 elsewhere,
// so xᵀ L x = ∫|∇x|² ≥ 0, L·1 = 0, and with M the mass matrix (mass_matrix.hpp) M⁻¹ L x ≈ −Δx.
// Applied to the coordinates: M⁻¹ L V ≈ 2 H N (mean curvature normal, H = 1/r on a sphere of radius r,
// N outward for counter-clockwise faces). Equivalently L = −D·G with the gradient G and divergence D
// of gradient.hpp.
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace spinmotor {

/// Inputs: V (n×3), F (m×3). Output: n×n symmetric sparse L (column-major, sorted indices, compressed),
/// with the convention above. The diagonal is always stored (0 for a vertex that no face references),
/// so L + s·M has the same pattern as L. Assembly is parallel (OpenMP) and writes the compressed
/// storage directly (no triplets). Throws Error naming the first degenerate face, or a face with an
/// index out of range, or a vertex with non-finite coordinates.
Eigen::SparseMatrix<double> cotangent_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace spinmotor
