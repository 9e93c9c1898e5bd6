// Shape snap study (issue 9, "--mode shape", library level only): extrude from the rest mesh toward the
// edit's half-density h* (Le Folgoc extrusion, curvature_spin_flow.hpp) and measure how much of a large
// bend survives, next to the edit's own Q. The sausage and the bend are those of test_snap.cpp.
// Measured (bend of the edit 59.9° by this end-slab measure): 4 steps, α = 0.05: 40.3° kept (67%),
// Q_mean 1.013 (edit 1.149), RMS to the edit 2.3% of the diagonal; with the area constraint ε = 0.5:
// 36.3° (61%), Q_mean 1.018. α = 0.005, α = 0.5 or 12 steps: 57–68%: the issue's ≥ 90% is NOT reached
// (the bend's h* is not the half-density of any conformal image of the rest sausage).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/curvature_spin_flow.hpp"

namespace test_shape_snap {

using namespace spinmotor;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::Vector3d;

namespace {

Mesh sausage() {
  Mesh m = icosphere(4);
  m.V.col(2) *= 3.0;
  return m;
}

MatrixXd bend(const MatrixXd& V, double degrees) {
  const double R = 6.0 / (degrees * M_PI / 180.0);
  MatrixXd out = V;
  for (Index i = 0; i < V.rows(); ++i) {
    const double phi = V(i, 2) / R, x = V(i, 0);
    out(i, 0) = R * (1.0 - std::cos(phi)) + x * std::cos(phi);
    out(i, 2) = R * std::sin(phi) - x * std::sin(phi);
  }
  return out;
}

double bend_angle(const MatrixXd& rest, const MatrixXd& V) {
  Vector3d c[4] = {Vector3d::Zero(), Vector3d::Zero(), Vector3d::Zero(), Vector3d::Zero()};
  int k[4] = {0, 0, 0, 0};
  for (Index i = 0; i < rest.rows(); ++i) {
    const double z = rest(i, 2);
    const int s = z <= -2 ? 0 : z <= -1 ? 1 : z >= 2 ? 3 : z >= 1 ? 2 : -1;
    if (s >= 0) c[s] += V.row(i).transpose(), ++k[s];
  }
  for (int s = 0; s < 4; ++s) c[s] /= k[s];
  const Vector3d a = (c[0] - c[1]).normalized(), b = (c[3] - c[2]).normalized();
  return 180.0 - std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace

TEST_CASE("shape snap of a 90-degree bent sausage: bend kept, Q_mean, RMS to the edit", "[lefolgoc][snap]") {
  const Mesh m = sausage();
  const MatrixXd edit = bend(m.V, 90.0);
  const double a_edit = bend_angle(m.V, edit);
  const double q_edit = quasi_conformal_summary(m.V, m.F, edit).q_mean;
  for (const double eps : {0.0, 0.5}) {
    CurvatureSpinOptions o{.alpha = 0.05};
    o.area_epsilon = eps;
    const CurvatureFlow r = curvature_extrusion(m.V, m.F, edit, 4, o);
    const double a = bend_angle(m.V, r.V);
    const double q = quasi_conformal_summary(m.V, m.F, r.V).q_mean;
    const double rms = vertex_distances(edit, r.V, Alignment::Similarity).rms;
    std::printf(
        "shape snap (area eps %.1f): bend %.1f of %.1f deg (%.0f%%), Q_mean %.4f (edit %.4f), RMS to edit "
        "%.4f of diag\n",
        eps, a, a_edit, 100 * a / a_edit, q, q_edit, rms);
    CHECK(a > 0.5 * a_edit);  // well beyond the §7.2 snap's 26 of 56 degrees
    CHECK(q < q_edit);
  }
}

}  // namespace test_shape_snap
