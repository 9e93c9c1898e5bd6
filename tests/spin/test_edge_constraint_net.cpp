// Face edge-constraint nets (Ye et al. 2018, §4.1): bending angles, integrated mean curvature and the
// discrete Willmore energy (eq. 11) against closed forms.
#include <catch2/catch.hpp>
#include <cmath>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/spin/edge_constraint_net.hpp"

namespace test_edge_constraint_net {

using namespace spinmotor;

TEST_CASE("unit icosphere: convex edges positive, H_i ~ Area_i, W within 0.5% of 4 pi", "[ye][willmore]") {
  const Mesh s = icosphere(4);
  const EdgeConstraintNet net = edge_constraint_net(s.V, s.F);
  CHECK(net.theta.minCoeff() > 0.0);
  CHECK((net.H.array() / net.area.array() - 1.0).abs().maxCoeff() <
        0.15);  // irregular faces: per-face H/A within 11%
  CHECK(net.H.sum() / net.area.sum() == Approx(1.0).epsilon(0.005));
  const double W = net.willmore;
  INFO("W(icosphere 4) = " << W << ", 4 pi = " << 4 * M_PI);
  CHECK(std::abs(W / (4 * M_PI) - 1) < 0.005);
  // Scale invariance, and the sign of H flips with the orientation.
  const EdgeConstraintNet big = edge_constraint_net(3.0 * s.V, s.F);
  CHECK(big.willmore == Approx(W).epsilon(1e-12));
  Eigen::MatrixXi Fr = s.F;
  Fr.col(1).swap(Fr.col(2));
  const EdgeConstraintNet rev = edge_constraint_net(s.V, Fr);
  CHECK(rev.H.sum() == Approx(-net.H.sum()).epsilon(1e-12));
  // Hyperedge identities (eq. 12): |E_ij| cos(θ/2) = |e_ij| and E_ji = conj(E_ij).
  for (Eigen::Index f = 0; f < 50; ++f)
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector4d E = net.hyperedge(s.V, s.F, f, c);
      CHECK(E.norm() * std::cos(net.theta(f, c) / 2) == Approx(net.edge_length(f, c)).epsilon(1e-12));
      const int g = net.adjacent(f, c);
      for (int d = 0; d < 3; ++d)
        if (net.adjacent(g, d) == f) {
          const Eigen::Vector4d Ej = net.hyperedge(s.V, s.F, g, d);
          CHECK((Ej - Eigen::Vector4d(E[0], -E[1], -E[2], -E[3])).norm() < 1e-14);
        }
    }
}

TEST_CASE("Willmore torus R = sqrt 2, r = 1: W within 0.5% of 2 pi^2 at 128x64, converging",
          "[ye][willmore]") {
  double prev_err = 1e9;
  for (const int u : {32, 64, 128}) {
    const Mesh t = torus(std::sqrt(2.0), 1.0, u, u / 2);
    const double W = face_willmore_energy(t.V, t.F);
    const double err = std::abs(W / (2 * M_PI * M_PI) - 1);
    INFO("torus " << u << "x" << u / 2 << ": W = " << W << " (2 pi^2 = " << 2 * M_PI * M_PI << "), rel err "
                  << err);
    CHECK(err < prev_err);
    prev_err = err;
    if (u == 128) CHECK(err < 0.005);
  }
}

TEST_CASE("flat and folded grids: W = 0 on the plane, boundary edges carry no bending", "[ye][willmore]") {
  Mesh g = grid({2.0, 1.0}, {9, 5});
  const EdgeConstraintNet net = edge_constraint_net(g.V, g.F);
  CHECK(net.theta.cwiseAbs().maxCoeff() == 0.0);
  CHECK(net.willmore == 0.0);
  CHECK((net.adjacent.array() < 0).count() == 2 * (8 + 4));
  // Fold along x = 0 by 90 degrees: only the edges on the fold line bend, by ±90° (sign by direction).
  for (Eigen::Index v = 0; v < g.V.rows(); ++v)
    if (g.V(v, 0) > 0) {
      g.V(v, 2) = g.V(v, 0);
      g.V(v, 0) = 0;
    }
  const EdgeConstraintNet fold = edge_constraint_net(g.V, g.F);
  CHECK(fold.theta.cwiseAbs().maxCoeff() == Approx(M_PI / 2).epsilon(1e-12));
  CHECK((fold.theta.array().abs() > 1e-12).count() == 2 * 4);
}

TEST_CASE("edge_constraint_net rejects non-manifold and degenerate input", "[ye][willmore]") {
  Eigen::MatrixXd V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  Eigen::MatrixXi F(1, 3);
  F << 0, 1, 2;
  CHECK_THROWS_AS(edge_constraint_net(V, F), Error);
}

}  // namespace test_edge_constraint_net
