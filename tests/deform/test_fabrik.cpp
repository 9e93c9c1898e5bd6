// FABRIK inverse kinematics (deform/fabrik.hpp) and the chain → key motors → B-spline pipeline
// (deform/chain_fit.hpp, CGA paper §III.C): reachable targets within tolerance, bone lengths kept,
// the stretched chain for unreachable targets, the prescribed end orientation, joint motors that carry
// rest joints onto posed joints, rigid chains giving rigid motors, and the joint parameters on a tube.
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/chain_fit.hpp"
#include "spinmotor/deform/fabrik.hpp"
#include "spinmotor/deform/harmonic_field.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace test_fabrik {

using namespace spinmotor;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Eigen::VectorXi;

namespace {

/// k joints on the z axis from 0 to `length`, slightly uneven bones.
MatrixXd straight_chain(int k, double length) {
  MatrixXd c(k, 3);
  for (int i = 0; i < k; ++i) {
    const double s = static_cast<double>(i) / (k - 1);
    c.row(i) << 0, 0, length * (s + 0.05 * std::sin(M_PI * s));
  }
  return c;
}

VectorXd bone_lengths(const MatrixXd& c) {
  VectorXd l(c.rows() - 1);
  for (Index i = 0; i + 1 < c.rows(); ++i) l[i] = (c.row(i + 1) - c.row(i)).norm();
  return l;
}

}  // namespace

TEST_CASE("FABRIK reaches reachable targets and keeps bone lengths", "[fabrik]") {
  const MatrixXd chain = straight_chain(7, 4.0);
  const VectorXd len = bone_lengths(chain);
  for (const Vector3d& target : {Vector3d(1.5, 0.5, 3.0), Vector3d(-2.0, 1.0, 1.0), Vector3d(0.3, -3.5, 0.5),
                                 Vector3d(0.0, 0.0, 2.0)}) {
    CAPTURE(target.transpose());
    const FabrikResult r = fabrik(chain, target, {.tolerance = 1e-6, .max_iterations = 500});
    CHECK(r.reachable);
    CHECK(r.converged);
    CHECK(r.error <= 1e-6);
    CHECK((r.joints.row(6).transpose() - target).norm() <= 1e-6);
    CHECK((bone_lengths(r.joints) - len).cwiseAbs().maxCoeff() < 1e-9);
    CHECK(r.joints.row(0) == chain.row(0));  // the root stays put
  }
}

TEST_CASE("FABRIK stretches the chain towards unreachable targets", "[fabrik]") {
  const MatrixXd chain = straight_chain(5, 2.0);
  const VectorXd len = bone_lengths(chain);
  const Vector3d target(3, 1, 2);  // distance √14 ≈ 3.74 > 2
  const FabrikResult r = fabrik(chain, target, {});
  CHECK_FALSE(r.reachable);
  CHECK_FALSE(r.converged);
  CHECK((bone_lengths(r.joints) - len).cwiseAbs().maxCoeff() < 1e-9);
  const Vector3d dir = target.normalized();
  for (Index i = 0; i < r.joints.rows(); ++i) {  // every joint on the ray root → target
    const Vector3d p = r.joints.row(i).transpose();
    CHECK((p - p.dot(dir) * dir).norm() < 1e-12);
  }
  CHECK(r.error == Approx(target.norm() - len.sum()).epsilon(1e-12));
}

TEST_CASE("FABRIK with a prescribed end orientation", "[fabrik]") {
  const MatrixXd chain = straight_chain(6, 4.0);
  const ga::Rot R = ga::rotor(Vector3d(1, 0, 0), -M_PI / 2);  // the end bone points along +y
  const Vector3d target(0.0, 2.0, 2.5);
  const FabrikResult r =
      fabrik(chain, target, {.tolerance = 1e-7, .max_iterations = 1000, .end_rotation = R});
  CHECK(r.converged);
  CHECK((r.joints.row(5).transpose() - target).norm() <= 1e-7);
  const Vector3d end_dir = (r.joints.row(5) - r.joints.row(4)).normalized().transpose();
  CHECK((end_dir - Vector3d(0, 1, 0)).norm() < 1e-12);
  CHECK((bone_lengths(r.joints) - bone_lengths(chain)).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("FABRIK rejects bad chains", "[fabrik][errors]") {
  MatrixXd c = straight_chain(4, 1.0);
  c.row(2) = c.row(1);
  CHECK_THROWS_WITH(fabrik(c, Vector3d(0, 0, 1), {}),
                    Catch::Contains("bone 1") && Catch::Contains("zero length"));
  CHECK_THROWS_WITH(fabrik(MatrixXd::Zero(1, 3), Vector3d(0, 0, 1), {}),
                    Catch::Contains("at least 2 joints"));
  CHECK_THROWS_WITH(fabrik(straight_chain(3, 1), Vector3d(0, 0, 1), {.tolerance = 0}),
                    Catch::Contains("tolerance"));
}

TEST_CASE("chain motors carry each rest joint onto its posed joint", "[fabrik][chain]") {
  const MatrixXd rest = straight_chain(7, 4.0);
  const FabrikResult r = fabrik(rest, Vector3d(1.8, 0.6, 2.8), {.tolerance = 1e-8, .max_iterations = 500});
  const auto Q = chain_motors(rest, r.joints);
  REQUIRE(Q.size() == 7);
  for (Index i = 0; i < 7; ++i) {
    CHECK((ga::transform(Q[i], rest.row(i).transpose()) - r.joints.row(i).transpose()).norm() < 1e-12);
    const auto n = Q[i] * ga::reverse(Q[i]);
    CHECK(std::abs(n.get<ga::blade::s>() - 1) < 1e-14);
  }
  // The root joint's rotation takes bone 0's rest direction onto its posed direction.
  const Vector3d r0 = (rest.row(1) - rest.row(0)).normalized().transpose();
  const Vector3d q0 = (r.joints.row(1) - r.joints.row(0)).normalized().transpose();
  CHECK((ga::rotate(ga::rotor_part(Q[0]), r0) - q0).norm() < 1e-12);
  // Tip: the last bone's frame.
  const Vector3d rl = (rest.row(6) - rest.row(5)).normalized().transpose();
  const Vector3d ql = (r.joints.row(6) - r.joints.row(5)).normalized().transpose();
  CHECK((ga::rotate(ga::rotor_part(Q[6]), rl) - ql).norm() < 1e-12);
}

TEST_CASE("a rigidly moved chain gives the same rigid motor at every joint", "[fabrik][chain]") {
  const MatrixXd rest = straight_chain(5, 3.0);
  const ga::Rot R = ga::rotor(Vector3d(1, 2, 0.5), 1.1);
  const Vector3d t(0.4, -1, 2);
  MatrixXd posed(5, 3);
  for (Index i = 0; i < 5; ++i) posed.row(i) = (ga::rotate(R, rest.row(i).transpose()) + t).transpose();
  // A straight chain has no twist information: the minimal rotation of the axis differs from R by a
  // twist about the posed axis. Compare the motion of points on the axis and the bone directions.
  const auto Q = chain_motors(rest, posed);
  for (const ga::Mot& q : Q) {
    const ga::Mot d = q * ga::reverse(Q[0]);  // all joint motors equal
    CHECK(std::abs(std::abs(d[0]) - 1.0) < 1e-12);
    for (int c = 1; c < 8; ++c) CHECK(std::abs(d[c]) < 1e-12);
  }
}

TEST_CASE("joint parameters match the harmonic parameter on a tube", "[fabrik][chain]") {
  // Open tube with 41 rings along z ∈ [0, 4]: λ = z/4. Joints at rings 0, 8, 20, 28, 40.
  const Mesh m = tube(0.5, 4.0, 41, 24, false);
  Handle from{"from", VectorXi::LinSpaced(24, 0, 23)},
      to{"to", VectorXi::LinSpaced(24, 40 * 24, 40 * 24 + 23)};
  const VectorXd lambda = harmonic_field(m.V, m.F, from, to);
  MatrixXd chain(5, 3);
  const int rings[5] = {0, 8, 20, 28, 40};
  for (int i = 0; i < 5; ++i) chain.row(i) << 0, 0, 0.1 * rings[i];
  const VectorXd p = chain_parameters(m.V, lambda, chain);
  for (int i = 0; i < 5; ++i) CHECK(p[i] == Approx(rings[i] / 40.0).margin(1e-9));
}

}  // namespace test_fabrik
