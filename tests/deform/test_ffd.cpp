// Free-form deformation with a lattice of points or motors (deform/ffd.hpp, CGA paper §V): the
// undeformed lattice reproduces the mesh (both bases), local support of a moved control, rigid motion
// of all controls, linear precision of the position mode, agreement of the fast motor path with
// ga::blend, vertices outside the box, and the errors.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/ffd.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace test_ffd {

using namespace spinmotor;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::Vector3d;

namespace {

Mesh test_mesh() { return torus(2.0, 0.7, 48, 24); }

FfdDeformer::Options opts(FfdDeformer::Basis basis, FfdDeformer::Mode mode, std::array<int, 3> lattice,
                          ga::Blend blend = ga::Blend::Log) {
  FfdDeformer::Options o;
  o.basis = basis;
  o.mode = mode;
  o.lattice = lattice;
  o.blend = blend;
  return o;
}

std::vector<ga::Mot> identities(Index L) { return std::vector<ga::Mot>(L, ga::Mot(1, 0, 0, 0, 0, 0, 0, 0)); }

ga::Mot rigid(const Vector3d& axis, double degrees, const Vector3d& t) {
  return ga::motor(ga::rotor(axis, degrees * M_PI / 180.0), ga::translator(t));
}

}  // namespace

TEST_CASE("FFD: the undeformed lattice reproduces the mesh", "[ffd]") {
  const Mesh m = test_mesh();
  for (auto basis : {FfdDeformer::Basis::Bezier, FfdDeformer::Basis::BSpline})
    for (auto mode : {FfdDeformer::Mode::Position, FfdDeformer::Mode::Motor})
      for (auto blend : {ga::Blend::Log, ga::Blend::DLB}) {
        FfdDeformer d = FfdDeformer::bind(m, opts(basis, mode, {5, 4, 7}, blend));
        MatrixXd V;
        d.pose(identities(d.controls().size()), V);
        CHECK((V - m.V).cwiseAbs().maxCoeff() < 1e-12);
        CHECK(d.outside() == 0);
        if (mode == FfdDeformer::Mode::Position) {
          d.pose_points(d.control_points(), V);
          CHECK((V - m.V).cwiseAbs().maxCoeff() < 1e-12);
        }
        // weights: a partition of unity
        const auto W = d.weights();
        const Eigen::VectorXd rows = W * Eigen::VectorXd::Ones(d.controls().size());
        CHECK((rows.array() - 1.0).abs().maxCoeff() < 1e-14);
      }
}

TEST_CASE("FFD: Bezier weights are the trivariate Bernstein polynomials (eq. 7)", "[ffd]") {
  const Mesh m = test_mesh();
  FfdDeformer d =
      FfdDeformer::bind(m, opts(FfdDeformer::Basis::Bezier, FfdDeformer::Mode::Position, {3, 4, 5}));
  const auto W = d.weights();
  const Eigen::AlignedBox3d& box = d.box();
  auto bern = [](int k, int deg, double t) {
    return std::tgamma(deg + 1.0) / (std::tgamma(k + 1.0) * std::tgamma(deg - k + 1.0)) * std::pow(t, k) *
           std::pow(1 - t, deg - k);
  };
  double err = 0.0;
  for (Index i = 0; i < m.V.rows(); i += 37) {
    const Vector3d s = (m.V.row(i).transpose() - box.min()).cwiseQuotient(box.sizes());
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 4; ++b)
        for (int c = 0; c < 5; ++c)
          err = std::max(err, std::abs(W.coeff(i, d.index(a, b, c)) -
                                       bern(a, 2, s.x()) * bern(b, 3, s.y()) * bern(c, 4, s.z())));
  }
  CHECK(err < 1e-14);
  // 5% margin around the bounding box
  const Vector3d lo = m.V.colwise().minCoeff(), hi = m.V.colwise().maxCoeff();
  CHECK((box.min() - (lo - 0.05 * (hi - lo))).norm() < 1e-14);
  CHECK((box.max() - (hi + 0.05 * (hi - lo))).norm() < 1e-14);
}

TEST_CASE("FFD: moving one control moves exactly the vertices in its support", "[ffd]") {
  const Mesh m = test_mesh();
  FfdDeformer d =
      FfdDeformer::bind(m, opts(FfdDeformer::Basis::BSpline, FfdDeformer::Mode::Position, {8, 8, 6}));
  const auto W = d.weights();
  // local support: (d+1)³ = 64 stored weights per vertex, not 384
  CHECK(W.nonZeros() == 64 * m.V.rows());
  const Index c = d.index(3, 5, 2);
  MatrixXd C = d.control_points(), V, V0;
  d.pose_points(C, V0);  // the undeformed lattice (equal to the rest mesh to rounding)
  C(c, 0) += 0.3;  // component by component: a RowVector3d temporary trips GCC 12's -Wmaybe-uninitialized
  C(c, 1) -= 0.2;
  C(c, 2) += 0.5;
  d.pose_points(C, V);
  Index in_support = 0, wrong = 0;
  for (Index i = 0; i < m.V.rows(); ++i) {
    const bool supported = W.coeff(i, c) != 0.0;
    const bool moved = (V.row(i) - V0.row(i)).norm() > 0.0;
    in_support += supported;
    wrong += supported != moved;
    // the displacement is w_c times the control's
    if (supported)
      CHECK((V.row(i) - m.V.row(i) - W.coeff(i, c) * Eigen::RowVector3d(0.3, -0.2, 0.5)).norm() < 1e-12);
  }
  CHECK(in_support > 0);
  CHECK(in_support < m.V.rows() * 3 / 4);
  CHECK(wrong == 0);
  // motor mode: rotating the same control moves the same set
  FfdDeformer dm =
      FfdDeformer::bind(m, opts(FfdDeformer::Basis::BSpline, FfdDeformer::Mode::Motor, {8, 8, 6}));
  auto M = identities(dm.controls().size());
  M[c] = rigid({1, 2, 0}, 40, {0.1, 0, 0.2});
  dm.pose(M, V);
  wrong = 0;  // motor mode: unsupported vertices get exp(0) = 1 exactly, so they do not move at all
  for (Index i = 0; i < m.V.rows(); ++i)
    wrong += (W.coeff(i, c) != 0.0) != ((V.row(i) - m.V.row(i)).norm() > 0.0);
  CHECK(wrong == 0);
}

TEST_CASE("FFD: the same rigid motion on every control moves the mesh rigidly", "[ffd]") {
  const Mesh m = test_mesh();
  const ga::Mot R = rigid({0.3, -1, 0.5}, 130, {1.5, -0.4, 2.0});
  const Eigen::Isometry3d iso = ga::to_isometry(R);
  const MatrixXd expected = (m.V * iso.linear().transpose()).rowwise() + iso.translation().transpose();
  for (auto basis : {FfdDeformer::Basis::Bezier, FfdDeformer::Basis::BSpline})
    for (auto mode : {FfdDeformer::Mode::Position, FfdDeformer::Mode::Motor})
      for (auto blend : {ga::Blend::Log, ga::Blend::DLB}) {
        FfdDeformer d = FfdDeformer::bind(m, opts(basis, mode, {4, 6, 5}, blend));
        MatrixXd V;
        d.pose(std::vector<ga::Mot>(d.controls().size(), R), V);
        CHECK((V - expected).cwiseAbs().maxCoeff() < 1e-12);
      }
}

TEST_CASE("FFD position mode: an affine map of the controls maps the points by the same map", "[ffd]") {
  const Mesh m = test_mesh();
  Eigen::Matrix3d A;
  A << 1.3, 0.4, -0.2, 0.1, 0.7, 0.5, -0.3, 0.2, 1.8;
  const Eigen::RowVector3d t(0.5, -1.0, 2.0);
  for (auto basis : {FfdDeformer::Basis::Bezier, FfdDeformer::Basis::BSpline}) {
    FfdDeformer d = FfdDeformer::bind(m, opts(basis, FfdDeformer::Mode::Position, {6, 5, 7}));
    const MatrixXd C = (d.control_points() * A.transpose()).rowwise() + t;
    MatrixXd V;
    d.pose_points(C, V);
    const MatrixXd expected = (m.V * A.transpose()).rowwise() + t;
    CHECK((V - expected).cwiseAbs().maxCoeff() < 1e-12);
  }
}

TEST_CASE("FFD motor mode: the fast path equals ga::blend over the supporting controls", "[ffd]") {
  const Mesh m = test_mesh();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (auto basis : {FfdDeformer::Basis::Bezier, FfdDeformer::Basis::BSpline})
    for (auto blend : {ga::Blend::Log, ga::Blend::DLB}) {
      FfdDeformer d = FfdDeformer::bind(m, opts(basis, FfdDeformer::Mode::Motor, {5, 5, 5}, blend));
      std::vector<ga::Mot> M(d.controls().size());
      for (auto& mo : M)
        mo = rigid({u(rng), u(rng), u(rng)}, 60 * u(rng), {0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng)});
      MatrixXd V;
      d.pose(M, V);
      double err = 0.0;
      for (Index i = 0; i < m.V.rows(); i += 13)
        err = std::max(
            err, (V.row(i).transpose() - ga::transform(d.vertex_motor(i, M), m.V.row(i).transpose())).norm());
      CHECK(err < 1e-12);
      // rotating controls changes edge lengths little compared with a shear of the same control displacement
    }
}

TEST_CASE("FFD: vertices outside an explicit box are unchanged and counted", "[ffd]") {
  const Mesh m = test_mesh();
  auto o = opts(FfdDeformer::Basis::Bezier, FfdDeformer::Mode::Motor, {4, 4, 4});
  o.box = Eigen::AlignedBox3d(Vector3d(0.0, -3, -1), Vector3d(3, 3, 1));
  FfdDeformer d = FfdDeformer::bind(m, o);
  const Index expected = (m.V.col(0).array() < 0.0).count();
  CHECK(d.outside() == expected);
  CHECK(expected > 0);
  MatrixXd V;
  d.pose(std::vector<ga::Mot>(d.controls().size(), rigid({0, 0, 1}, 30, {1, 0, 0})), V);
  Index same = 0;
  for (Index i = 0; i < m.V.rows(); ++i)
    if (!d.inside(i)) same += V.row(i) == m.V.row(i);
  CHECK(same == expected);
}

TEST_CASE("FFD log blend by blocks of 4: a short last block and outside vertices inside blocks", "[ffd]") {
  // 1,081 vertices (one in the last block of 4), a box that leaves the x < 0 half outside, so blocks mix
  // inside and outside vertices; every vertex against ga::blend over its supporting controls.
  const Mesh m = torus(2.0, 0.7, 47, 23);
  REQUIRE(m.V.rows() % 4 == 1);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (auto basis : {FfdDeformer::Basis::Bezier, FfdDeformer::Basis::BSpline}) {
    auto o = opts(basis, FfdDeformer::Mode::Motor, {4, 5, 4});
    o.box = Eigen::AlignedBox3d(Vector3d(0.0, -3, -1), Vector3d(3, 3, 1));
    FfdDeformer d = FfdDeformer::bind(m, o);
    REQUIRE(d.outside() > 0);
    std::vector<ga::Mot> M(d.controls().size());
    for (auto& mo : M)  // rotations up to 170°
      mo = rigid({u(rng), u(rng), u(rng)}, 170 * u(rng), {0.5 * u(rng), 0.5 * u(rng), 0.5 * u(rng)});
    MatrixXd V;
    d.pose(M, V);
    double err = 0.0;
    Index unchanged = 0;
    for (Index i = 0; i < m.V.rows(); ++i) {
      if (!d.inside(i)) {
        unchanged += V.row(i) == m.V.row(i);
        continue;
      }
      err = std::max(
          err, (V.row(i).transpose() - ga::transform(d.vertex_motor(i, M), m.V.row(i).transpose())).norm());
    }
    CHECK(unchanged == d.outside());
    CHECK(err < 1e-12);
  }
}

TEST_CASE("FFD: bad input throws Error naming it", "[ffd]") {
  const Mesh m = test_mesh();
  auto o = opts(FfdDeformer::Basis::Bezier, FfdDeformer::Mode::Motor, {4, 1, 4});
  CHECK_THROWS_WITH(FfdDeformer::bind(m, o), Catch::Contains("along y"));
  o.lattice = {4, 4, 4};
  o.blend = ga::Blend::PivotLog;
  CHECK_THROWS_AS(FfdDeformer::bind(m, o), Error);
  o.blend = ga::Blend::Log;
  o.box = Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(1, 0, 1));
  CHECK_THROWS_WITH(FfdDeformer::bind(m, o), Catch::Contains("box"));
  o.box.reset();
  FfdDeformer d = FfdDeformer::bind(m, o);
  MatrixXd V;
  CHECK_THROWS_WITH(d.pose(identities(63), V), Catch::Contains("63 motors"));
  auto M = identities(64);
  M[17][0] = 2.0;
  CHECK_THROWS_WITH(d.pose(M, V), Catch::Contains("motor 17"));
  CHECK_THROWS_WITH(d.pose_points(d.control_points(), V), Catch::Contains("position mode"));
}

}  // namespace test_ffd
