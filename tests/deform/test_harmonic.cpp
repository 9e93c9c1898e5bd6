// Harmonic fields and harmonic coordinates (deform/harmonic_field.hpp, CGA paper §IV, §VIII):
// closed form on a tube (λ = z / L), partition of unity, the maximum principle, exact Dirichlet
// values, one factorization with k right-hand sides against k separate solves, and the errors for
// bad handles and for a connected component without a handle.
#include <Eigen/Core>
#include <catch2/catch.hpp>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/harmonic_field.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace test_harmonic {

using namespace spinmotor;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using Eigen::VectorXi;

namespace {

constexpr int kRings = 41, kSides = 24;
constexpr double kLength = 4.0, kRadius = 0.5;

Mesh test_tube(bool capped = false) { return tube(kRadius, kLength, kRings, kSides, capped); }

/// The vertices of ring k of test_tube(), optionally only sides [j0, j1).
Handle ring(const std::string& name, int k, int j0 = 0, int j1 = kSides) {
  Handle h{name, VectorXi(j1 - j0)};
  for (int j = j0; j < j1; ++j) h.vertices[j - j0] = k * kSides + j;
  return h;
}

Handle ball(const std::string& name, const MatrixXd& V, const Eigen::Vector3d& c, double r) {
  std::vector<int> v;
  for (Index i = 0; i < V.rows(); ++i)
    if ((V.row(i).transpose() - c).norm() < r) v.push_back(static_cast<int>(i));
  return Handle{name, Eigen::Map<VectorXi>(v.data(), static_cast<Index>(v.size()))};
}

const HarmonicWeights kBoth[] = {HarmonicWeights::MeanValue, HarmonicWeights::Cotangent};

}  // namespace

TEST_CASE("harmonic field on an open tube is z / L for both weights", "[harmonic]") {
  // z is harmonic on a cylinder, and the tube's one-rings are symmetric under the half turn about the
  // vertex normal, so both discrete Laplacians annihilate z: the field is exactly linear.
  const Mesh m = test_tube();
  for (HarmonicWeights w : kBoth) {
    const VectorXd lambda = harmonic_field(m.V, m.F, ring("base", 0), ring("tip", kRings - 1), w);
    const VectorXd expected = m.V.col(2) / kLength;
    CAPTURE(to_string(w));
    CHECK((lambda - expected).cwiseAbs().maxCoeff() < 1e-12);
  }
}

TEST_CASE("harmonic field is exactly 0 and 1 on its sets and obeys the maximum principle", "[harmonic]") {
  const Mesh m = test_tube(true);  // capped: the field bends over the caps, no closed form
  const Handle zero = ball("base", m.V, {0, 0, 0}, 0.3), one = ring("side", 30, 0, 6);
  for (HarmonicWeights w : kBoth) {
    CAPTURE(to_string(w));
    const VectorXd lambda = harmonic_field(m.V, m.F, zero, one, w);
    for (Index k = 0; k < zero.vertices.size(); ++k) CHECK(lambda[zero.vertices[k]] == 0.0);
    for (Index k = 0; k < one.vertices.size(); ++k) CHECK(lambda[one.vertices[k]] == 1.0);
    CHECK(lambda.minCoeff() >= -1e-13);
    CHECK(lambda.maxCoeff() <= 1.0 + 1e-13);
    // Strictly inside away from the sets (a non-trivial field).
    CHECK(lambda[(kRings - 1) * kSides] > 0.0);
    CHECK(lambda[(kRings - 1) * kSides] < 1.0);
  }
}

TEST_CASE("harmonic coordinates: partition of unity, bounds, exact on handles", "[harmonic]") {
  struct Case {
    const char* name;
    Mesh mesh;
    std::vector<Handle> handles;
  };
  std::vector<Case> cases;
  {
    Mesh t = test_tube();
    cases.push_back({"tube, 2 rings", t, {ring("a", 0), ring("b", kRings - 1)}});
    cases.push_back({"tube, 4 handles",
                     t,
                     {ring("a", 0), ring("b", kRings - 1), ring("c", 20, 0, 5), ring("d", 12, 12, 16)}});
  }
  {
    Mesh s = icosphere(3);
    std::vector<Handle> h = {ball("n", s.V, {0, 0, 1}, 0.3), ball("s", s.V, {0, 0, -1}, 0.3),
                             ball("e", s.V, {1, 0, 0}, 0.25)};
    cases.push_back({"icosphere, 3 caps", s, h});
  }
  {
    Mesh c = capsule(0.5, 2.0, 30, 20);
    cases.push_back({"capsule, 1 handle", c, {ball("only", c.V, {0, 0, -0.5}, 0.2)}});
  }
  for (const Case& c : cases) {
    for (HarmonicWeights w : kBoth) {
      CAPTURE(c.name, to_string(w));
      const MatrixXd L = harmonic_coordinates(c.mesh.V, c.mesh.F, c.handles, w);
      REQUIRE(L.rows() == c.mesh.V.rows());
      REQUIRE(L.cols() == static_cast<Index>(c.handles.size()));
      // Partition of unity: the last column is not solved for but set to 1 − Σ of the others, so the
      // row sums alone prove nothing; it must equal its own solve (1 on its handle, 0 on the others).
      CHECK((L.rowwise().sum().array() - 1.0).abs().maxCoeff() < 1e-12);
      if (c.handles.size() > 1) {
        Handle others{"others", VectorXi(c.mesh.V.rows())};
        Index o = 0;
        for (std::size_t j = 0; j + 1 < c.handles.size(); ++j)
          for (Index k = 0; k < c.handles[j].vertices.size(); ++k)
            others.vertices[o++] = c.handles[j].vertices[k];
        others.vertices.conservativeResize(o);
        const VectorXd last = harmonic_field(c.mesh.V, c.mesh.F, others, c.handles.back(), w);
        CHECK((L.col(L.cols() - 1) - last).cwiseAbs().maxCoeff() < 1e-12);
      }
      CHECK(L.minCoeff() >= -1e-12);  // maximum principle
      CHECK(L.maxCoeff() <= 1.0 + 1e-12);
      for (std::size_t j = 0; j < c.handles.size(); ++j)
        for (Index k = 0; k < c.handles[j].vertices.size(); ++k)
          for (Index col = 0; col < L.cols(); ++col)
            CHECK(L(c.handles[j].vertices[k], col) == (col == static_cast<Index>(j) ? 1.0 : 0.0));
    }
  }
}

TEST_CASE("one factorization with k - 1 right-hand sides equals k separate solves", "[harmonic]") {
  const Mesh m = test_tube(true);
  const std::vector<Handle> h = {ring("a", 0), ring("b", kRings - 1), ring("c", 20, 0, 5)};
  for (HarmonicWeights w : kBoth) {
    CAPTURE(to_string(w));
    const MatrixXd L = harmonic_coordinates(m.V, m.F, h, w);
    for (int j = 0; j < 3; ++j) {
      // Field j: 1 on handle j, 0 on the union of the other two.
      Handle others{"others", VectorXi(h[(j + 1) % 3].vertices.size() + h[(j + 2) % 3].vertices.size())};
      others.vertices << h[(j + 1) % 3].vertices, h[(j + 2) % 3].vertices;
      const VectorXd f = harmonic_field(m.V, m.F, others, h[j], w);
      CHECK((L.col(j) - f).cwiseAbs().maxCoeff() < 1e-12);
    }
  }
}

TEST_CASE("harmonic fields reject bad handles and unconstrained components", "[harmonic][errors]") {
  const Mesh m = test_tube();
  const std::vector<Handle> empty = {ring("a", 0), Handle{"nothing", VectorXi()}};
  CHECK_THROWS_WITH(harmonic_coordinates(m.V, m.F, empty),
                    Catch::Contains("'nothing'") && Catch::Contains("no vertex"));
  const std::vector<Handle> shared = {ring("a", 0), ring("b", 0, 3, 5)};
  CHECK_THROWS_WITH(harmonic_coordinates(m.V, m.F, shared),
                    Catch::Contains("'a' and 'b'") && Catch::Contains("share vertex 3"));
  const std::vector<Handle> range = {Handle{"far", VectorXi::Constant(1, 100000)}};
  CHECK_THROWS_WITH(harmonic_coordinates(m.V, m.F, range),
                    Catch::Contains("'far'") && Catch::Contains("out of range"));

  // Two tubes, handles only on the first: component 1 has no constrained vertex.
  Mesh two;
  two.V.resize(2 * m.V.rows(), 3);
  two.V << m.V, (m.V.rowwise() + Eigen::RowVector3d(3, 0, 0));
  two.F.resize(2 * m.F.rows(), 3);
  two.F << m.F, (m.F.array() + static_cast<int>(m.V.rows())).matrix();
  const std::vector<Handle> one_side = {ring("a", 0), ring("b", kRings - 1)};
  for (HarmonicWeights w : kBoth) {
    CAPTURE(to_string(w));
    CHECK_THROWS_WITH(harmonic_coordinates(two.V, two.F, one_side, w),
                      Catch::Contains("connected component 1") && Catch::Contains("no constrained vertex"));
    try {
      harmonic_coordinates(two.V, two.F, one_side, w);
    } catch (const Error& e) {
      CHECK(e.kind() == Error::Kind::BadInput);
    }
  }
}

}  // namespace test_harmonic
