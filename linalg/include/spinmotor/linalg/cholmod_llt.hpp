#pragma once
// Private to spin/: supernodal Cholesky A = Pᵀ L Lᴴ P of a sparse symmetric (real) or Hermitian
// (complex) positive definite matrix through CHOLMOD, with access to the partial solves.
//
// Why not mesh's CholeskySolver (real, full solves only):
//   - the complex Hermitian form of the quaternionic eigen matrix (dirac_assembly.hpp, 2n×2n with 2×2
//     blocks) factors about 3× faster than its real 4n×4n form (bench_spin), and the factorization is
//     the dominant cost of a spin transformation;
//   - the spectrum (dirac_spectrum.cpp) runs Spectra in Cholesky mode, which needs L⁻¹Px and PᵀL⁻ᴴx
//     separately.
// Contract as CholeskySolver: A is given by its lower triangle (column-major, int indices, viewed
// without copying), analyze once per pattern, factorize per value set; spinmotor::Error on misuse,
// numerical_error when A is not (numerically) positive definite. The vertex ordering is normally done
// by DiracAssembly, so Natural is the default here (CHOLMOD still postorders the elimination tree).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <complex>
#include <memory>

namespace spinmotor::detail {

template <class Scalar>  // double or std::complex<double>
class CholmodLLT {
 public:
  enum class Ordering { Natural, AMD, METIS };
  /// Which system solve() solves (CHOLMOD's sys argument): A x = b, or one factor of A = Pᵀ L Lᴴ P.
  enum class System { A, L, Lt, P, Pt };
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;

  explicit CholmodLLT(Ordering ordering = Ordering::Natural, bool supernodal = true);
  ~CholmodLLT();
  CholmodLLT(CholmodLLT&&) noexcept;
  CholmodLLT& operator=(CholmodLLT&&) noexcept;

  void analyze(const Eigen::SparseMatrix<Scalar>& A);
  void factorize(const Eigen::SparseMatrix<Scalar>& A);
  Vector solve(const Vector& b, System system = System::A) const;
  Eigen::Index rows() const;
  double factor_nonzeros() const;
  double factor_flops() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

extern template class CholmodLLT<double>;
extern template class CholmodLLT<std::complex<double>>;

}  // namespace spinmotor::detail
