#pragma once
// CholeskySolver: sparse symmetric positive definite systems A X = B through CHOLMOD (SuiteSparse).
//
// Factor once, solve many: analyze() orders and builds the symbolic factor from A's pattern,
// factorize() computes the numeric factor for a matrix with that pattern (call it again when only the
// values change), solve() takes any number of right-hand sides at once (one n×k block: CHOLMOD's
// supernodal solve works on the whole block with dense BLAS kernels).
//
// Input convention: A is n×n, symmetric, stored in full or as its lower triangle (only the lower
// triangle is read; the upper one is ignored, not checked). Column-major Eigen storage with int
// indices, viewed by CHOLMOD without copying when compressed.
//
// Ordering (fill-reducing permutation, computed once per analyze()):
//   Auto   (default) AMD below 500,000 rows, METIS from there on: AMD's ordering is cheap and wins a
//          one-off solve up to a few 100k rows; nested dissection halves the factorization flops at 1M
//          (the measured ordering study: docs/performance.md, "Cholesky ordering").
//   AMD    approximate minimum degree.
//   METIS  nested dissection (METIS_NodeND).
//   NESDIS CHOLMOD's nested dissection (METIS partitions + constrained minimum degree).
//   Natural no permutation (tests, banded matrices).
// Supernodal (default) vs simplicial: supernodal factorizes faster from ~100k rows on, simplicial
// can win around 10k (docs/performance.md).
//
// Failures throw spinmotor::Error:
//   - BadInput: A not square, not finite, size or pattern different from the analyzed one, B with the
//     wrong number of rows, solve() before factorize().
//   - Numerical: "matrix is not positive definite (CHOLMOD: leading minor k, row r, in connected
//     component c of the matrix graph ...)", also raised when the factor is numerically singular
//     (rcond = (min diag L / max diag L)² below machine epsilon: e.g. a Laplacian with a connected
//     component that has no constraint, whose last pivot is roundoff of either sign), and when the
//     solution is not finite.
// Not thread-safe: one solver object per thread (solve() uses CHOLMOD workspace).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

namespace spinmotor {

class CholeskySolver {
 public:
  enum class Ordering { Auto, Natural, AMD, METIS, NESDIS };

  struct Options {
    Ordering ordering = Ordering::Auto;
    /// Supernodal LLᵀ (dense BLAS kernels on supernodes; the default) or simplicial LDLᵀ (up-looking,
    /// no BLAS; can win on very small matrices).
    bool supernodal = true;
  };

  CholeskySolver();
  explicit CholeskySolver(const Options& options);
  ~CholeskySolver();
  CholeskySolver(CholeskySolver&&) noexcept;
  CholeskySolver& operator=(CholeskySolver&&) noexcept;
  CholeskySolver(const CholeskySolver&) = delete;
  CholeskySolver& operator=(const CholeskySolver&) = delete;

  /// Symbolic analysis of A's pattern (values are not read): ordering + symbolic factor.
  void analyze(const Eigen::SparseMatrix<double>& A);
  /// Numeric factorization of A, whose pattern must be the analyzed one.
  void factorize(const Eigen::SparseMatrix<double>& A);
  /// analyze(A) then factorize(A).
  void compute(const Eigen::SparseMatrix<double>& A);

  /// Inputs: B (n×k). Output: X (n×k) with A X = B. Throws if not factorized or B has ≠ n rows.
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& B) const;

  Eigen::Index rows() const;
  bool analyzed() const;
  bool factorized() const;
  /// Nonzeros of the factor L (after analyze: predicted; measures the ordering's fill).
  double factor_nonzeros() const;
  /// Floating-point operations of the numeric factorization predicted by analyze().
  double factor_flops() const;
  const Options& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinmotor
