#include "spinmotor/deform/spline_basis.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "spinmotor/core/error.hpp"

namespace spinmotor {

const char* to_string(SplineBasis basis) {
  switch (basis) {
    case SplineBasis::Linear:
      return "linear";
    case SplineBasis::Quadratic:
      return "quadratic";
    case SplineBasis::Bezier:
      return "bezier";
    case SplineBasis::BSpline:
    default:
      return "bspline";
  }
}

void check_spline(SplineBasis basis, int keys, int degree) {
  const std::string who = std::string("spline (") + to_string(basis) + " basis): ";
  switch (basis) {
    case SplineBasis::Linear:
    case SplineBasis::Bezier:
      if (keys < 2) throw Error(who + "needs at least 2 keys, got " + std::to_string(keys));
      if (basis == SplineBasis::Bezier && keys > 16)
        throw Error(who + "at most 16 keys (degree 15), got " + std::to_string(keys));
      return;
    case SplineBasis::Quadratic:
      if (keys != 3) throw Error(who + "needs exactly 3 keys, got " + std::to_string(keys));
      return;
    case SplineBasis::BSpline:
      if (degree < 1 || degree > 15)
        throw Error(who + "degree must be in [1, 15], got " + std::to_string(degree));
      if (keys < degree + 1)
        throw Error(who + "degree " + std::to_string(degree) + " needs at least " +
                    std::to_string(degree + 1) + " keys, got " + std::to_string(keys));
      return;
  }
}

namespace {

/// The basis functions of all n controls at t (zero outside the d + 1 supporting ones).
void bspline(int n, int d, double t, double* w) {
  std::fill(w, w + n, 0.0);
  double N[32];
  const int first = bspline_nonzero(n, d, t, N);
  for (int r = 0; r <= d; ++r) w[first + r] = N[r];
}

}  // namespace

double clamped_knot(int j, int n, int d) noexcept {
  if (j <= d) return 0.0;
  if (j >= n) return 1.0;
  return static_cast<double>(j - d) / (n - d);
}

int bspline_nonzero(int n, int d, double t, double* N) noexcept {
  // Span k with U[k] ≤ t < U[k+1], k ∈ [d, n−1]; t = 1 belongs to the last span.
  int k = t >= 1.0 ? n - 1 : d + static_cast<int>(std::floor(t * (n - d)));
  k = std::clamp(k, d, n - 1);
  double left[32], right[32];
  N[0] = 1.0;
  for (int j = 1; j <= d; ++j) {
    left[j] = t - clamped_knot(k + 1 - j, n, d);
    right[j] = clamped_knot(k + j, n, d) - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double tmp = N[r] / (right[r + 1] + left[j - r]);
      N[r] = saved + right[r + 1] * tmp;
      saved = left[j - r] * tmp;
    }
    N[j] = saved;
  }
  return k - d;
}

void spline_weights(SplineBasis basis, int n, int degree, double lambda, double* w) {
  const double t = std::clamp(lambda, 0.0, 1.0);
  switch (basis) {
    case SplineBasis::Linear: {  // §III.B, Fig. 2 (n = 2); hat functions on uniform nodes for n > 2
      std::fill(w, w + n, 0.0);
      const double s = t * (n - 1);
      const int j = std::min(static_cast<int>(std::floor(s)), n - 2);
      const double f = s - j;
      w[j] = 1.0 - f;
      w[j + 1] = f;
      return;
    }
    case SplineBasis::Quadratic:  // §III.B: quadratic Lagrange weights
      w[0] = 2.0 * t * t - 3.0 * t + 1.0;
      w[1] = -4.0 * t * t + 4.0 * t;
      w[2] = 2.0 * t * t - t;
      return;
    case SplineBasis::Bezier: {  // Bernstein polynomials of degree n − 1
      const int d = n - 1;
      double c = 1.0;  // C(d, j)
      for (int j = 0; j <= d; ++j) {
        w[j] = c * std::pow(t, j) * std::pow(1.0 - t, d - j);
        c = c * (d - j) / (j + 1);
      }
      return;
    }
    case SplineBasis::BSpline:
    default:
      bspline(n, degree, t, w);  // §III.B: w_j = N_{j,d}(λ)
      return;
  }
}

Eigen::VectorXd spline_weights(SplineBasis basis, int keys, int degree, double lambda) {
  check_spline(basis, keys, degree);
  Eigen::VectorXd w(keys);
  spline_weights(basis, keys, degree, lambda, w.data());
  return w;
}

std::vector<std::pair<int, double>> spline_interpolation_nodes(SplineBasis basis, int keys, int degree) {
  check_spline(basis, keys, degree);
  std::vector<std::pair<int, double>> nodes;
  if (basis == SplineBasis::Linear || (basis == SplineBasis::BSpline && degree == 1)) {
    for (int j = 0; j < keys; ++j) nodes.emplace_back(j, static_cast<double>(j) / (keys - 1));
  } else if (basis == SplineBasis::Quadratic) {
    nodes = {{0, 0.0}, {1, 0.5}, {2, 1.0}};
  } else {
    nodes = {{0, 0.0}, {keys - 1, 1.0}};
  }
  return nodes;
}

}  // namespace spinmotor
