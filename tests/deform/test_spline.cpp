// Spline-aligned deformation (deform/spline_basis.hpp, spline_deformer.hpp; CGA paper §III):
// the bases against independent formulas (recursive Cox–de Boor, Bernstein, the paper's Lagrange
// weights), partition of unity, key reproduction at the nodes each basis interpolates (on the mesh,
// through the harmonic parameter), the translation closed form, and the rest-pose binding.
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/spline_deformer.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace test_spline {

using namespace spinmotor;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Eigen::VectorXi;

namespace {

/// Textbook recursive Cox–de Boor on an explicit knot vector (independent of the library's A2.2).
double cox_de_boor(const std::vector<double>& U, int j, int d, double t) {
  if (d == 0) {
    // Half-open spans; t = 1 belongs to the last non-empty span.
    if (t == U.back()) return (U[j] < t && U[j + 1] == t) ? 1.0 : 0.0;
    return (U[j] <= t && t < U[j + 1]) ? 1.0 : 0.0;
  }
  double a = 0, b = 0;
  if (U[j + d] > U[j]) a = (t - U[j]) / (U[j + d] - U[j]) * cox_de_boor(U, j, d - 1, t);
  if (U[j + d + 1] > U[j + 1])
    b = (U[j + d + 1] - t) / (U[j + d + 1] - U[j + 1]) * cox_de_boor(U, j + 1, d - 1, t);
  return a + b;
}

std::vector<double> clamped_knots(int n, int d) {
  std::vector<double> U;
  for (int i = 0; i <= d; ++i) U.push_back(0.0);
  for (int i = 1; i < n - d; ++i) U.push_back(static_cast<double>(i) / (n - d));
  for (int i = 0; i <= d; ++i) U.push_back(1.0);
  return U;
}

double binomial(int n, int k) {
  double c = 1;
  for (int i = 1; i <= k; ++i) c = c * (n - k + i) / i;
  return c;
}

struct BasisCase {
  SplineBasis basis;
  int keys, degree;
};
const BasisCase kCases[] = {
    {SplineBasis::Linear, 2, 0},  {SplineBasis::Linear, 5, 0},  {SplineBasis::Quadratic, 3, 0},
    {SplineBasis::Bezier, 4, 0},  {SplineBasis::Bezier, 6, 0},  {SplineBasis::BSpline, 5, 1},
    {SplineBasis::BSpline, 6, 3}, {SplineBasis::BSpline, 4, 3}, {SplineBasis::BSpline, 9, 4}};

constexpr int kRings = 41, kSides = 24;  // ring k is at λ = k/40 exactly (λ = z/L on an open tube)
constexpr double kLength = 4.0;

Handle ring(const std::string& name, int k) {
  Handle h{name, VectorXi(kSides)};
  for (int j = 0; j < kSides; ++j) h.vertices[j] = k * kSides + j;
  return h;
}

ga::Mot screw(const Vector3d& axis, double degrees, const Vector3d& about, const Vector3d& t) {
  const ga::Rot r = ga::rotor(axis, degrees * M_PI / 180.0);
  return ga::motor(r, ga::translator(about + t - ga::rotate(r, about)));
}

std::vector<ga::Mot> random_keys(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<ga::Mot> k;
  for (int j = 0; j < n; ++j)
    k.push_back(screw({u(rng), u(rng), u(rng)}, 120 * u(rng), {0, 0, kLength * j / std::max(1, n - 1)},
                      {u(rng), u(rng), u(rng)}));
  return k;
}

}  // namespace

TEST_CASE("spline bases: partition of unity and independent formulas", "[spline][basis]") {
  for (const BasisCase& c : kCases) {
    CAPTURE(to_string(c.basis), c.keys, c.degree);
    for (int s = 0; s <= 200; ++s) {
      const double t = s / 200.0;
      const VectorXd w = spline_weights(c.basis, c.keys, c.degree, t);
      CHECK(std::abs(w.sum() - 1.0) < 1e-14);
      VectorXd ref(c.keys);
      for (int j = 0; j < c.keys; ++j) {
        switch (c.basis) {
          case SplineBasis::Linear: {  // hat functions on nodes j/(n−1)
            const double h = 1.0 / (c.keys - 1);
            ref[j] = std::max(0.0, 1.0 - std::abs(t - j * h) / h);
            break;
          }
          case SplineBasis::Quadratic: {  // Lagrange polynomials on 0, ½, 1
            const double x[3] = {0, 0.5, 1};
            double l = 1;
            for (int i = 0; i < 3; ++i)
              if (i != j) l *= (t - x[i]) / (x[j] - x[i]);
            ref[j] = l;
            break;
          }
          case SplineBasis::Bezier:
            ref[j] = binomial(c.keys - 1, j) * std::pow(t, j) * std::pow(1 - t, c.keys - 1 - j);
            break;
          case SplineBasis::BSpline:
            ref[j] = cox_de_boor(clamped_knots(c.keys, c.degree), j, c.degree, t);
            break;
        }
      }
      CHECK((w - ref).cwiseAbs().maxCoeff() < 1e-13);
      if (c.basis != SplineBasis::Quadratic) CHECK(w.minCoeff() >= 0.0);
    }
  }
  // The paper's quadratic weights, literally (§III.B).
  const double t = 0.3;
  const VectorXd w = spline_weights(SplineBasis::Quadratic, 3, 0, t);
  CHECK(w[0] == Approx(2 * t * t - 3 * t + 1).epsilon(1e-15));
  CHECK(w[1] == Approx(-4 * t * t + 4 * t).epsilon(1e-15));
  CHECK(w[2] == Approx(2 * t * t - t).epsilon(1e-15));
}

TEST_CASE("spline bases interpolate their keys at their nodes", "[spline][basis]") {
  for (const BasisCase& c : kCases) {
    CAPTURE(to_string(c.basis), c.keys, c.degree);
    for (auto [j, t] : spline_interpolation_nodes(c.basis, c.keys, c.degree)) {
      const VectorXd w = spline_weights(c.basis, c.keys, c.degree, t);
      VectorXd e = VectorXd::Zero(c.keys);
      e[j] = 1.0;
      CHECK((w - e).cwiseAbs().maxCoeff() < 1e-15);
    }
  }
}

TEST_CASE("spline deformer reproduces its key motors at the nodes it interpolates", "[spline][deform]") {
  const Mesh m = tube(0.5, kLength, kRings, kSides, false);
  const std::vector<Handle> h = {ring("from", 0), ring("to", kRings - 1)};
  for (const BasisCase& c : kCases) {
    for (HarmonicWeights hw : {HarmonicWeights::MeanValue, HarmonicWeights::Cotangent}) {
      CAPTURE(to_string(c.basis), c.keys, c.degree, to_string(hw));
      auto d =
          SplineDeformer::bind(m, h, {.basis = c.basis, .degree = c.degree, .keys = c.keys, .weights = hw});
      const auto keys = random_keys(c.keys, 11);
      MatrixXd V;
      d.pose(keys, V);
      for (auto [j, t] : spline_interpolation_nodes(c.basis, c.keys, c.degree)) {
        const int k = static_cast<int>(std::lround(t * (kRings - 1)));
        REQUIRE(std::abs(k - t * (kRings - 1)) < 1e-12);  // the node is a ring of the tube
        double err = 0;
        for (int s = 0; s < kSides; ++s) {
          const int v = k * kSides + s;
          err = std::max(err, (V.row(v).transpose() - ga::transform(keys[j], m.V.row(v).transpose())).norm());
        }
        CAPTURE(j, t);
        CHECK(err < 1e-10);  // λ at the ring is k/40 to solver precision (~1e-13)
      }
    }
  }
}

TEST_CASE("spline deformer: identity, translations, rest binding", "[spline][deform]") {
  const Mesh m = tube(0.5, kLength, kRings, kSides, true);
  const std::vector<Handle> h = {ring("from", 0), ring("to", kRings - 1)};
  const SplineDeformer::Options o{.basis = SplineBasis::BSpline, .degree = 3, .keys = 6};
  auto d = SplineDeformer::bind(m, h, o);
  MatrixXd V;
  d.pose(std::vector<ga::Mot>(6, ga::Mot(1, 0, 0, 0, 0, 0, 0, 0)), V);
  CHECK((V - m.V).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(d.parameter().minCoeff() >= -1e-13);
  CHECK(d.parameter().maxCoeff() <= 1 + 1e-13);

  // Translations: V' = V + Σ_j W_j(λ_i) t_j.
  MatrixXd T = MatrixXd::Random(6, 3);
  std::vector<ga::Mot> keys;
  for (int j = 0; j < 6; ++j)
    keys.push_back(ga::motor(ga::Rot(1, 0, 0, 0), ga::translator(T.row(j).transpose())));
  d.pose(keys, V);
  const MatrixXd expected = m.V + MatrixXd(d.field().weights()) * T;
  CHECK((V - expected).cwiseAbs().maxCoeff() < 1e-12);

  // §III.A: bound to non-identity rest keys, posing with them gives the rest mesh back.
  SplineDeformer::Options ob = o;
  ob.rest_keys = random_keys(6, 5);
  auto db = SplineDeformer::bind(m, h, ob);
  db.pose(ob.rest_keys, V);
  CHECK((V - m.V).cwiseAbs().maxCoeff() < 1e-12);
}

TEST_CASE("spline deformer rejects bad bases and handles", "[spline][errors]") {
  const Mesh m = tube(0.5, kLength, kRings, kSides, false);
  const std::vector<Handle> h = {ring("from", 0), ring("to", kRings - 1)};
  CHECK_THROWS_WITH(SplineDeformer::bind(m, h, {.basis = SplineBasis::Quadratic, .keys = 4}),
                    Catch::Contains("exactly 3 keys"));
  CHECK_THROWS_WITH(SplineDeformer::bind(m, h, {.basis = SplineBasis::BSpline, .degree = 3, .keys = 3}),
                    Catch::Contains("at least 4 keys"));
  const std::vector<Handle> one = {ring("from", 0)};
  CHECK_THROWS_WITH(SplineDeformer::bind(m, one, {}), Catch::Contains("exactly two handles"));
}

}  // namespace test_spline
