// Surface harmonic coordinates with motor handles (deform/surface_harmonic.hpp, CGA paper §IV) and the
// motor field engine (deform/motor_blend_field.hpp): identity, rigid motion, handle exactness, the
// closed form for translations, agreement of the fast per-vertex path with ga::blend, the §III.A
// rest-pose binding, and the errors.
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/surface_harmonic.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace test_deform_surface_harmonic {

using namespace spinmotor;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXi;

namespace {

constexpr int kRings = 40, kSides = 24;

Handle ring(const std::string& name, int k, int j0 = 0, int j1 = kSides) {
  Handle h{name, VectorXi(j1 - j0)};
  for (int j = j0; j < j1; ++j) h.vertices[j - j0] = k * kSides + j;
  return h;
}

/// Four handles on a capped 40×24 tube: both end rings, two side patches.
std::vector<Handle> four_handles() {
  return {ring("base", 0), ring("tip", kRings - 1), ring("left", 20, 0, 4), ring("right", 14, 12, 16)};
}

ga::Mot screw(const Vector3d& axis, double degrees, const Vector3d& about, const Vector3d& t) {
  const ga::Rot r = ga::rotor(axis, degrees * M_PI / 180.0);
  // Rotate about `about`, then translate by t: x ↦ R (x − a) + a + t.
  return ga::motor(r, ga::translator(about + t - ga::rotate(r, about)));
}

const ga::Blend kModes[] = {ga::Blend::Log, ga::Blend::PivotLog, ga::Blend::DLB};
const char* name(ga::Blend b) {
  return b == ga::Blend::Log ? "log" : b == ga::Blend::PivotLog ? "pivot-log" : "linear";
}

MatrixXd apply(const ga::Mot& m, const MatrixXd& V) {
  MatrixXd out(V.rows(), 3);
  for (Index i = 0; i < V.rows(); ++i) out.row(i) = ga::transform(m, V.row(i).transpose()).transpose();
  return out;
}

}  // namespace

TEST_CASE("identity motors give the rest mesh", "[deform][surface-harmonic]") {
  const Mesh m = tube(0.5, 4.0, kRings, kSides, true);
  const auto h = four_handles();
  for (ga::Blend mode : kModes) {
    CAPTURE(name(mode));
    auto d = SurfaceHarmonicDeformer::bind(m, h, {.blend = mode});
    const std::vector<ga::Mot> id(4, ga::Mot(1, 0, 0, 0, 0, 0, 0, 0));
    MatrixXd V;
    d.pose(id, V);
    CHECK((V - m.V).cwiseAbs().maxCoeff() < 1e-12);
  }
}

TEST_CASE("equal rigid motors on all handles move the mesh rigidly", "[deform][surface-harmonic]") {
  const Mesh m = tube(0.5, 4.0, kRings, kSides, true);
  const auto h = four_handles();
  const ga::Mot M = screw({1, 2, 3}, 130, {0.3, -0.2, 1}, {0.5, 1.5, -2});
  const MatrixXd expected = apply(M, m.V);
  for (HarmonicWeights w : {HarmonicWeights::MeanValue, HarmonicWeights::Cotangent})
    for (ga::Blend mode : kModes) {
      CAPTURE(name(mode), to_string(w));
      auto d = SurfaceHarmonicDeformer::bind(m, h, {.weights = w, .blend = mode});
      MatrixXd V;
      d.pose(std::vector<ga::Mot>(4, M), V);
      CHECK((V - expected).cwiseAbs().maxCoeff() < 1e-12);
    }
}

TEST_CASE("handle vertices follow their own motor exactly", "[deform][surface-harmonic]") {
  const Mesh m = tube(0.5, 4.0, kRings, kSides, true);
  const auto h = four_handles();
  const std::vector<ga::Mot> motors = {
      screw({0, 0, 1}, 0, {0, 0, 0}, {0, 0, 0}), screw({1, 0, 0}, 75, {0, 0, 4}, {0, 0.8, 0.2}),
      screw({0, 1, 1}, -40, {0.5, 0, 2}, {0.3, 0, 0}), screw({1, 1, 0}, 170, {0, 0.5, 1.4}, {0, -0.2, 0.1})};
  for (ga::Blend mode : kModes) {
    CAPTURE(name(mode));
    auto d = SurfaceHarmonicDeformer::bind(m, h, {.blend = mode});
    MatrixXd V;
    d.pose(motors, V);
    double err = 0;
    for (std::size_t j = 0; j < h.size(); ++j)
      for (Index k = 0; k < h[j].vertices.size(); ++k) {
        const int v = h[j].vertices[k];
        err = std::max(err, (V.row(v).transpose() - ga::transform(motors[j], m.V.row(v).transpose())).norm());
      }
    CHECK(err < 1e-12);
    // Elsewhere the motors mix: a free vertex moves by none of the handle motors.
    const int free_vertex = 30 * kSides + 6;
    for (const ga::Mot& M : motors)
      CHECK((V.row(free_vertex).transpose() - ga::transform(M, m.V.row(free_vertex).transpose())).norm() >
            1e-3);
  }
}

TEST_CASE("translations blend to the harmonic interpolation of the offsets", "[deform][surface-harmonic]") {
  // log of a translator is linear in its offset, so exp(Σ λ_j log T_j) is the translation by Σ λ_j t_j:
  // V' = V + Λ T, an independent closed form (Log and PivotLog; Linear (DLB) also: the normalized sum of
  // translators 1 − ½ (Σ λ t) inf is the same translator).
  const Mesh m = tube(0.5, 4.0, kRings, kSides, true);
  const auto h = four_handles();
  MatrixXd T(4, 3);
  T << 0, 0, 0, 0.5, -1, 2, 1, 0, 0, 0, 0.25, -0.5;
  std::vector<ga::Mot> motors;
  for (int j = 0; j < 4; ++j)
    motors.push_back(ga::motor(ga::Rot(1, 0, 0, 0), ga::translator(T.row(j).transpose())));
  for (ga::Blend mode : kModes) {
    CAPTURE(name(mode));
    auto d = SurfaceHarmonicDeformer::bind(m, h, {.blend = mode});
    MatrixXd V;
    d.pose(motors, V);
    const MatrixXd expected = m.V + MatrixXd(d.coordinates()) * T;
    CHECK((V - expected).cwiseAbs().maxCoeff() < 1e-12);
  }
}

TEST_CASE("the per-vertex fast path equals ga::blend vertex by vertex", "[deform][surface-harmonic]") {
  const Mesh m = tube(0.5, 4.0, kRings, kSides, true);
  const auto h = four_handles();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<ga::Mot> motors;
  for (int j = 0; j < 4; ++j)
    motors.push_back(screw({u(rng), u(rng), u(rng)}, 170 * u(rng), {u(rng), u(rng), 2 + u(rng)},
                           {u(rng), u(rng), u(rng)}));
  for (ga::Blend mode : kModes) {
    CAPTURE(name(mode));
    auto d = SurfaceHarmonicDeformer::bind(m, h, {.blend = mode});
    MatrixXd V;
    d.pose(motors, V);
    double err = 0;
    for (Index i = 0; i < m.V.rows(); ++i)
      err = std::max(err, (V.row(i).transpose() -
                           ga::transform(d.field().vertex_motor(i, motors), m.V.row(i).transpose()))
                              .norm());
    CHECK(err < 1e-12);
  }
}

TEST_CASE("rest-pose binding (§III.A): posing with the rest motors gives the rest mesh",
          "[deform][surface-harmonic]") {
  const Mesh m = tube(0.5, 4.0, kRings, kSides, true);
  const auto h = four_handles();
  const std::vector<ga::Mot> rest = {
      screw({0, 0, 1}, 20, {0, 0, 0}, {0, 0, 0}), screw({1, 0, 0}, 30, {0, 0, 4}, {0, 0, 0}),
      screw({0, 1, 0}, -15, {0.5, 0, 2}, {0.1, 0, 0}), screw({1, 1, 0}, 45, {0, 0.5, 1.4}, {0, 0, 0.3})};
  for (ga::Blend mode : kModes) {
    CAPTURE(name(mode));
    auto d = SurfaceHarmonicDeformer::bind(m, h, {.blend = mode, .rest_motors = rest});
    MatrixXd V;
    d.pose(rest, V);
    CHECK((V - m.V).cwiseAbs().maxCoeff() < 1e-12);
    // The bound points are not the rest points (the binding did something).
    CHECK((MatrixXd(d.field().bound_positions()) - m.V).cwiseAbs().maxCoeff() > 0.01);
  }
}

TEST_CASE("pose rejects wrong motor counts and non-unit motors", "[deform][surface-harmonic][errors]") {
  const Mesh m = tube(0.5, 4.0, kRings, kSides, true);
  auto d = SurfaceHarmonicDeformer::bind(m, four_handles());
  MatrixXd V;
  CHECK_THROWS_WITH(d.pose(std::vector<ga::Mot>(3, ga::Mot(1, 0, 0, 0, 0, 0, 0, 0)), V),
                    Catch::Contains("3 motors given for 4 controls"));
  std::vector<ga::Mot> bad(4, ga::Mot(1, 0, 0, 0, 0, 0, 0, 0));
  bad[2] = ga::Mot(2, 0, 0, 0, 0, 0, 0, 0);
  CHECK_THROWS_WITH(d.pose(bad, V), Catch::Contains("motor 2 is not a unit motor"));
  bad[2] = ga::Mot(std::nan(""), 0, 0, 0, 0, 0, 0, 0);
  CHECK_THROWS_WITH(d.pose(bad, V), Catch::Contains("motor 2 is not finite"));
}

}  // namespace test_deform_surface_harmonic
