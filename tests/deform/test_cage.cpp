// Cage coordinates and the cage deformer (deform/cage_coordinates.hpp, cage_deformer.hpp, CGA paper
// §VI): mean value coordinates reproduce linear functions and interpolate the cage; harmonic
// coordinates are non-negative, sum to 1, interpolate the cage vertices and reproduce the mesh within
// the stated grid interpolation bound; rigid motions; cage and containment errors.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/memory_budget.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/deform/cage_coordinates.hpp"
#include "spinmotor/deform/cage_deformer.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace test_cage {

using namespace spinmotor;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::Vector3d;

namespace {

/// An icosphere cage (42 vertices) around a torus of outer radius 1.4 (cage faces at distance ≥ 1.8).
Mesh cage_mesh() { return icosphere(1, 2.0); }
Mesh inner_mesh() { return torus(1.0, 0.4, 40, 20); }

/// A non-convex cage: a unit cube whose top face centre is pushed down to z = 0.7, 9 vertices.
Mesh dented_cube() {
  Mesh m;
  m.V.resize(9, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 0.5, 0.5, 0.7;
  m.F.resize(14, 3);
  m.F << 0, 2, 1, 0, 3, 2,                 // bottom (z = 0), normal −z
      0, 1, 5, 0, 5, 4,                    // y = 0
      1, 2, 6, 1, 6, 5,                    // x = 1
      2, 3, 7, 2, 7, 6,                    // y = 1
      3, 0, 4, 3, 4, 7,                    // x = 0
      4, 5, 8, 5, 6, 8, 6, 7, 8, 7, 4, 8;  // dented top
  return m;
}

ga::Mot rigid(const Vector3d& axis, double degrees, const Vector3d& t) {
  return ga::motor(ga::rotor(axis, degrees * M_PI / 180.0), ga::translator(t));
}

}  // namespace

TEST_CASE("cage: closed, consistently and outward oriented cages only", "[cage]") {
  Mesh c = cage_mesh();
  REQUIRE_NOTHROW(check_cage(c.V, c.F));
  REQUIRE_NOTHROW(check_cage(dented_cube().V, dented_cube().F));
  Mesh open = c;
  open.F.conservativeResize(c.F.rows() - 1, 3);
  CHECK_THROWS_WITH(check_cage(open.V, open.F), Catch::Contains("not closed"));
  Mesh flipped = c;
  flipped.F.row(5) = Eigen::RowVector3i(c.F(5, 0), c.F(5, 2), c.F(5, 1));
  CHECK_THROWS_WITH(check_cage(flipped.V, flipped.F),
                    Catch::Contains("not consistently oriented") && Catch::Contains("face"));
  Mesh inverted = c;
  inverted.F.col(1).swap(inverted.F.col(2));
  CHECK_THROWS_WITH(check_cage(inverted.V, inverted.F), Catch::Contains("inwards"));
  Mesh bad = c;
  bad.F(3, 1) = 99;
  CHECK_THROWS_WITH(check_cage(bad.V, bad.F), Catch::Contains("face 3"));
}

TEST_CASE("MVC: linear precision, partition of unity, interpolation of the cage", "[cage][mvc]") {
  for (const Mesh& cage : {cage_mesh(), dented_cube()}) {
    const bool cube = cage.V.rows() == 9;
    Mesh inner = inner_mesh();
    if (cube) inner.V = (inner.V * 0.25).rowwise() + Eigen::RowVector3d(0.5, 0.5, 0.35);
    const MatrixXd W = mean_value_coordinates(cage.V, cage.F, inner.V);
    CHECK((W.rowwise().sum().array() - 1.0).abs().maxCoeff() < 1e-12);
    CHECK((W * cage.V - inner.V).cwiseAbs().maxCoeff() < 1e-10);
    // an affine function f(x) = a·x + b is reproduced
    const Vector3d a(0.3, -1.2, 2.5);
    const Eigen::VectorXd f = cage.V * a + Eigen::VectorXd::Constant(cage.V.rows(), 0.7);
    const Eigen::VectorXd g = inner.V * a + Eigen::VectorXd::Constant(inner.V.rows(), 0.7);
    CHECK((W * f - g).cwiseAbs().maxCoeff() < 1e-10);
  }
  // at a cage vertex: δ_j; on a face: the barycentric coordinates there
  const Mesh cage = cage_mesh();
  MatrixXd X(2, 3);
  X.row(0) = cage.V.row(7);
  X.row(1) = 0.2 * cage.V.row(cage.F(4, 0)) + 0.3 * cage.V.row(cage.F(4, 1)) + 0.5 * cage.V.row(cage.F(4, 2));
  const MatrixXd W = mean_value_coordinates(cage.V, cage.F, X);
  CHECK(std::abs(W(0, 7) - 1.0) < 1e-12);
  CHECK(W.row(0).cwiseAbs().sum() < 1.0 + 1e-12);
  CHECK(std::abs(W(1, cage.F(4, 0)) - 0.2) < 1e-10);
  CHECK(std::abs(W(1, cage.F(4, 1)) - 0.3) < 1e-10);
  CHECK(std::abs(W(1, cage.F(4, 2)) - 0.5) < 1e-10);
}

TEST_CASE("HC: non-negative, partition of unity, cage interpolation, mesh within the stated bound",
          "[cage][hc]") {
  const Mesh cage = cage_mesh(), inner = inner_mesh();
  const int grid = 32;
  const MatrixXd W = harmonic_cage_coordinates(cage.V, cage.F, inner.V, grid);
  const double bound = harmonic_interpolation_bound(cage.V, grid);
  CHECK(W.minCoeff() >= -1e-12);
  CHECK((W.rowwise().sum().array() - 1.0).abs().maxCoeff() < 1e-10);
  const double err = std::sqrt((W * cage.V - inner.V).rowwise().squaredNorm().maxCoeff());
  WARN("HC grid " << grid << ": max |Σλ C − x| = " << err << ", bound √3h = " << bound);
  CHECK(err <= bound);
  // at (just inside) a cage vertex, λ is δ_j up to the interpolation: the coordinate of a vertex
  // changes by at most √3h / (the shortest cage edge) over the band.
  const MatrixXd Wc = harmonic_cage_coordinates(cage.V, cage.F, cage.V * (1 - 1e-9), grid);
  double emin = INFINITY;
  for (Index f = 0; f < cage.F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      emin = std::min(emin, (cage.V.row(cage.F(f, c)) - cage.V.row(cage.F(f, (c + 1) % 3))).norm());
  double dev = 0.0;
  for (Index j = 0; j < cage.V.rows(); ++j) dev = std::max(dev, 1.0 - Wc(j, j));
  WARN("HC grid " << grid << ": max 1 − λ_j(C_j) = " << dev << " (tolerance √3h/e_min = " << bound / emin
                  << ")");
  CHECK(dev <= bound / emin);
  // finer grids interpolate better
  const MatrixXd W2 = harmonic_cage_coordinates(cage.V, cage.F, inner.V, 48);
  CHECK(std::sqrt((W2 * cage.V - inner.V).rowwise().squaredNorm().maxCoeff()) < err);
}

TEST_CASE("cage deformer: rest pose, rigid motion in motor mode, position mode", "[cage]") {
  const Mesh cage = cage_mesh(), inner = inner_mesh();
  const ga::Mot R = rigid({1, -0.5, 0.2}, 70, {0.4, 1.0, -2.0});
  const Eigen::Isometry3d iso = ga::to_isometry(R);
  const MatrixXd expected = (inner.V * iso.linear().transpose()).rowwise() + iso.translation().transpose();
  for (auto coords : {CageDeformer::Coordinates::MeanValue, CageDeformer::Coordinates::Harmonic}) {
    for (auto blend : {ga::Blend::Log, ga::Blend::PivotLog, ga::Blend::DLB}) {
      CageDeformer d = CageDeformer::bind(inner, cage, {coords, 24, CageDeformer::Mode::Motor, blend});
      MatrixXd V;
      d.pose(std::vector<ga::Mot>(d.controls().size(), ga::Mot(1, 0, 0, 0, 0, 0, 0, 0)), V);
      CHECK((V - inner.V).cwiseAbs().maxCoeff() < 1e-12);
      d.pose(std::vector<ga::Mot>(d.controls().size(), R), V);
      CHECK((V - expected).cwiseAbs().maxCoeff() < 1e-12);
    }
    CageDeformer p = CageDeformer::bind(inner, cage, {coords, 24, CageDeformer::Mode::Position});
    MatrixXd V;
    p.pose(std::vector<ga::Mot>(p.controls().size(), R), V);
    CHECK(std::sqrt((V - expected).rowwise().squaredNorm().maxCoeff()) <=
          std::max(1e-10, p.interpolation_bound()));
    // moving one cage vertex moves the mesh by λ_j times its displacement
    MatrixXd C = cage.V, V0;
    p.pose_points(C, V0);
    C(3, 0) += 0.5;
    p.pose_points(C, V);
    CHECK(((V - V0).col(0) - 0.5 * p.coordinates().col(3)).cwiseAbs().maxCoeff() < 1e-12);
  }
}

TEST_CASE("cage deformer: a mesh vertex outside the cage is named", "[cage]") {
  const Mesh cage = cage_mesh();
  Mesh inner = inner_mesh();
  inner.V.row(123) << 3.0, 0.0, 0.0;
  CHECK_THROWS_WITH(CageDeformer::bind(inner, cage, {CageDeformer::Coordinates::MeanValue}),
                    Catch::Contains("mesh vertex 123") && Catch::Contains("outside the cage"));
  CHECK_THROWS_WITH(CageDeformer::bind(inner, cage, {CageDeformer::Coordinates::Harmonic, 16}),
                    Catch::Contains("mesh vertex 123"));
  CHECK_THROWS_WITH(CageDeformer::bind(inner_mesh(), cage, {CageDeformer::Coordinates::Harmonic, 2}),
                    Catch::Contains("grid 2"));
}

TEST_CASE("HC: a grid that cannot fit is refused at once with the estimate and the limit", "[cage][memory]") {
  // Grid 512 on a 42-vertex cage: 138M grid nodes, ~60M unknowns with 42 right-hand sides each. It used
  // to rasterize and order for minutes before CHOLMOD refused; now the estimate refuses it before any
  // per-node allocation. The time bound is the point of the check (the work itself takes minutes).
  struct Reset {
    ~Reset() { set_memory_limit(0); }
  } reset;
  set_memory_limit(8ull << 30);
  const Mesh cage = cage_mesh(), inner = inner_mesh();
  const auto t0 = std::chrono::steady_clock::now();
  try {
    (void)harmonic_cage_coordinates(cage.V, cage.F, inner.V, 512);
    FAIL("no refusal");
  } catch (const Error& e) {
    const std::string m = e.what();
    INFO(m);
    CHECK(m.find("harmonic_cage_coordinates: grid 512 (") != std::string::npos);
    CHECK(m.find("nodes) needs an estimated ") != std::string::npos);
    CHECK(m.find(" TB of memory; the limit is 8.0 GB") != std::string::npos);  // the factor alone: ~2 TB
  }
  CHECK(ms_since(t0) < 1000);
  // A grid that fits under the same limit runs (grid 16: a few MB).
  CHECK(harmonic_cage_coordinates(cage.V, cage.F, inner.V, 16).rows() == inner.V.rows());
}

}  // namespace test_cage
