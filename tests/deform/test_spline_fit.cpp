// B-spline fitting of key motors (deform/bspline_fit.hpp, CGA paper §III.C eqs. 3–5): exact recovery
// of a representable motor curve (Cholesky path and pinned ends), the SVD path when AᵀA is singular,
// and the least-squares optimum against an independent dense QR solve.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <random>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/bspline_fit.hpp"
#include "spinmotor/deform/spline_basis.hpp"

namespace test_spline_fit {

using namespace spinmotor;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

std::vector<ga::Dll> random_generators(int m, unsigned seed, double scale = 0.5) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-scale, scale);
  std::vector<ga::Dll> g(m);
  for (auto& b : g)
    for (double& c : b.c) c = u(rng);
  return g;
}

/// Keys on the spline: Q_i = exp(Σ_j N_j(λ_i) B_j).
std::vector<ga::Mot> keys_on_curve(const std::vector<ga::Dll>& B, const std::vector<double>& lambda,
                                   int degree) {
  const int m = static_cast<int>(B.size());
  std::vector<ga::Mot> Q;
  for (double t : lambda) {
    const VectorXd w = spline_weights(SplineBasis::BSpline, m, degree, t);
    ga::Dll acc;
    for (int j = 0; j < m; ++j) acc += w[j] * B[j];
    Q.push_back(ga::exp(acc));
  }
  return Q;
}

std::vector<double> uniform(int n) {
  std::vector<double> t(n);
  for (int i = 0; i < n; ++i) t[i] = static_cast<double>(i) / (n - 1);
  return t;
}

double max_diff(const std::vector<ga::Dll>& a, const std::vector<ga::Dll>& b) {
  double e = 0;
  for (std::size_t j = 0; j < a.size(); ++j)
    for (int c = 0; c < 6; ++c) e = std::max(e, std::abs(a[j].c[c] - b[j].c[c]));
  return e;
}

}  // namespace

TEST_CASE("B-spline fit recovers a motor curve the spline can represent", "[spline][fit]") {
  for (int degree : {2, 3}) {
    for (int m : {4, 6, 8}) {
      if (m < degree + 1) continue;
      CAPTURE(degree, m);
      const auto B = random_generators(m, 17 + m);
      const auto lambda = uniform(3 * m);
      const auto Q = keys_on_curve(B, lambda, degree);
      const BSplineFit fit = fit_bspline_motors(Q, lambda, {.controls = m, .degree = degree});
      CHECK_FALSE(fit.used_svd);
      CHECK(fit.residual < 1e-12);
      CHECK(max_diff(fit.generators, B) < 1e-10);
      // Pinned ends: the same curve, ends exact.
      const BSplineFit pinned =
          fit_bspline_motors(Q, lambda, {.controls = m, .degree = degree, .interpolate_ends = true});
      CHECK(max_diff(pinned.generators, B) < 1e-10);
      for (int c = 0; c < 6; ++c) {
        CHECK(pinned.generators[0].c[c] == Approx(ga::log(Q.front()).c[c]).margin(1e-14));
        CHECK(pinned.generators[m - 1].c[c] == Approx(ga::log(Q.back()).c[c]).margin(1e-14));
      }
    }
  }
}

TEST_CASE("B-spline fit falls back to the SVD when AᵀA is singular", "[spline][fit]") {
  // 3 keys for 6 controls: AᵀA has rank 3. The minimum-norm solution still interpolates the keys.
  const auto B = random_generators(6, 3);
  const std::vector<double> lambda = {0.0, 0.4, 1.0};
  const auto Q = keys_on_curve(B, lambda, 3);
  const BSplineFit fit = fit_bspline_motors(Q, lambda, {.controls = 6, .degree = 3});
  CHECK(fit.used_svd);
  CHECK(fit.rcond < 1e-12);
  CHECK(fit.residual < 1e-12);
}

TEST_CASE("B-spline fit is the least-squares optimum (independent QR solve)", "[spline][fit]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  const int n = 25, m = 5;
  std::vector<double> lambda(n);
  std::vector<ga::Mot> Q(n);
  MatrixXd A(n, m), L(n, 6);
  for (int i = 0; i < n; ++i) {
    lambda[i] = std::pow(static_cast<double>(i) / (n - 1), 1.3);  // non-uniform parameters
    ga::Dll b;
    for (int c = 0; c < 6; ++c) b.c[c] = std::sin(3.0 * lambda[i] + c) + u(rng);  // noisy, not on a spline
    Q[i] = ga::exp(b);
    const ga::Dll lb = ga::log(Q[i]);
    for (int c = 0; c < 6; ++c) L(i, c) = lb.c[c];
    A.row(i) = spline_weights(SplineBasis::BSpline, m, 3, lambda[i]).transpose();
  }
  const BSplineFit fit = fit_bspline_motors(Q, lambda, {.controls = m, .degree = 3});
  const MatrixXd R = A.colPivHouseholderQr().solve(L);
  for (int j = 0; j < m; ++j)
    for (int c = 0; c < 6; ++c) CHECK(fit.generators[j].c[c] == Approx(R(j, c)).margin(1e-11));
  CHECK(fit.residual == Approx((A * R - L).rowwise().norm().maxCoeff()).epsilon(1e-9));
  CHECK(fit.residual > 0.1);  // the data is not on the curve
}

TEST_CASE("B-spline fit rejects bad input", "[spline][fit][errors]") {
  const auto Q = keys_on_curve(random_generators(4, 1), uniform(6), 3);
  CHECK_THROWS_WITH(fit_bspline_motors(Q, std::vector<double>(5, 0.5), {}),
                    Catch::Contains("5 parameters for 6 keys"));
  std::vector<double> bad = uniform(6);
  bad[2] = 1.5;
  CHECK_THROWS_WITH(fit_bspline_motors(Q, bad, {}), Catch::Contains("parameter 2 is 1.5"));
  CHECK_THROWS_WITH(fit_bspline_motors(Q, uniform(6), {.controls = 3}), Catch::Contains("at least 4 keys"));
  std::vector<double> inner = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  CHECK_THROWS_WITH(fit_bspline_motors(Q, inner, {.interpolate_ends = true}),
                    Catch::Contains("λ = 0 and λ = 1"));
}

}  // namespace test_spline_fit
