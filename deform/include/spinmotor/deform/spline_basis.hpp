#pragma once
// Basis functions W_j(λ) of the spline-aligned deformation (CGA paper §III, eq. 1 and §III.B). For
// every basis the weights of the n keys form a partition of unity at each λ ∈ [0, 1] (λ outside is
// clamped).
//
//   Linear     n ≥ 2 keys at uniform nodes λ_j = j/(n−1), piecewise-linear hat functions; n = 2 is the
//              paper's w_1 = 1 − λ, w_2 = λ (Fig. 2). Interpolates every key at its node.
//   Quadratic  n = 3: the paper's quadratic Lagrange weights w_1 = 2λ² − 3λ + 1, w_2 = −4λ² + 4λ,
//              w_3 = 2λ² − λ (Fig. 3; w_1, w_3 are negative inside). Interpolates at 0, ½, 1.
//   Bezier     n ≥ 2: Bernstein polynomials of degree n − 1 (n = 4: the cubic Bézier),
//              w_j = C(n−1, j) λ^j (1−λ)^(n−1−j). Interpolates the first key at 0 and the last at 1.
//   BSpline    degree d ≥ 1, n ≥ d + 1: clamped uniform B-spline N_{j,d}(λ) (Cox–de Boor) on the
//              knot vector of d+1 zeros, the interior knots i/(n−d) (i = 1..n−d−1) and d+1 ones.
//              Local support (at most d+1 non-zero weights), non-negative; interpolates the first key
//              at 0 and the last at 1 (d = 1: every key at j/(n−1), like Linear).
#include <Eigen/Core>
#include <utility>
#include <vector>

#include "spinmotor/core/option_names.hpp"

namespace spinmotor {

enum class SplineBasis { Linear, Quadratic, Bezier, BSpline };
inline constexpr OptionNames<SplineBasis, 4> kSplineBasisNames{"basis",
                                                               {{{SplineBasis::Linear, "linear"},
                                                                 {SplineBasis::Quadratic, "quadratic"},
                                                                 {SplineBasis::Bezier, "bezier"},
                                                                 {SplineBasis::BSpline, "bspline"}}}};
constexpr const auto& option_names(SplineBasis) { return kSplineBasisNames; }

/// "linear" / "quadratic" / "bezier" / "bspline".
const char* to_string(SplineBasis basis);

/// Throws Error unless (basis, keys, degree) is valid as listed above (degree is read only for
/// BSpline; degree ≤ 15).
void check_spline(SplineBasis basis, int keys, int degree);

/// Knot j of the clamped uniform knot vector of n controls and degree d on [0, 1]: 0 for j ≤ d, 1 for
/// j ≥ n, (j − d)/(n − d) between.
[[nodiscard]] double clamped_knot(int j, int n, int d) noexcept;

/// The d + 1 non-zero clamped uniform B-spline basis functions N_{first..first+d, d}(t) at t ∈ [0, 1]
/// (Cox–de Boor, Piegl & Tiller, The NURBS Book, A2.2) into N[0..d]; returns `first`. t = 1 belongs
/// to the last span. Inputs: n ≥ d + 1, 1 ≤ d ≤ 31. Shared by the spline deformer and the FFD lattice.
int bspline_nonzero(int n, int d, double t, double* N) noexcept;

/// Inputs: basis, n keys, degree (BSpline), λ. Output: w[0..n) (Σ w = 1). No allocation.
void spline_weights(SplineBasis basis, int keys, int degree, double lambda, double* w);

/// Same, returned as a vector of n weights.
Eigen::VectorXd spline_weights(SplineBasis basis, int keys, int degree, double lambda);

/// The (key index, λ) pairs at which the basis interpolates its keys (W_j(λ) = 1 there).
std::vector<std::pair<int, double>> spline_interpolation_nodes(SplineBasis basis, int keys, int degree);

}  // namespace spinmotor
