#pragma once
// DirichletSolver: A x = b with some unknowns fixed (Dirichlet constraints), factorized once.
//
// Splitting the unknowns into free (F) and constrained (C) ones, the rows of the constrained
// unknowns are dropped and their values moved to the right-hand side:
//   A_FF x_F = B_F − A_FC X_C,   x_C = X_C.
// bind() factorizes A_FF once (Cholesky for symmetric positive definite A_FF, e.g. a cotangent
// Laplacian; LU otherwise, e.g. the mean-value Laplacian); solve() then costs two triangular solves
// per column, whatever the constrained values: changing only the values reuses the factorization.
//
// Before factorizing, bind() checks that every connected component of A's sparsity graph (i ~ j
// when A(i,j) or A(j,i) is stored) contains a constrained unknown: otherwise A_FF is singular (the
// component floats) and bind throws Error (BadInput) "connected component 3 (120 vertices, e.g.
// vertex 4711) has no constrained vertex". Components are numbered 0.. in order of their smallest
// index, as vertex_components (topology.hpp) numbers them for a mesh Laplacian.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/linalg/lu_solver.hpp"

namespace spinmotor {

class DirichletSolver {
 public:
  enum class Kind {
    SPD,  ///< A_FF symmetric positive definite: CholeskySolver (only the lower triangle of A is read)
    LU,   ///< general: LUSolver
  };

  struct Options {
    CholeskySolver::Options cholesky;
    LUSolver::Options lu;
  };

  DirichletSolver();
  explicit DirichletSolver(const Options& options);
  ~DirichletSolver();
  DirichletSolver(DirichletSolver&&) noexcept;
  DirichletSolver& operator=(DirichletSolver&&) noexcept;

  /// Inputs: A (n×n sparse), constrained (c distinct indices in [0, n), any order), kind.
  /// Checks the components, extracts A_FF and A_FC and factorizes A_FF. Throws Error: BadInput for
  /// an index out of range or repeated (naming its position), for a component without a constrained
  /// unknown; Numerical if the factorization fails.
  void bind(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& constrained, Kind kind = Kind::SPD);

  /// Inputs: B (n×k right-hand side; rows of constrained unknowns are ignored; 0×0 or 0×k means
  /// B = 0, the Laplace problem), values (c×k, row r = values of constrained(r)).
  /// Output: X (n×k) with X(constrained(r), :) = values(r, :) exactly and A_FF X_F = B_F − A_FC X_C.
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& B,
                        const Eigen::Ref<const Eigen::MatrixXd>& values) const;
  /// solve(B = 0, values).
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& values) const;

  Eigen::Index rows() const;
  bool bound() const;
  const Eigen::VectorXi& constrained() const;  ///< as given to bind()
  const Eigen::VectorXi& free() const;         ///< the other indices, increasing

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinmotor
