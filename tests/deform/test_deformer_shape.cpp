// The deformer shape (deform/deformer.hpp): every deformer satisfies the concept, AnyDeformer poses
// exactly as the concrete type, controls carry the documented names and rest anchors, the IK-driven
// spline is one deformer, and every option enum has one name table.
#include <catch2/catch.hpp>
#include <numbers>

#include "spinmotor/deform/any_deformer.hpp"
#include "spinmotor/deform/arap.hpp"
#include "spinmotor/deform/cage_deformer.hpp"
#include "spinmotor/deform/delta_mush.hpp"
#include "spinmotor/deform/direct_delta_mush.hpp"
#include "spinmotor/deform/ffd.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/deform/spline_deformer.hpp"
#include "spinmotor/deform/spline_ik.hpp"
#include "spinmotor/deform/surface_harmonic.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"

namespace test_deformer_shape {

using namespace spinmotor;
using Eigen::Vector3d;

static_assert(Deformer<SurfaceHarmonicDeformer>);
static_assert(Deformer<SplineDeformer>);
static_assert(Deformer<SplineIkDeformer>);
static_assert(Deformer<FfdDeformer>);
static_assert(Deformer<CageDeformer>);
static_assert(Deformer<ArapDeformer>);
static_assert(Deformer<SkinDeformer>);
static_assert(Deformer<DeltaMushDeformer>);
static_assert(Deformer<DirectDeltaMushDeformer>);
static_assert(!Deformer<Mesh>);

namespace {

const ga::Mot kIdentity(1, 0, 0, 0, 0, 0, 0, 0);

ga::Mot rigid(const Vector3d& axis, double degrees, const Vector3d& t) {
  return ga::from_isometry(Eigen::Isometry3d(
      Eigen::Translation3d(t) * Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis.normalized())));
}

/// The tube's rings at z = 0 and z = length.
std::vector<Handle> end_rings(const Mesh& m, double length) {
  std::vector<Handle> h(2);
  h[0].name = "base";
  h[1].name = "tip";
  std::vector<int> a, b;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    if (std::abs(m.V(i, 2)) < 1e-9) a.push_back(int(i));
    if (std::abs(m.V(i, 2) - length) < 1e-9) b.push_back(int(i));
  }
  h[0].vertices = Eigen::Map<Eigen::VectorXi>(a.data(), Eigen::Index(a.size()));
  h[1].vertices = Eigen::Map<Eigen::VectorXi>(b.data(), Eigen::Index(b.size()));
  return h;
}

/// Poses d directly and through an AnyDeformer holding a copy bound the same way: identical output.
template <Deformer D>
void same_through_any(D direct, D erased, std::span<const ga::Mot> motors) {
  Eigen::MatrixXd A, B;
  direct.pose(motors, A);
  AnyDeformer any = std::move(erased);
  REQUIRE(any.controls() == direct.controls());
  any.pose(motors, B);
  CHECK(A.rows() == any.vertices());
  CHECK((A - B).cwiseAbs().maxCoeff() == 0.0);
  CHECK(any.get<D>() != nullptr);
}

}  // namespace

TEST_CASE("every deformer poses the same through AnyDeformer, with named, anchored controls",
          "[deform][shape]") {
  const Mesh tube = spinmotor::tube(0.25, 4.0, 41, 12);
  const auto ends = end_rings(tube, 4.0);
  const Rig rig{.handles = ends};
  const ga::Mot bend = rigid({1, 0, 0}, 40, {0, 0.3, 0});
  const Vector3d c_base = handle_centroid(tube.V, ends[0]), c_tip = handle_centroid(tube.V, ends[1]);

  SECTION("surface harmonic: a control per handle at its centroid") {
    auto b = [&] { return SurfaceHarmonicDeformer::bind(tube, rig, {}); };
    const std::vector<ga::Mot> m = {kIdentity, bend};
    same_through_any(b(), b(), m);
    CHECK(b().controls() == std::vector<Control>{{"base", c_base}, {"tip", c_tip}});
  }
  SECTION("spline: keys between the end handles, named by key_names") {
    SplineDeformer::Options o;
    o.basis = SplineBasis::Linear;
    o.keys = 3;
    o.key_names = {"a", "b", "c"};
    auto b = [&] { return SplineDeformer::bind(tube, rig, o); };
    const std::vector<ga::Mot> m = {kIdentity, bend, bend};
    same_through_any(b(), b(), m);
    const SplineDeformer bound = b();
    const auto& c = bound.controls();
    REQUIRE(c.size() == 3);
    CHECK(c[1].name == "b");
    CHECK((c[1].anchor - 0.5 * (c_base + c_tip)).norm() < 1e-12);
    o.key_names = {"a"};
    CHECK_THROWS_WITH(SplineDeformer::bind(tube, rig, o), Catch::Contains("1 key names for 3 keys"));
  }
  SECTION("ffd: ffd[a,b,c] at the lattice points, in index order") {
    FfdDeformer::Options o;
    o.lattice = {2, 3, 2};
    auto b = [&] { return FfdDeformer::bind(tube, Rig{}, o); };
    std::vector<ga::Mot> m(12, kIdentity);
    m[5] = bend;
    same_through_any(b(), b(), m);
    const FfdDeformer f = b();
    REQUIRE(f.controls().size() == 12);
    CHECK(f.controls()[f.index(1, 2, 0)].name == "ffd[1,2,0]");
    CHECK(f.controls()[f.index(1, 2, 0)].anchor == Vector3d(f.control_points().row(f.index(1, 2, 0))));
    CHECK(f.controls()[0].anchor == f.box().min());
  }
  SECTION("cage: cage[j] at the cage vertices; a rig without a cage is an error") {
    Rig r;
    r.cage = spinmotor::icosphere(1, 2.5);
    r.cage->V.col(2).array() += 2.0;
    CageDeformer::Options o;
    o.coordinates = CageDeformer::Coordinates::MeanValue;
    auto b = [&] { return CageDeformer::bind(tube, r, o); };
    const std::vector<ga::Mot> m(r.cage->V.rows(), bend);
    same_through_any(b(), b(), m);
    CHECK(b().controls()[7] == Control{"cage[7]", r.cage->V.row(7).transpose()});
    CHECK_THROWS_WITH(CageDeformer::bind(tube, Rig{}, o), Catch::Contains("no cage"));
  }
  SECTION("arap: a control per handle") {
    ArapDeformer::Options o;
    o.iterations = 5;
    auto b = [&] { return ArapDeformer::bind(tube, rig, o); };
    const std::vector<ga::Mot> m = {kIdentity, bend};
    same_through_any(b(), b(), m);
    CHECK(b().controls()[1] == Control{"tip", c_tip});
  }
  SECTION("skin: a control per bone at its head") {
    Rig r;
    r.skeleton = {Bone{.name = "upper", .head = {0, 0, 0}, .tail = {0, 0, 2}},
                  Bone{.name = "fore", .parent = 0, .head = {0, 0, 2}, .tail = {0, 0, 4}}};
    Eigen::MatrixXd W(tube.V.rows(), 2);
    for (Eigen::Index i = 0; i < tube.V.rows(); ++i) {
      const double t = std::clamp((tube.V(i, 2) - 1.5) / 1.0, 0.0, 1.0);
      W.row(i) << 1 - t, t;
    }
    r.weights = W.sparseView();
    auto b = [&] { return SkinDeformer::bind(tube, r, {}); };
    const std::vector<ga::Mot> m = {kIdentity, bend};
    same_through_any(b(), b(), m);
    CHECK(b().controls()[1] == Control{"fore", {0, 0, 2}});
  }
}

TEST_CASE("spline IK is one deformer: the tip lands on the moved target, identity keeps the rest target",
          "[deform][shape][ik]") {
  const Mesh tube = spinmotor::tube(0.25, 4.0, 41, 12);
  Rig rig{.handles = end_rings(tube, 4.0)};
  Eigen::MatrixXd chain(5, 3);
  for (int i = 0; i < 5; ++i) chain.row(i) << 0, 0, i;
  rig.ik = IkChain{.chain = chain, .target = {0, 0, 4}, .tolerance = 1e-8, .iterations = 200};
  SplineIkDeformer d = SplineIkDeformer::bind(tube, rig, {});
  REQUIRE(d.controls() == std::vector<Control>{{"ik.target", {0, 0, 4}}});

  Eigen::MatrixXd V;
  d.pose(std::vector<ga::Mot>{kIdentity}, V);
  CHECK((V - tube.V).cwiseAbs().maxCoeff() < 1e-9);  // a straight chain to its own tip: the rest tube

  const Vector3d target(1.2, 0.4, 3.3);
  const ga::Mot move = ga::from_isometry(Eigen::Isometry3d(Eigen::Translation3d(target - Vector3d(0, 0, 4))));
  d.pose(std::vector<ga::Mot>{move}, V);
  CHECK(d.fabrik_result().converged);
  CHECK((handle_centroid(V, rig.handles[1]) - target).norm() < 1e-6);
  // The base ring stays where it is: the root joint motor is the identity.
  CHECK((handle_centroid(V, rig.handles[0]) - handle_centroid(tube.V, rig.handles[0])).norm() < 1e-9);

  CHECK_THROWS_WITH(d.pose(std::vector<ga::Mot>{}, V), Catch::Contains("expected 1 motors"));
  Rig no_ik{.handles = rig.handles};
  CHECK_THROWS_WITH(SplineIkDeformer::bind(tube, no_ik, {}), Catch::Contains("no ik chain"));
  CHECK_THROWS_WITH(SplineIkDeformer::bind(tube, rig, {.controls = 3}),
                    Catch::Contains("needs at least 4 controls"));
}

TEST_CASE("option tables: every name parses back to its value, unknown names list the choices",
          "[deform][options]") {
  auto roundtrip = [](auto e) {
    using E = decltype(e);
    for (const auto& [v, name] : option_names(E{}).entries) {
      CHECK(parse_option<E>(name) == v);
      CHECK(option_name(v) == name);
    }
  };
  roundtrip(ga::Blend{});
  roundtrip(HarmonicWeights{});
  roundtrip(SplineBasis{});
  roundtrip(ControlMode{});
  roundtrip(FfdDeformer::Basis{});
  roundtrip(CageDeformer::Coordinates{});
  roundtrip(ArapEnergy{});
  roundtrip(ArapInitial{});
  roundtrip(SkinBlend{});
  roundtrip(Alignment{});
  CHECK(option_values<ga::Blend>() == std::vector<std::string>{"log", "pivot-log", "dlb"});
  CHECK(option_name(SkinBlend::DLB) == "dlb");
  CHECK_THROWS_WITH(parse_option<ga::Blend>("lgo", "x: "),
                    "x: unknown blend 'lgo' (one of: log, pivot-log, dlb)");
  CHECK_THROWS_WITH(option_name(static_cast<ArapEnergy>(7)), Catch::Contains("energy: value 7 has no name"));
}

}  // namespace test_deformer_shape
