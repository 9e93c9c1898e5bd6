#pragma once
// Quaternionic matrices as real matrices (Crane, Pinkall & Schröder 2011, §5.1).
//
// A quaternionic matrix X ∈ H^{m×n} acting on column vectors of quaternions from the LEFT is stored
// as the real 4m×4n matrix X̂ in which each entry q = a + bi + cj + dk becomes the 4×4 block
//     [ a −b −c −d ]
//     [ b  a −d  c ]
//     [ c  d  a −b ]
//     [ d −c  b  a ]
// (the matrix of p ↦ q p on (w, x, y, z) coordinates). Then (XY)^ = X̂Ŷ and X̂ᵀ = (X^H)^, the real
// transpose is the conjugate transpose. A quaternion vector λ ∈ H^n is the real 4n-vector
// (w₀, x₀, y₀, z₀, w₁, ...), i.e. the project's n×4 quaternion field (real part first) read row by row.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "spinmotor/ga/quaternion.hpp"

namespace spinmotor {

/// The 4×4 real block of left multiplication by q (§5.1).
inline Eigen::Matrix4d quaternion_block(const ga::Quat& q) {
  const double a = q.w(), b = q.x(), c = q.y(), d = q.z();
  Eigen::Matrix4d X;
  X << a, -b, -c, -d,  //
      b, a, -d, c,     //
      c, d, a, -b,     //
      d, -c, b, a;
  return X;
}

/// Inputs: d (k). Output: the 4k×4k real diagonal matrix of the quaternionic diagonal matrix with real
/// entries d (each d_i repeated four times), e.g. the mass matrices M_F and M_V of §5.4.
Eigen::SparseMatrix<double> quaternion_diagonal(const Eigen::VectorXd& d);

/// Inputs: Q (n×4 quaternion field, real part first). Output: the 4n real vector (rows concatenated).
inline Eigen::VectorXd flatten_quaternions(const Eigen::MatrixXd& Q) {
  Eigen::VectorXd x(Q.size());
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>>(x.data(), Q.rows(), 4) = Q;
  return x;
}

/// Inputs: x (4n real vector). Output: the n×4 quaternion field (real part first).
inline Eigen::MatrixXd unflatten_quaternions(const Eigen::VectorXd& x) {
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>>(x.data(), x.size() / 4,
                                                                                     4);
}

}  // namespace spinmotor
