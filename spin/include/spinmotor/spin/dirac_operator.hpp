#pragma once
// The discrete operators of the vertex-based spin transformation (Crane, Pinkall & Schröder 2011,
// §5.2–§5.4), assembled explicitly as real 4×4-block sparse matrices (quaternion_matrix.hpp).
//
// λ lives at the n vertices (piecewise linear), ρ and Dλ on the m faces (piecewise constant):
//   D ∈ H^{m×n}  D_fj = −e_j / (2 A_f)                      (eq. 5), e_j the edge of face f opposite
//                                                            vertex j, oriented counter-clockwise
//                                                            (from F(f,c+1) to F(f,c+2), c = corner of j)
//   B ∈ H^{m×n}  B_fj = 1/3 for each vertex j of face f      (§5.3)
//   R = P B      P = diag(ρ_f)                               (§5.3)
//   A = D − R                                                 (§5.3)
//   M_F = diag(A_f),  M_V = diag(⅓ Σ_{f∋i} A_f)               (§5.4)
//   X* = X^H M_F  (the adjoint with M_V⁻¹ omitted, §5.4), i.e. the real matrix X̂ᵀ M̂_F.
// With these, A*A and B*A are Hermitian (B*A only on closed meshes: at a boundary edge B*D is not)
// and A*A is positive semi-definite; with ρ = 0 the constant quaternions are in the kernel of D.
//
// These explicit matrices are the readable reference (tests, spectrum validation). The spin
// transformation itself assembles A*A directly in its factorization's storage
// (dirac_assembly.hpp), which is several times faster than forming the products below.
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace spinmotor {

/// Inputs: V (n×3), F (m×3, counter-clockwise). Output: D (4m×4n), eq. 5. Throws Error naming the
/// first degenerate face (zero area).
Eigen::SparseMatrix<double> dirac_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// Inputs: F (m×3), n (number of vertices). Output: B (4m×4n), the face-from-vertex average of §5.3.
Eigen::SparseMatrix<double> face_vertex_average(const Eigen::MatrixXi& F, Eigen::Index n);

/// Inputs: F (m×3), n, rho (m, the change of mean curvature half-density per face). Output:
/// R = P B (4m×4n), §5.3.
Eigen::SparseMatrix<double> curvature_change_operator(const Eigen::MatrixXi& F, Eigen::Index n,
                                                      const Eigen::VectorXd& rho);

/// Inputs: V (n×3), F (m×3), rho (m). Output: A = D − R (4m×4n).
Eigen::SparseMatrix<double> dirac_minus_rho(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                            const Eigen::VectorXd& rho);

/// Inputs: X (4m×4k), face_areas (m). Output: X* = X̂ᵀ M̂_F (4k×4m), the adjoint of §5.4.
Eigen::SparseMatrix<double> dirac_adjoint(const Eigen::SparseMatrix<double>& X,
                                          const Eigen::VectorXd& face_areas);

}  // namespace spinmotor
