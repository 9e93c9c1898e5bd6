#pragma once
// Least-squares fit of B-spline control motors to key motors (CGA paper §III.C, eqs. 3–5).
//
// Given keys Q_i at parameters λ_i (i = 0..n−1), find m control motors R_j such that
// Q_i ≈ exp(Σ_j N_j(λ_i) log R_j) (eq. 3), N_j the clamped uniform B-spline basis of spline_basis.hpp
// (the one SplineDeformer evaluates). With A_ij = N_j(λ_i) (n×m), Q the n×6 logarithms of the keys
// (bivector components e12, e31, e23, e1∞, e2∞, e3∞) and R the m×6 unknown generators, eq. (4) is
// A R = Q and eq. (5) the normal equations (AᵀA) R = AᵀQ: one Cholesky factorization of AᵀA, six
// right-hand sides. When AᵀA is singular or ill-conditioned (reciprocal condition number below
// `min_rcond`, e.g. fewer keys than controls or keys missing the support of a control) the system is
// solved by the SVD of A instead (minimum-norm least squares).
//
// interpolate_ends: the first and last controls are pinned to the keys at λ = 0 and λ = 1 (which must
// exist): the spline then passes exactly through the end keys (a clamped B-spline's ends are its end
// controls), and only the interior controls are fitted (same equations on the remaining columns).
// The fit is exact (residual 0) whenever the key logarithms lie on a B-spline curve of this basis.
//
// The result is returned as generators B_j = log R_j (feed SplineDeformer::pose_generators) and as
// motors exp(B_j).
#include <span>
#include <vector>

#include "spinmotor/ga.hpp"

namespace spinmotor {

struct BSplineFitOptions {
  int controls = 4;               ///< m ≥ degree + 1
  int degree = 3;                 ///< the paper fits cubic B-splines
  bool interpolate_ends = false;  ///< pin R_0 = Q(λ=0), R_{m−1} = Q(λ=1)
  double min_rcond = 1e-12;       ///< below this (reciprocal condition of AᵀA), use the SVD
};

struct BSplineFit {
  std::vector<ga::Dll> generators;  ///< m generators B_j = log R_j
  std::vector<ga::Mot> controls;    ///< m motors R_j = exp(B_j)
  bool used_svd = false;            ///< true when AᵀA was too ill-conditioned for Cholesky
  double rcond = 0;                 ///< reciprocal condition estimate of the (free part of) AᵀA
  double residual = 0;  ///< max_i |Σ_j N_j(λ_i) B_j − log Q_i| (Euclidean norm of 6 components)
};

/// Inputs: n ≥ 1 unit key motors, their n parameters λ_i ∈ [0, 1], options. Output: the fit.
/// Throws Error on mismatched sizes, λ outside [0, 1] or not finite, a non-unit key, bad
/// controls/degree, or interpolate_ends without keys at λ = 0 and λ = 1.
BSplineFit fit_bspline_motors(std::span<const ga::Mot> keys, std::span<const double> lambda,
                              const BSplineFitOptions& options);

}  // namespace spinmotor
