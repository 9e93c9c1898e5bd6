#pragma once
// smallest_eigenpair: the eigenvalue of smallest magnitude of a sparse symmetric (real) or Hermitian
// (complex) pencil, K x = θ G x (or K x = θ x), by inverse iteration on one factorization.
//
// The caller factors the shifted matrix K_σ = K + σI once (σ ≥ 0 keeps it definite when θ_min ≈ 0,
// e.g. BasicCholeskySolver) and passes its solve; each iteration costs one solve and two or three
// sparse products. Two methods:
//   - plain inverse iteration x ← K_σ⁻¹ G x / ‖·‖ (converges at the rate θ₁/θ₂);
//   - `krylov` (default): Rayleigh–Ritz on every iterate, i.e. on the Krylov space of K_σ⁻¹G from the
//     start vector (the same solves, the Lanczos rate). The basis is kept orthonormal (classical
//     Gram–Schmidt, twice) and restarted from the current Ritz vector at `max_basis` vectors. When the
//     wanted Ritz value is (nearly) multiple — a quaternionic eigenvalue in complex form, a degenerate
//     kernel — the projection of the start vector on its eigenspace is returned, which is what plain
//     inverse iteration converges to.
// Stopping: the relative residual ‖K x − θ G x‖/‖K_σ x‖ below `tolerance`, or at its roundoff floor
// ε‖K_σ‖/‖K_σ x‖, or stalled below 1e-6 (less than 10% progress in 4 iterations); or `iterations`
// steps. With `fixed_iterations`, exactly `iterations` plain steps and no test (SpinXForm: 3).
//
// Inputs: K (n×n, lower triangle of K_σ, i.e. with the shift σ already on its diagonal), G (lower
// triangle, Hermitian positive definite) or nullptr for the standard problem, solve (b ↦ K_σ⁻¹ b),
// sigma, options, x (the start vector, n; need not be normalised).
// Outputs: x (the unit eigenvector), the eigenvalue θ of the unshifted pencil, the residual and the
// iterations taken. Throws Error (Numerical) "<who>: inverse iteration broke down" when an iterate
// is zero or not finite.
// Used by the spin transformation (spin_transform.cpp) on its eigen matrix (eq. 6 and 7).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <complex>
#include <functional>

namespace spinmotor {

struct SmallestEigenpairOptions {
  double tolerance = 1e-10;       ///< relative eigen-residual at which the iteration stops
  int iterations = 50;            ///< maximum iterations (exact count when fixed_iterations)
  bool fixed_iterations = false;  ///< plain inverse iteration, exactly `iterations` steps, no test
  bool krylov = true;             ///< Rayleigh–Ritz on all iterates (ignored with fixed_iterations)
  int max_basis = 24;             ///< Krylov basis size before a restart (≥ 2)
  const char* who = "smallest_eigenpair";  ///< prefix of error messages
};

struct SmallestEigenpair {
  double eigenvalue = 0;  ///< θ of K x = θ G x (unshifted)
  double residual = 0;    ///< ‖K x − θ G x‖ / ‖K_σ x‖ at the end
  int iterations = 0;     ///< solves taken
};

template <class Scalar>
using SolveFunction =
    std::function<Eigen::Matrix<Scalar, Eigen::Dynamic, 1>(const Eigen::Matrix<Scalar, Eigen::Dynamic, 1>&)>;

/// See the header comment. Scalar: double or std::complex<double>.
template <class Scalar>
[[nodiscard]] SmallestEigenpair smallest_eigenpair(const Eigen::SparseMatrix<Scalar>& K,
                                                   const Eigen::SparseMatrix<Scalar>* G,
                                                   const SolveFunction<Scalar>& solve, double sigma,
                                                   const SmallestEigenpairOptions& options,
                                                   Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& x);

extern template SmallestEigenpair smallest_eigenpair(const Eigen::SparseMatrix<double>&,
                                                     const Eigen::SparseMatrix<double>*,
                                                     const SolveFunction<double>&, double,
                                                     const SmallestEigenpairOptions&, Eigen::VectorXd&);
extern template SmallestEigenpair smallest_eigenpair(const Eigen::SparseMatrix<std::complex<double>>&,
                                                     const Eigen::SparseMatrix<std::complex<double>>*,
                                                     const SolveFunction<std::complex<double>>&, double,
                                                     const SmallestEigenpairOptions&, Eigen::VectorXcd&);

}  // namespace spinmotor
