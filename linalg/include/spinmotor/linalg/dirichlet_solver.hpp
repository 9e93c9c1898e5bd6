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
// component floats) and bind throws FloatingComponentError (an Error, BadInput) "connected component
// 3 (120 vertices, e.g. vertex 4711) of 5 has no constrained vertex", which also carries every
// floating component so that a caller can say it in its own words (ARAP: "has no handle vertex").
// Components are numbered 0.. in order of their smallest index, as vertex_components (topology.hpp)
// numbers them for a mesh Laplacian.
//
// The rows of A_FF follow the free unknowns in increasing order, or an order the caller gives (e.g. a
// geometric nested dissection, factorized with the natural ordering). A caller that assembles its
// own right-hand side in that order (ARAP's global step) uses solve_free() and free_constrained_block()
// instead of solve(): the same factorization without the scatter to all n unknowns.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/linalg/lu_solver.hpp"

namespace spinmotor {

/// Thrown by DirichletSolver::bind when connected components of the matrix graph have no constrained
/// unknown. what() names the first; the accessors list all of them (component ids, increasing).
class FloatingComponentError : public Error {
 public:
  struct Component {
    int id = 0;     ///< in [0, count)
    int size = 0;   ///< unknowns in the component
    int first = 0;  ///< its smallest index
  };
  FloatingComponentError(const std::string& what, std::vector<Component> floating, int count)
      : Error(what), floating_(std::move(floating)), count_(count) {}
  /// The components without a constrained unknown (at least one), by increasing id.
  [[nodiscard]] const std::vector<Component>& floating() const noexcept { return floating_; }
  /// Number of connected components of the matrix graph.
  [[nodiscard]] int count() const noexcept { return count_; }

 private:
  std::vector<Component> floating_;
  int count_ = 0;
};

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

  /// Inputs: A (n×n sparse, compressed), constrained (c distinct indices in [0, n), any order), kind.
  /// Checks the components, extracts A_FF and A_FC and factorizes A_FF. Throws Error: BadInput for
  /// an index out of range or repeated (naming its position), FloatingComponentError for a component
  /// without a constrained unknown; Numerical if the factorization fails.
  void bind(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& constrained, Kind kind = Kind::SPD);
  /// As above, where a component is also anchored by an unknown i with anchors[i] ≠ 0 (n entries): the
  /// caller's diagonal term there (an attraction c_i > 0 added to a Laplacian) makes A_FF regular.
  void bind(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& constrained, Kind kind,
            const std::vector<char>& anchors);
  /// As above, with the rows of A_FF in the order `free_order` (the n − c unconstrained indices, each
  /// once, in any order; free() returns it). Throws Error (BadInput) if it is not exactly those.
  void bind(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& constrained,
            const Eigen::VectorXi& free_order, Kind kind = Kind::SPD);

  /// Inputs: B (n×k right-hand side; rows of constrained unknowns are ignored; 0×0 or 0×k means
  /// B = 0, the Laplace problem), values (c×k, row r = values of constrained(r)).
  /// Output: X (n×k) with X(constrained(r), :) = values(r, :) exactly and A_FF X_F = B_F − A_FC X_C.
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& B,
                        const Eigen::Ref<const Eigen::MatrixXd>& values) const;
  /// solve(B = 0, values).
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& values) const;

  /// Input: rhs_F ((n − c)×k, row r for the free unknown free()[r]). Output: X_F with A_FF X_F = rhs_F
  /// (the factorization alone: the caller has moved the constrained values to the right-hand side,
  /// e.g. with free_constrained_block()). Throws Error if not bound or rhs_F has the wrong row count.
  [[nodiscard]] Eigen::MatrixXd solve_free(const Eigen::Ref<const Eigen::MatrixXd>& rhs_F) const;
  /// A_FC ((n − c)×c): rows in free() order, columns in constrained() order.
  [[nodiscard]] const Eigen::SparseMatrix<double>& free_constrained_block() const;
  /// The factorization of A_FF (Kind::SPD; throws Error for Kind::LU or before bind): its ordering,
  /// fill and flops.
  [[nodiscard]] const CholeskySolver& cholesky() const;

  Eigen::Index rows() const;
  bool bound() const;
  const Eigen::VectorXi& constrained() const;  ///< as given to bind()
  const Eigen::VectorXi& free() const;         ///< the other indices: increasing, or as given to bind()

 private:
  void bind_impl(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& constrained,
                 const Eigen::VectorXi* free_order, Kind kind, const std::vector<char>* anchors = nullptr);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinmotor
