#pragma once
// Gradient and divergence of piecewise-linear functions (hat-function basis φ_i, one per vertex).
//
// Row layout: PER FACE. Row 3f+k of G is the k-th coordinate (x, y, z) of the gradient on face f, so
// the 3m-vector G·u viewed as a row-major m×3 matrix is the per-face gradient field:
//   Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(g.data(), m, 3).
// (libigl's grad stacks coordinate blocks instead, rows k·m+f.) A face vector field X (m×3) enters the
// divergence the same way, flattened row by row.
//
// On face f with area A and unit normal N: ∇φ_i = N × e_i / (2A), e_i the edge opposite corner i
// oriented counter-clockwise (from F(f,i+1) to F(f,i+2)).
// Divergence (integrated, weak form): (D X)_i = −Σ_f A_f ∇φ_i|_f · X_f, i.e. D = −Gᵀ·diag(A ⊗ 1₃), so
//   −D·G = Gᵀ diag(A) G = L, the cotangent Laplacian of cotangent_laplacian.hpp (exactly, up to
//   rounding), and M⁻¹ D X is the pointwise divergence (M the mass matrix).
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace spinmotor {

/// Inputs: V (n×3), F (m×3). Output: 3m×n sparse G (9 entries per face), rows per face as above.
/// Throws Error naming the first degenerate face.
Eigen::SparseMatrix<double> gradient(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// Inputs: V (n×3), F (m×3). Output: n×3m sparse D = −Gᵀ·diag(A ⊗ 1₃), columns per face as above.
/// Throws Error naming the first degenerate face.
Eigen::SparseMatrix<double> divergence(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace spinmotor
