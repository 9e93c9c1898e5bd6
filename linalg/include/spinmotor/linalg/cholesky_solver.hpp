#pragma once
// BasicCholeskySolver<Scalar>: sparse symmetric (Scalar = double) or Hermitian (Scalar =
// std::complex<double>) positive definite systems A X = B through CHOLMOD (SuiteSparse), the one
// CHOLMOD wrapper of the project. CholeskySolver is the real one, ComplexCholeskySolver the complex one
// (the spin transformation's quaternionic eigen matrix in its 2n×2n complex Hermitian form factors ~3×
// faster than the real 4n×4n form).
//
// Factor once, solve many: analyze() orders and builds the symbolic factor from A's pattern,
// factorize() computes the numeric factor A = Pᵀ L Lᴴ P for a matrix with that pattern (call it again
// when only the values change), solve() takes any number of right-hand sides at once (one n×k block:
// CHOLMOD's supernodal solve works on the whole block with dense BLAS kernels).
//
// Partial solves: solve(B, System::L) = L⁻¹B, System::Lt = L⁻ᴴB, System::P = P B, System::Pt = Pᵀ B
// (CHOLMOD's sys argument), so that L⁻¹P and PᵀL⁻ᴴ can be applied separately (Spectra's Cholesky mode,
// dirac_spectrum.cpp). L is the Cholesky factor of P A Pᵀ whether the numeric factor is LLᴴ or LDLᴴ.
//
// Input convention: A is n×n, symmetric / Hermitian, stored in full or as its lower triangle: one
// triangle is read, the other is not checked. A matrix with as many entries above the diagonal as
// below counts as stored in full, and then its upper triangle is read when the ordering permutes it
// (CHOLMOD forms the permuted factor input from it with one transpose instead of two); otherwise the
// lower triangle. Column-major, compressed Eigen storage with int indices, viewed by CHOLMOD without
// copying.
//
// Ordering (ordering.hpp; the fill-reducing permutation, computed once per analyze()); the constructor
// throws Error (BadInput) for the orderings of other solvers (colamd, nested-dissection, ...):
//   Auto   (default) AMD below 500,000 rows, METIS from there on: AMD's ordering is cheap and wins a
//          one-off solve up to a few 100k rows; nested dissection halves the factorization flops at 1M
//          (the measured ordering study: docs/performance.md, "Cholesky ordering").
//   AMD    approximate minimum degree.
//   METIS  nested dissection (METIS_NodeND).
//   NESDIS CHOLMOD's nested dissection (METIS partitions + constrained minimum degree).
//   Natural no permutation (tests, banded matrices, matrices the caller has ordered already; CHOLMOD
//          still postorders the elimination tree).
// Supernodal (default) LLᴴ vs simplicial LDLᴴ: supernodal factorizes faster from ~100k rows on,
// simplicial can win around 10k (docs/performance.md).
//
// Failures throw spinmotor::Error:
//   - BadInput: A not square, not compressed, not finite, size or pattern different from the analyzed
//     one, B with the wrong number of rows, solve() before factorize().
//   - Numerical: "matrix is not positive definite (CHOLMOD: leading minor k; pivot at row r, in
//     connected component c of the matrix graph ...)" when a pivot is not positive, and "... numerically
//     singular, smallest pivot d vs largest diagonal entry a ..." when the smallest pivot d_k (L(k,k)²,
//     or D(k,k) for LDLᴴ) is ≤ 1000·ε·max_j A(j,j) (cond(A) ≳ 4.5e12: e.g. a Laplacian with a
//     connected component that has no constraint, whose last pivot is roundoff of either sign); also
//     when the solution is not finite.
// Not thread-safe: one solver object per thread (solve() uses CHOLMOD workspace).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <complex>
#include <memory>

#include "spinmotor/linalg/ordering.hpp"

namespace spinmotor {

template <class Scalar>  // double or std::complex<double>
class BasicCholeskySolver {
 public:
  using Ordering = spinmotor::Ordering;
  /// The orderings this solver implements.
  static constexpr Ordering kOrderings[] = {Ordering::Auto, Ordering::Natural, Ordering::AMD, Ordering::METIS,
                                            Ordering::NESDIS};
  using SparseMatrix = Eigen::SparseMatrix<Scalar>;
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  /// Which system solve() solves (A = Pᵀ L Lᴴ P): A X = B, L X = B, Lᴴ X = B, X = P B, X = Pᵀ B.
  enum class System { A, L, Lt, P, Pt };

  struct Options {
    Ordering ordering = Ordering::Auto;
    /// Supernodal LLᴴ (dense BLAS kernels on supernodes; the default) or simplicial LDLᴴ (up-looking,
    /// no BLAS; can win on very small matrices).
    bool supernodal = true;
    /// Also analyse the natural order (the rows as given, e.g. already ordered by the caller) and keep
    /// whichever of the two predicts fewer factorization flops (ARAP: AMD against its geometric nested
    /// dissection). Costs a second symbolic analysis.
    bool try_natural = false;
  };

  BasicCholeskySolver();
  explicit BasicCholeskySolver(const Options& options);
  ~BasicCholeskySolver();
  BasicCholeskySolver(BasicCholeskySolver&&) noexcept;
  BasicCholeskySolver& operator=(BasicCholeskySolver&&) noexcept;
  BasicCholeskySolver(const BasicCholeskySolver&) = delete;
  BasicCholeskySolver& operator=(const BasicCholeskySolver&) = delete;

  /// Symbolic analysis of A's pattern (values are not read): ordering + symbolic factor.
  void analyze(const SparseMatrix& A);
  /// Numeric factorization of A, whose pattern must be the analyzed one.
  void factorize(const SparseMatrix& A);
  /// analyze(A) then factorize(A).
  void compute(const SparseMatrix& A);

  /// Inputs: B (n×k), the system (default A). Output: X (n×k) solving it. Throws if not factorized or
  /// B has ≠ n rows.
  [[nodiscard]] Matrix solve(const Eigen::Ref<const Matrix>& B, System system = System::A) const;

  [[nodiscard]] Eigen::Index rows() const;
  [[nodiscard]] bool analyzed() const;
  [[nodiscard]] bool factorized() const;
  /// Nonzeros of the factor L (after analyze: predicted; measures the ordering's fill).
  [[nodiscard]] double factor_nonzeros() const;
  /// Floating-point operations of the numeric factorization predicted by analyze().
  [[nodiscard]] double factor_flops() const;
  [[nodiscard]] const Options& options() const;
  /// The ordering the last analyze() used: Natural when try_natural chose it, AMD or METIS for Auto.
  [[nodiscard]] Ordering ordering_used() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

extern template class BasicCholeskySolver<double>;
extern template class BasicCholeskySolver<std::complex<double>>;

using CholeskySolver = BasicCholeskySolver<double>;
using ComplexCholeskySolver = BasicCholeskySolver<std::complex<double>>;

}  // namespace spinmotor
