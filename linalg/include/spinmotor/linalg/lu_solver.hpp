#pragma once
// LUSolver: sparse non-symmetric systems A X = B through SuperLU 5 (supernodal LU with partial
// pivoting), e.g. the mean-value Laplacian (mean_value_laplacian.hpp).
//
// Same shape as CholeskySolver: analyze() computes the fill-reducing column ordering from A's
// pattern; factorize() computes P_r A P_c = L U for a matrix with that pattern (call it again when
// only the values change); solve() takes all right-hand sides at once (n×k).
//
// Column ordering (ordering.hpp): colamd (default), natural, mmd-ata or mmd-at-plus-a; the constructor
// throws Error (BadInput) for the orderings of other solvers. COLAMD by default, as docs/design.md asks (MMD
// was measured ~40× slower on the 4n×4n quaternionic systems of the spin module). On matrices with a
// SYMMETRIC PATTERN, such as the mean-value Laplacian (+ mass), MMD_AtPlusA is better: bench_laplacian
// (lu_ordering/*/10k) measured nnz(L+U) 0.72M with MMD(Aᵀ+A) vs 1.43M with COLAMD, 1.41M with MMD(AᵀA), 2.84M
// natural, and about half the factorization time; choose it there. The ordering is computed once per
// analyze(). Row pivoting: threshold partial pivoting with `pivot_threshold` (1 = classical partial pivoting;
// smaller values prefer the diagonal, which keeps the column ordering's sparsity on diagonally
// dominant matrices such as Laplacians).
//
// SuperLU is called directly (dgstrf/dgstrs) instead of through Eigen/SuperLUSupport because that
// wrapper recomputes the column ordering on every factorize(), resets the options and does not report
// which pivot failed.
//
// Failures throw spinmotor::Error: BadInput as for CholeskySolver; Numerical "matrix is singular
// (SuperLU: zero pivot in column j, ...)" naming the column and its connected component in the matrix
// graph, also when the reciprocal condition number estimate (dgscon, 1-norm) is below machine epsilon
// (numerically singular) and when the solution is not finite.
// Not thread-safe: one solver object per thread.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

#include "spinmotor/linalg/ordering.hpp"

namespace spinmotor {

class LUSolver {
 public:
  using Ordering = spinmotor::Ordering;
  /// The orderings this solver implements.
  static constexpr Ordering kOrderings[] = {Ordering::Natural, Ordering::COLAMD, Ordering::MMD_AtA,
                                            Ordering::MMD_AtPlusA};

  struct Options {
    Ordering ordering = Ordering::COLAMD;
    double pivot_threshold = 1.0;  ///< in [0, 1]: SuperLU's DiagPivotThresh
  };

  LUSolver();
  explicit LUSolver(const Options& options);
  ~LUSolver();
  LUSolver(LUSolver&&) noexcept;
  LUSolver& operator=(LUSolver&&) noexcept;
  LUSolver(const LUSolver&) = delete;
  LUSolver& operator=(const LUSolver&) = delete;

  /// Column ordering from A's pattern (values are not read).
  void analyze(const Eigen::SparseMatrix<double>& A);
  /// Numeric factorization of A, whose pattern must be the analyzed one.
  void factorize(const Eigen::SparseMatrix<double>& A);
  /// analyze(A) then factorize(A).
  void compute(const Eigen::SparseMatrix<double>& A);

  /// Inputs: B (n×k). Output: X (n×k) with A X = B.
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& B) const;

  Eigen::Index rows() const;
  bool analyzed() const;
  bool factorized() const;
  /// nnz(L) + nnz(U) of the last factorization.
  double factor_nonzeros() const;
  /// Reciprocal condition number estimate (1-norm) of the last factorization.
  double rcond() const;
  const Options& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinmotor
