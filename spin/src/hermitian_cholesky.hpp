#pragma once
// Private to spin/: supernodal Cholesky LLᴴ of a sparse complex Hermitian positive definite matrix
// through CHOLMOD, for the complex form of the quaternionic eigen matrix (dirac_assembly.hpp).
//
// Why not mesh's CholeskySolver: it is real-only, and the complex form of A*A (2n×2n, 2×2 blocks)
// factors about 3× faster than its real 4n×4n form (bench_spin, "factor" counters), which is the
// dominant cost of a spin transformation. Same contract otherwise: A stored as its lower triangle
// (column-major, int indices, viewed without copying), analyze once per pattern, factorize per
// value set; errors as spinmotor::Error (BadInput for misuse, Numerical when not positive definite).
// The vertex ordering is done by DiracAssembly, so the default here is the natural order.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <complex>
#include <memory>

namespace spinmotor::detail {

class HermitianCholesky {
public:
  enum class Ordering { Natural, AMD, METIS };
  explicit HermitianCholesky(Ordering ordering = Ordering::Natural, bool supernodal = true);
  ~HermitianCholesky();
  HermitianCholesky(HermitianCholesky&&) noexcept;
  HermitianCholesky& operator=(HermitianCholesky&&) noexcept;

  void analyze(const Eigen::SparseMatrix<std::complex<double>>& A);
  void factorize(const Eigen::SparseMatrix<std::complex<double>>& A);
  Eigen::VectorXcd solve(const Eigen::VectorXcd& b) const;
  double factor_nonzeros() const;
  double factor_flops() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinmotor::detail
