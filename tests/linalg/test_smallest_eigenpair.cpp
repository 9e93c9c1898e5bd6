// smallest_eigenpair (linalg/smallest_eigenpair.hpp) on matrices with closed-form spectra: the path
// graph with both ends grounded, tridiag(−1, 2, −1) of size n − 1, has the eigenvalues
// 2 − 2cos(kπ/n), k = 1 … n − 1, with eigenvectors sin(kπj/n); the free path graph's Laplacian has
// 0 (constants) and 2 − 2cos(kπ/n).
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/linalg/smallest_eigenpair.hpp"

namespace test_smallest_eigenpair {

using namespace spinmotor;
using cd = std::complex<double>;

namespace {

// Lower triangle of tridiag(−1, 2, −1) (m×m) + sigma·I, or of the free path Laplacian when `free`; the
// complex variant is D T Dᴴ with D = diag(e^{i·0.4j}) (unitary: the same spectrum).
template <class Scalar>
Eigen::SparseMatrix<Scalar> path(int m, double sigma, bool free) {
  std::vector<Eigen::Triplet<Scalar>> t;
  for (int j = 0; j < m; ++j) {
    const double d = free ? (j == 0 || j == m - 1 ? 1.0 : 2.0) : 2.0;
    t.emplace_back(j, j, Scalar(d + sigma));
    if (j + 1 < m) {
      Scalar off(-1.0);
      if constexpr (!std::is_same_v<Scalar, double>)
        off = -std::polar(1.0, 0.4 * (j + 1)) * std::polar(1.0, -0.4 * j);
      t.emplace_back(j + 1, j, off);
    }
  }
  Eigen::SparseMatrix<Scalar> A(m, m);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

template <class Scalar>
void check_grounded_path(bool krylov, bool generalized) {
  using Vec = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  const int n = 60, m = n - 1;
  const Eigen::SparseMatrix<Scalar> K = path<Scalar>(m, 0.0, false);
  BasicCholeskySolver<Scalar> chol;
  chol.compute(K);
  const SolveFunction<Scalar> solve = [&](const Vec& b) -> Vec { return chol.solve(b); };
  // G = 2I halves every eigenvalue of the pencil.
  Eigen::SparseMatrix<Scalar> G(m, m);
  G.setIdentity();
  G *= Scalar(2.0);
  SmallestEigenpairOptions o;
  o.krylov = krylov;
  o.iterations = 2000;
  o.tolerance = 1e-10;
  Vec x = Vec::Ones(m);
  const SmallestEigenpair r = smallest_eigenpair<Scalar>(K, generalized ? &G : nullptr, solve, 0.0, o, x);
  const double lambda1 = (2.0 - 2.0 * std::cos(M_PI / n)) / (generalized ? 2.0 : 1.0);
  INFO("krylov " << krylov << ", generalized " << generalized << ", iterations " << r.iterations);
  CHECK(std::abs(r.eigenvalue - lambda1) < 1e-9 * lambda1);
  CHECK(r.residual < 1e-9);
  CHECK(std::abs(x.norm() - 1.0) < 1e-12);
  // The eigenvector is sin(πj/n) (up to the unitary D and a phase): compare moduli.
  Eigen::VectorXd s(m);
  for (int j = 0; j < m; ++j) s[j] = std::sin(M_PI * (j + 1) / n);
  s.normalize();
  CHECK((x.cwiseAbs() - s).cwiseAbs().maxCoeff() < 1e-6);
  if (krylov) CHECK(r.iterations < 60);  // the Lanczos rate: far fewer than plain inverse iteration
}

}  // namespace

TEST_CASE("smallest_eigenpair: grounded path graph, λ₁ = 2 − 2cos(π/n), real and complex, both methods",
          "[solvers][eigen]") {
  for (bool krylov : {true, false})
    for (bool generalized : {false, true}) {
      check_grounded_path<double>(krylov, generalized);
      check_grounded_path<cd>(krylov, generalized);
    }
}

TEST_CASE("smallest_eigenpair: a shifted singular Laplacian returns its zero eigenvalue, the constants",
          "[solvers][eigen]") {
  const int n = 40;
  const double sigma = 1e-8;
  const Eigen::SparseMatrix<double> Ks = path<double>(n, sigma, true);  // L + σI
  CholeskySolver chol;
  chol.compute(Ks);
  const SolveFunction<double> solve = [&](const Eigen::VectorXd& b) -> Eigen::VectorXd {
    return chol.solve(b);
  };
  Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  const SmallestEigenpair r = smallest_eigenpair<double>(Ks, nullptr, solve, sigma, {}, x);
  CHECK(std::abs(r.eigenvalue) < 1e-10);
  CHECK((x.cwiseAbs().array() - 1.0 / std::sqrt(n)).abs().maxCoeff() < 1e-8);
  // The second eigenvalue, 2 − 2cos(π/n), bounds the error of plain inverse iteration after k steps:
  // fixed_iterations runs exactly k.
  SmallestEigenpairOptions fixed;
  fixed.fixed_iterations = true;
  fixed.iterations = 3;
  Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  CHECK(smallest_eigenpair<double>(Ks, nullptr, solve, sigma, fixed, y).iterations == 3);
}

TEST_CASE("smallest_eigenpair: a solve that returns zero is reported", "[solvers][eigen]") {
  const Eigen::SparseMatrix<double> K = path<double>(5, 0.0, false);
  const SolveFunction<double> zero = [](const Eigen::VectorXd& b) -> Eigen::VectorXd {
    return Eigen::VectorXd::Zero(b.size());
  };
  Eigen::VectorXd x = Eigen::VectorXd::Ones(5);
  SmallestEigenpairOptions o;
  o.krylov = false;
  o.who = "test";
  CHECK_THROWS_WITH(smallest_eigenpair<double>(K, nullptr, zero, 0.0, o, x),
                    Catch::Contains("test: inverse iteration broke down"));
  Eigen::VectorXd wrong = Eigen::VectorXd::Ones(4);
  CHECK_THROWS_WITH(smallest_eigenpair<double>(K, nullptr, zero, 0.0, o, wrong),
                    Catch::Contains("same size"));
}

}  // namespace test_smallest_eigenpair
