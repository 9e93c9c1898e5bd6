// Curvature-space spin transformations (Le Folgoc & Blanc 2019, eq. 8, Appendix D): identity for the
// current half-density, fairing to a sphere with and without the area constraint, extrusion back.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "shared_data.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/area_distortion.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/curvature_spin_flow.hpp"
#include "spinmotor/spin/edge_constraint_net.hpp"

namespace test_curvature_spin_flow {

using namespace spinmotor;

namespace {
double mean_relative(const VertexDistances& d) { return d.d.mean() / d.diagonal; }
}  // namespace

TEST_CASE("prescribing the current half-density is the identity (phi = 1)", "[lefolgoc]") {
  Mesh e = icosphere(2);
  e.V.col(0) *= 1.5;
  const EdgeConstraintNet net = edge_constraint_net(e.V, e.F);
  for (const double eps : {0.0, 0.5}) {
    CurvatureSpinOptions o;
    o.area_epsilon = eps;
    const CurvatureSpinStep st = curvature_spin_step(e.V, e.F, net.h, net.area, o);
    CHECK((st.phi.col(0).array() - 1).abs().maxCoeff() < 1e-9);
    CHECK(st.phi.rightCols(3).cwiseAbs().maxCoeff() < 1e-9);
    CHECK((st.V - e.V).cwiseAbs().maxCoeff() < 1e-9);
  }
}

TEST_CASE("fairing an ellipsoid to a sphere and extruding it back", "[lefolgoc]") {
  Mesh e = icosphere(3);
  e.V.col(0) *= 2.0;
  e.V.col(2) *= 0.7;
  const CurvatureFlow fair = curvature_fairing(e.V, e.F, 6, 0.5);
  for (std::size_t k = 1; k < fair.willmore.size(); ++k) CHECK(fair.willmore[k] < fair.willmore[k - 1]);
  for (const double c : fair.closure) CHECK(c < 0.01);
  CHECK(fair.willmore.back() < 4 * M_PI * 1.04);
  const CurvatureFlow back = curvature_extrusion(fair.V, e.F, e.V, 4);
  const VertexDistances d = vertex_distances(e.V, back.V, Alignment::Similarity);
  std::printf("ellipsoid: W %.4f -> %.4f; extrusion mean %.4g max %.4g of the diagonal\n",
              fair.willmore.front(), fair.willmore.back(), mean_relative(d), d.max);
  CHECK(mean_relative(d) < 0.005);
}

TEST_CASE("spot: fair to a sphere with and without the area constraint, extrude back", "[lefolgoc][spot]") {
  SPINMOTOR_REQUIRE_MESHES();
  const Mesh spot = read_mesh(std::string(SPINMOTOR_MESHES_DIR) + "/spot.obj");
  CurvatureSpinOptions area;
  area.area_epsilon = 1.5;
  const CurvatureFlow free = curvature_fairing(spot.V, spot.F, 6, 0.5);
  const CurvatureFlow ac = curvature_fairing(spot.V, spot.F, 6, 0.5, area);
  const QuasiConformalSummary qf = quasi_conformal_summary(spot.V, spot.F, free.V);
  const QuasiConformalSummary qa = quasi_conformal_summary(spot.V, spot.F, ac.V);
  const AreaDistortionSummary sf = area_distortion_summary(spot.V, spot.F, free.V);
  const AreaDistortionSummary sa = area_distortion_summary(spot.V, spot.F, ac.V);
  std::printf("spot fairing, 6 steps of tau 0.5 (W start %.3f):\n", free.willmore.front());
  std::printf("  free:       W %.3f, Q max %.3f mean %.4f, |log area| max %.3f mean %.3f\n",
              free.willmore.back(), qf.q_max, qf.q_mean, sf.max_abs, sf.mean_abs);
  std::printf("  area eps %.1f: W %.3f, Q max %.3f mean %.4f, |log area| max %.3f mean %.3f\n",
              area.area_epsilon, ac.willmore.back(), qa.q_max, qa.q_mean, sa.max_abs, sa.mean_abs);
  CHECK(free.willmore.back() < 4 * M_PI * 1.05);
  CHECK(ac.willmore.back() < 4 * M_PI * 1.15);
  CHECK(sa.mean_abs < sf.mean_abs);  // the area constraint lowers the area distortion ...
  CHECK(sa.max_abs < sf.max_abs);
  CHECK(qa.q_mean > qf.q_mean);  // ... at some cost in conformality
  const CurvatureFlow back = curvature_extrusion(free.V, spot.F, spot.V, 8);
  const VertexDistances d = vertex_distances(spot.V, back.V, Alignment::Similarity);
  std::printf("spot extrusion from its faired sphere, 8 steps: mean %.4g max %.4g of the diagonal, W %.3f\n",
              mean_relative(d), d.max, back.willmore.back());
  CHECK(mean_relative(d) < 0.01);
  CHECK(d.max < 0.02);
}

TEST_CASE("curvature spin flows reject bad input", "[lefolgoc]") {
  const Mesh s = icosphere(1);
  const Eigen::VectorXd h = Eigen::VectorXd::Ones(s.F.rows());
  CHECK_THROWS_AS(curvature_spin_step(s.V, s.F, Eigen::VectorXd::Ones(3), {}, {}), Error);
  CurvatureSpinOptions bad;
  bad.alpha = 0;
  CHECK_THROWS_AS(curvature_spin_step(s.V, s.F, h, {}, bad), Error);
  CurvatureSpinOptions area;
  area.area_epsilon = 0.5;
  CHECK_THROWS_AS(curvature_spin_step(s.V, s.F, h, -h, area), Error);
  CHECK_THROWS_AS(curvature_fairing(s.V, s.F, 2, 1.5), Error);
  CHECK_THROWS_AS(curvature_extrusion(s.V, s.F, icosphere(2).V, 2), Error);
}

TEST_CASE("genus 1: the exactness constraint keeps a torus closing up, without it a period opens",
          "[lefolgoc][torus]") {
  Mesh t = torus(2.0, 0.8, 32, 16);
  for (Eigen::Index v = 0; v < t.V.rows(); ++v) {  // break the symmetry: elliptic, with a bump
    t.V(v, 0) *= 1.4;
    const double bump = 0.5 * std::exp(-((t.V.row(v) - Eigen::RowVector3d(2.8, 0.0, 0.8)).squaredNorm()));
    t.V(v, 2) += bump;
  }
  for (const bool exact : {true, false}) {
    CurvatureSpinOptions o;
    o.exactness = exact;
    const EdgeConstraintNet net = edge_constraint_net(t.V, t.F);
    const double fac = 0.3;
    const CurvatureSpinStep st = curvature_spin_step(t.V, t.F, fac * net.h, {}, o);
    std::printf("torus step (h -> %g h), exactness %s (%d constraints): closure residual %.3g, period %.3g\n",
                fac, exact ? "on" : "off", st.exactness_constraints, st.closure, st.period);
    // The period (sum of the new edges against a harmonic form, relative) measures the failure to close
    // around the handles; the face-closure residual of the soft eq. 8 solve (~5% here, the step prescribes
    // a far-from-integrable h) is the same either way. Measured: period 0.0023 with, 0.060 without.
    if (exact) {
      CHECK(st.exactness_constraints == 6);
      CHECK(st.period < 0.005);
    } else {
      CHECK(st.exactness_constraints == 0);
      CHECK(st.period > 0.03);
    }
  }
}

}  // namespace test_curvature_spin_flow
