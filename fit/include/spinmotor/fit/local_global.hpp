#pragma once
// The local/global solver under ARAP (deform/arap.hpp) and the pose-keeping cleanup
// (spin/pinned_cleanup.hpp): minimise Σ_cells E_c(X, T_c) over positions X and per-cell transforms T_c by
// alternating a local step (each cell's best transform for the current X: cells.hpp) and a global step
// (the best X for those transforms: one linear solve).
//
// Global step. With the constrained vertices C fixed at their values X_C (handles, pins):
//   (A X)_F = B_F(T) + c_F ⊙ Y_F,   A = L + diag(c),
// L the problem's global matrix (a cotangent Laplacian), c ≥ 0 an optional attraction toward target
// positions Y (the cleanup's pose attraction) and B the problem's right-hand side. A_FF is factorised once
// at bind (DirichletSolver; components anchored by a constrained vertex or a positive c_i); each step
// costs one back-substitution of 3 columns (the constant A_FC X_C is computed once per solve).
// Optional equality row (MeasureKind): the enclosed volume (Σ_f v0·(v1 × v2) / 6) or the total area of
// the faces with a free vertex (plus the fixed faces' share) held at a target, linearised around the
// current X: g · X = target − measure(X_k) + g · X_k with g = ∂measure/∂X_F; the KKT system
// [A_FF g; gᵀ 0] is solved with the same factor: X_a = A_FF⁻¹ b, X_g = A_FF⁻¹ g (6 columns together),
// X = X_a − μ X_g, μ = (g·X_a − rhs) / (g·X_g).
//
// Acceleration (SolveOptions::anderson = m > 0): Anderson acceleration of the fixed point x → G(x) (one
// local + global step) on the free coordinates (Peng et al. 2018, "Anderson acceleration for geometry
// optimization and physics simulation", §3–4): x_{k+1} = G_k − ΔG γ, γ = argmin |f_k − ΔF γ|,
// f = G(x) − x, the last m differences; a step whose energy rises is replaced by the plain iterate G_k and
// the history restarts. Affine combinations keep the constrained vertices (not part of x) exact. The
// returned X is a plain iterate: the last step allowed is not accelerated, and a stop at an accelerated
// point takes one more plain step from it (so the energy last reported is that of the X returned).
//
// Stopping rule (one for every problem): after the local step of iteration k ≥ 1, stop when
// |E_k − E_{k−1}| ≤ tolerance · max(E_k, E_{k−1}) (the relative energy change), or when
// E_k ≤ 1e-24 · Problem::energy_scale() (the positions are already a zero-energy state: nothing to
// do), or after max_iterations global steps. E is the problem's energy after each local step.
//
// Errors (spinmotor::Error): bind with a component anchored by nothing (FloatingComponentError, which
// the caller words), sizes that do not match; solve with X or values of the wrong size; numerical_error
// when the energy or the positions stop being finite.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

#include "spinmotor/linalg/dirichlet_solver.hpp"

namespace spinmotor::fit {

using RowMatrix3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// One solve's figures (an ARAP pose, a cleanup frame).
struct SolveReport {
  std::vector<double> energy;      ///< E_0 (the start), E_1, …: after each local step
  int iterations = 0;              ///< global steps taken
  bool converged = false;          ///< stopped by the rule, not by max_iterations
  double local_ms = 0;             ///< local steps (cell fits and energies)
  double global_ms = 0;            ///< global steps: right-hand sides, solves, updates
  double rhs_ms = 0;               ///< of which the right-hand sides (and the equality row's gradient)
  double solve_ms = 0;             ///< of which the back-substitutions
  Eigen::Index fallback_fits = 0;  ///< cell fits that took a fallback (Jacobi, a collapsed cell), all steps
  int rejected_accelerations = 0;  ///< Anderson steps replaced by the plain iterate
};

struct SolveOptions {
  int max_iterations = 100;  ///< global steps per solve (≥ 0)
  double tolerance = 1e-4;   ///< relative energy change that stops the iteration (≥ 0)
  int anderson = 0;          ///< Anderson depth (0: plain local/global)
};

/// The equality row of the global step.
enum class MeasureKind { None, Volume, Area };

class LocalGlobal;

/// The measure of X over the faces F: the enclosed volume (Volume) or the total area (Area, None).
[[nodiscard]] double total_measure(MeasureKind kind, const Eigen::MatrixXi& F, const RowMatrix3& X);

/// What a solve iterates: the cells' local step and the right-hand side of their transforms. The
/// solver owns the matrix, the constraints, the attraction, the measure row, the acceleration and the
/// stopping rule.
class Problem {
 public:
  virtual ~Problem() = default;
  /// Local step of iteration `it` (0 = the start): fit the cells to X (n×3) and return the energy the
  /// stopping rule reads; count fallback fits in report.fallback_fits.
  virtual double fit(const RowMatrix3& X, int it, SolveReport& report) = 0;
  /// The right-hand side B_F of the fitted transforms for the global step after the local step of
  /// iteration `it`: row r for the free vertex solver.free()[r] (nf×3).
  virtual void rhs(int it, const LocalGlobal& solver, RowMatrix3& B_free) = 0;
  /// False when the global step after local step `it` is not a step of the fixed-point map (a special
  /// start): the acceleration does not record it.
  virtual bool plain_step(int it) const { return true; }
  /// The energy of the problem's zero-energy scale (the stopping rule's 1e-24 is relative to it).
  virtual double energy_scale() const = 0;
  /// Called after each global step (and its acceleration) with the new positions.
  virtual void after_step(const RowMatrix3& X, int it) {}
};

class LocalGlobal {
 public:
  struct Bind {
    Eigen::SparseMatrix<double> L;  ///< n×n global matrix (symmetric, positive semi-definite)
    Eigen::VectorXi constrained;    ///< vertices held at given values (distinct)
    Eigen::VectorXi free_order;     ///< the free vertices in the order of A_FF's rows (empty: increasing)
    Eigen::VectorXd attraction;     ///< n values c_i ≥ 0 on the diagonal (empty: none)
    MeasureKind measure = MeasureKind::None;
    Eigen::MatrixXi F;  ///< faces of the measure (MeasureKind ≠ None)
    DirichletSolver::Options solver;
  };

  LocalGlobal();
  ~LocalGlobal();
  LocalGlobal(LocalGlobal&&) noexcept;
  LocalGlobal& operator=(LocalGlobal&&) noexcept;

  /// Factorises A_FF (see the header comment). Throws FloatingComponentError for a component without
  /// an anchor, Error for bad sizes, numerical errors of the factorization.
  void bind(const Bind& b);

  /// One solve: X (n×3) holds the start and receives the result (constrained rows = `values`, rows in the
  /// order of `constrained`); targets Y (n×3, read where c > 0); measure target (MeasureKind ≠ None).
  SolveReport solve(Problem& problem, RowMatrix3& X, const RowMatrix3& values, const RowMatrix3* targets,
                    double measure_target, const SolveOptions& options);

  /// The kept measure of X over every face (volume or area; area for MeasureKind::None).
  double measure(const RowMatrix3& X) const;

  Eigen::Index rows() const;            ///< n
  const Eigen::VectorXi& free() const;  ///< the free vertices, in the rows' order
  const Eigen::VectorXi& constrained() const;
  /// The factor's solver: X (n×k) with X_C = values and A_FF X_F = B_F − A_FC X_C.
  const DirichletSolver& dirichlet() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace spinmotor::fit
