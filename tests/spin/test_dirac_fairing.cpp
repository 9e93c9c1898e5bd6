// Dirac immersions and fast fairing (Ye et al. 2018, §5.3): the first Dirac immersion lowers the Willmore
// energy (Thm. 5.1) at every step on spot, and a round sphere is (nearly) its own first immersion.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "shared_data.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/spin/dirac_fairing.hpp"
#include "spinmotor/spin/edge_constraint_net.hpp"

namespace test_dirac_fairing {

using namespace spinmotor;

TEST_CASE("fast fairing decreases W at every step on spot", "[ye][fairing]") {
  SPINMOTOR_REQUIRE_MESHES();
  const Mesh spot = read_mesh(std::string(SPINMOTOR_MESHES_DIR) + "/spot.obj");
  const DiracFairing r = dirac_fairing(spot.V, spot.F, 3);
  REQUIRE(r.willmore.size() == 4);
  std::printf("spot fast fairing: W = %.4f at the start (4 pi = %.4f)\n", r.willmore[0], 4 * M_PI);
  for (std::size_t k = 1; k < r.willmore.size(); ++k)
    std::printf("  step %zu: W = %.4f, closure residual %.3g\n", k, r.willmore[k], r.residual[k - 1]);
  for (std::size_t k = 1; k < r.willmore.size(); ++k) {
    CHECK(r.willmore[k] < r.willmore[k - 1]);
    CHECK(r.willmore[k] >= 4 * M_PI * 0.99);  // discrete W of a closed surface stays near or above 4π
  }
  CHECK(r.willmore.back() < 0.5 * (r.willmore.front() + 4 * M_PI));  // at least half way to the sphere
}

TEST_CASE("the unit sphere is its own first Dirac immersion", "[ye][fairing]") {
  const Mesh s = icosphere(3);
  const DiracImmersion d = dirac_immersion(s.V, s.F);
  CHECK(std::abs(std::abs(d.eigenvalue) - 1) < 0.01);
  const Eigen::VectorXd radius = d.V.rowwise().norm();
  INFO("radius range " << radius.minCoeff() << " .. " << radius.maxCoeff() << ", residual " << d.residual);
  CHECK(radius.maxCoeff() - radius.minCoeff() < 0.01);
  CHECK(d.residual < 0.01);
}

TEST_CASE("dirac immersion rejects a torus (not simply connected) and bad indices", "[ye][fairing]") {
  const Mesh t = torus(2.0, 1.0, 12, 8);
  CHECK_THROWS_AS(dirac_immersion(t.V, t.F), Error);
  const Mesh s = icosphere(1);
  CHECK_THROWS_AS(dirac_immersion(s.V, s.F, -1), Error);
  CHECK_THROWS_AS(dirac_fairing(s.V, s.F, -2), Error);
}

}  // namespace test_dirac_fairing
