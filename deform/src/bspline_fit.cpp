#include "spinmotor/deform/bspline_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <cmath>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/motor_blend_field.hpp"
#include "spinmotor/deform/spline_basis.hpp"

namespace spinmotor {

BSplineFit fit_bspline_motors(std::span<const ga::Mot> keys, std::span<const double> lambda,
                              const BSplineFitOptions& options) {
  const int n = static_cast<int>(keys.size()), m = options.controls, d = options.degree;
  if (n == 0) throw Error("fit_bspline_motors: needs at least one key");
  if (lambda.size() != keys.size()) {
    std::ostringstream s;
    s << "fit_bspline_motors: " << lambda.size() << " parameters for " << n << " keys";
    throw Error(s.str());
  }
  check_spline(SplineBasis::BSpline, m, d);
  // Q: the key logarithms (eq. 4), A_ij = N_j(λ_i).
  Eigen::MatrixXd Q(n, 6), A(n, m);
  int first = -1, last = -1;
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(lambda[i]) || lambda[i] < 0.0 || lambda[i] > 1.0) {
      std::ostringstream s;
      s << "fit_bspline_motors: parameter " << i << " is " << lambda[i] << ", outside [0, 1]";
      throw Error(s.str());
    }
    const ga::Dll b = ga::log(checked_unit_motor(keys[i], "fit_bspline_motors: key " + std::to_string(i)));
    for (int c = 0; c < 6; ++c) Q(i, c) = b.c[c];
    A.row(i) = spline_weights(SplineBasis::BSpline, m, d, lambda[i]).transpose();
    if (lambda[i] == 0.0 && first < 0) first = i;
    if (lambda[i] == 1.0) last = i;
  }
  // Columns that are fitted (all, or the interior ones when the ends are pinned).
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(m, 6);
  int j0 = 0, j1 = m;  // free columns [j0, j1)
  Eigen::MatrixXd rhs = Q;
  if (options.interpolate_ends) {
    if (first < 0 || last < 0)
      throw Error("fit_bspline_motors: interpolate_ends needs keys at λ = 0 and λ = 1");
    R.row(0) = Q.row(first);
    R.row(m - 1) = Q.row(last);
    rhs -= A.col(0) * R.row(0) + A.col(m - 1) * R.row(m - 1);
    j0 = 1;
    j1 = m - 1;
  }
  BSplineFit fit;
  if (j1 > j0) {
    const Eigen::MatrixXd Af = A.middleCols(j0, j1 - j0);
    const Eigen::MatrixXd AtA = Af.transpose() * Af;  // eq. (5)
    Eigen::LLT<Eigen::MatrixXd> llt(AtA);
    fit.rcond = llt.info() == Eigen::Success ? llt.rcond() : 0.0;
    if (fit.rcond >= options.min_rcond) {
      R.middleRows(j0, j1 - j0) = llt.solve(Af.transpose() * rhs);  // six right-hand sides at once
    } else {
      fit.used_svd = true;  // ill-conditioned knots (§III.C): minimum-norm least squares by SVD
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(Af, Eigen::ComputeThinU | Eigen::ComputeThinV);
      R.middleRows(j0, j1 - j0) = svd.solve(rhs);
    }
  } else {
    fit.rcond = 1.0;
  }
  if (!R.allFinite()) throw numerical_error("fit_bspline_motors: the fitted generators are not finite");
  fit.residual = (A * R - Q).rowwise().norm().maxCoeff();
  fit.generators.resize(m);
  fit.controls.resize(m);
  for (int j = 0; j < m; ++j) {
    for (int c = 0; c < 6; ++c) fit.generators[j].c[c] = R(j, c);
    fit.controls[j] = ga::exp(fit.generators[j]);
  }
  return fit;
}

}  // namespace spinmotor
