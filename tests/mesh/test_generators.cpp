// Procedural meshes (mesh/generators.hpp): counts, topology, orientation, geometry and texture seams.
#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <numbers>
#include <utility>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/topology.hpp"

namespace test_generators {

using namespace spinmotor;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

constexpr double pi = std::numbers::pi;

double signed_volume(const Mesh& m) {
  double vol = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    vol += a.dot(b.cross(c)) / 6.0;
  }
  return vol;
}

double min_face_area(const Mesh& m) {
  double lo = 1e300;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    lo = std::min(lo, 0.5 * (b - a).cross(c - a).norm());
  }
  return lo;
}

int euler_characteristic(const Mesh& m) {
  return static_cast<int>(m.V.rows() - edge_topology(m.F).num_edges() + m.F.rows());
}

// Every directed edge occurs once: a consistently oriented manifold (closed: its twin occurs too).
void check_oriented_manifold(const Mesh& m, bool closed) {
  std::vector<std::pair<int, int>> h;
  h.reserve(3 * m.F.rows());
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) h.emplace_back(m.F(f, c), m.F(f, (c + 1) % 3));
  std::sort(h.begin(), h.end());
  CHECK(std::adjacent_find(h.begin(), h.end()) == h.end());
  if (closed) {
    bool all_twins = true;
    for (const auto& [a, b] : h) all_twins &= std::binary_search(h.begin(), h.end(), std::make_pair(b, a));
    CHECK(all_twins);
  }
  CHECK(m.F.minCoeff() >= 0);
  CHECK(m.F.maxCoeff() < m.V.rows());
}

// Exact volume of a discrete surface of revolution: the profile polygon (ρ, z) (from the bottom on
// the axis, up the outside, to the top on the axis) revolved with `sides` planar trapezoids per band.
// A wedge of angle Δ sweeps the chords between the two copies of each point: volume sin Δ ∫∫ ρ dA,
// and ∫∫ ρ dA = ∮ ρ²/2 dz (Green).
double revolution_volume(const std::vector<Eigen::Vector2d>& profile, int sides) {
  double integral = 0;
  for (size_t k = 0; k + 1 < profile.size(); ++k) {
    const Eigen::Vector2d a = profile[k], b = profile[k + 1];
    // ∫ ρ²/2 dz along the segment, ρ linear in the parameter
    integral += (b.y() - a.y()) * (a.x() * a.x() + a.x() * b.x() + b.x() * b.x()) / 6.0;
  }
  return sides * std::sin(2 * pi / sides) * integral;
}

std::vector<Eigen::Vector2d> profile_of(const Mesh& m, int rings, int sides) {
  std::vector<Eigen::Vector2d> p;
  p.emplace_back(0.0, m.V(rings * sides, 2));  // bottom pole
  for (int k = 0; k < rings; ++k) p.emplace_back(m.V.row(k * sides).head<2>().norm(), m.V(k * sides, 2));
  p.emplace_back(0.0, m.V(rings * sides + 1, 2));  // top pole
  return p;
}

// UVs exist per corner, and every UV triangle is counter-clockwise (orientation-preserving chart,
// so no face wraps across a seam) and not degenerate.
void check_uv(const Mesh& m, double u_max = 1.0) {
  REQUIRE(m.has_uv());
  CHECK(m.FUV.minCoeff() >= 0);
  CHECK(m.FUV.maxCoeff() < m.UV.rows());
  double lo = 1e300, hi = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector2d a = m.UV.row(m.FUV(f, 0)), b = m.UV.row(m.FUV(f, 1)), c = m.UV.row(m.FUV(f, 2));
    const Eigen::Vector2d e1 = b - a, e2 = c - a;
    const double area = 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
    lo = std::min(lo, area);
    hi = std::max(hi, area);
  }
  CHECK(lo > 0);
  CHECK(hi < 0.25);  // no face spans a large part of the chart (a wrapped face would)
  CHECK(m.UV.minCoeff() >= -1e-15);
  CHECK(m.UV.col(0).maxCoeff() <= u_max + 1e-15);
  CHECK(m.UV.col(1).maxCoeff() <= 1 + 1e-15);
}

}  // namespace

TEST_CASE("icosphere: 10·4^l + 2 vertices on the sphere, closed, outward, seam duplicated", "[generators]") {
  for (int level : {0, 1, 3}) {
    const Mesh m = icosphere(level, 2.0);
    const int p = 1 << (2 * level);
    CHECK(m.V.rows() == 10 * p + 2);
    CHECK(m.F.rows() == 20 * p);
    CHECK(euler_characteristic(m) == 2);
    check_oriented_manifold(m, true);
    // The valence-5 south pole has no edge on the seam meridian: its straddling fan face spans
    // u ∈ [0.9, 1.1] at every level (documented); no face wraps.
    check_uv(m, 1.1);
    CHECK((m.V.rowwise().norm().array() - 2.0).abs().maxCoeff() < 1e-14);
    CHECK(m.V.row(0).isApprox(Eigen::RowVector3d(0, 0, 2)));
    CHECK(m.V.row(11).isApprox(Eigen::RowVector3d(0, 0, -2)));
    CHECK(signed_volume(m) > 0);
    CHECK((m.FUV.array() != m.F.array()).any());  // the seam and the poles have their own UV rows
  }
  // Volume converges to 4/3 π r³ from below (inscribed polyhedron).
  const double v4 = signed_volume(icosphere(4, 2.0)), exact = 4.0 / 3.0 * pi * 8.0;
  CHECK(v4 < exact);
  CHECK_THAT(v4, WithinRel(exact, 5e-3));
  // Level 0 is the regular icosahedron: all 30 edges have the same length 4/√(10 + 2√5).
  const Mesh ico = icosphere(0);
  const EdgeTopology t = edge_topology(ico.F);
  for (Eigen::Index e = 0; e < t.num_edges(); ++e)
    CHECK_THAT((ico.V.row(t.E(e, 0)) - ico.V.row(t.E(e, 1))).norm(),
               WithinRel(4.0 / std::sqrt(10.0 + 2.0 * std::sqrt(5.0)), 1e-14));
}

TEST_CASE("icosphere: a 655k-vertex mesh (level 8) is valid", "[generators]") {
  const Mesh m = icosphere(8);
  CHECK(m.V.rows() == 655362);
  CHECK(m.F.rows() == 1310720);
  CHECK(m.F.maxCoeff() == m.V.rows() - 1);
  CHECK(min_face_area(m) > 0);
}

TEST_CASE("uv_sphere: rings·sectors + 2 vertices, closed, outward, sphere volume", "[generators]") {
  const Mesh m = uv_sphere(30, 62, 1.5);
  CHECK(m.V.rows() == 30 * 62 + 2);
  CHECK(m.F.rows() == 2 * 30 * 62);
  CHECK(euler_characteristic(m) == 2);
  check_oriented_manifold(m, true);
  check_uv(m);
  CHECK((m.V.rowwise().norm().array() - 1.5).abs().maxCoeff() < 1e-14);
  CHECK(m.V(30 * 62, 2) == -1.5);  // south pole
  CHECK(m.V(30 * 62 + 1, 2) == 1.5);
  const double vol = signed_volume(m), exact = 4.0 / 3.0 * pi * 1.5 * 1.5 * 1.5;
  CHECK(vol < exact);
  CHECK_THAT(vol, WithinRel(exact, 5e-3));
  CHECK_THAT(vol, WithinRel(revolution_volume(profile_of(m, 30, 62), 62), 1e-12));
  // The documented 1M-vertex request.
  const Mesh big = uv_sphere(707, 1414);
  CHECK(big.V.rows() == 999700);
  CHECK(min_face_area(big) > 0);
}

TEST_CASE("capsule of length 0 is the uv_sphere, capsule is closed and its volume is right", "[generators]") {
  const Mesh s = uv_sphere(9, 16, 0.7), c0 = capsule(0.7, 0.0, 9, 16);
  REQUIRE(s.V.rows() == c0.V.rows());
  CHECK((s.V - c0.V).cwiseAbs().maxCoeff() < 1e-14);
  CHECK(s.F == c0.F);
  CHECK((s.UV - c0.UV).cwiseAbs().maxCoeff() < 1e-15);

  const double r = 0.5, len = 3.0;
  const Mesh m = capsule(r, len, 120, 96);
  CHECK(m.V.rows() == 120 * 96 + 2);
  CHECK(euler_characteristic(m) == 2);
  check_oriented_manifold(m, true);
  check_uv(m);
  CHECK_THAT(m.V.col(2).minCoeff(), WithinAbs(-r, 1e-15));
  CHECK_THAT(m.V.col(2).maxCoeff(), WithinAbs(len + r, 1e-15));
  // Every vertex lies on the capsule: distance to the segment z ∈ [0, len] on the axis equals r.
  double worst = 0;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    const Eigen::Vector3d p = m.V.row(i);
    const Eigen::Vector3d q(0, 0, std::clamp(p.z(), 0.0, len));
    worst = std::max(worst, std::abs((p - q).norm() - r));
  }
  CHECK(worst < 1e-14);
  const double exact = pi * r * r * len + 4.0 / 3.0 * pi * r * r * r;
  CHECK_THAT(signed_volume(m), WithinRel(exact, 2e-3));
  CHECK_THAT(signed_volume(m), WithinRel(revolution_volume(profile_of(m, 120, 96), 96), 1e-12));
}

TEST_CASE("tube: open has two boundary loops and χ = 0, capped is a closed sphere", "[generators]") {
  const Mesh open = tube(0.5, 2.0, 400, 200, false);  // the "80k-vertex tube"
  CHECK(open.V.rows() == 80000);
  CHECK(open.F.rows() == 2 * 399 * 200);
  CHECK(euler_characteristic(open) == 0);
  check_oriented_manifold(open, false);
  check_uv(open);
  const auto loops = boundary_loops(open.F);
  REQUIRE(loops.size() == 2);
  CHECK(loops[0].size() == 200);
  CHECK(loops[1].size() == 200);
  CHECK(open.V.col(2).minCoeff() == 0.0);
  CHECK(open.V.col(2).maxCoeff() == 2.0);
  // Outward normals: the normal of every face points away from the axis.
  bool outward = true;
  for (Eigen::Index f = 0; f < open.F.rows(); ++f) {
    const Eigen::Vector3d a = open.V.row(open.F(f, 0)), b = open.V.row(open.F(f, 1)),
                          c = open.V.row(open.F(f, 2));
    Eigen::Vector3d radial = (a + b + c) / 3.0;
    radial.z() = 0;
    outward &= (b - a).cross(c - a).dot(radial) > 0;
  }
  CHECK(outward);

  const Mesh capped = tube(0.5, 2.0, 10, 24, true);
  CHECK(capped.V.rows() == 10 * 24 + 2);
  CHECK(capped.F.rows() == 2 * 9 * 24 + 2 * 24);
  CHECK(euler_characteristic(capped) == 2);
  check_oriented_manifold(capped, true);
  check_uv(capped);
  CHECK(boundary_loops(capped.F).empty());
  // A prism over a regular 24-gon: volume exactly length · ½ n r² sin(2π/n).
  CHECK_THAT(signed_volume(capped), WithinRel(2.0 * 0.5 * 24 * 0.25 * std::sin(2 * pi / 24), 1e-13));
}

TEST_CASE("torus: u·v vertices, genus 1, outward, volume → 2π²Rr²", "[generators]") {
  const double R = std::sqrt(2.0), r = 1.0;
  const Mesh m = torus(R, r, 128, 64);
  CHECK(m.V.rows() == 128 * 64);
  CHECK(m.F.rows() == 2 * 128 * 64);
  CHECK(euler_characteristic(m) == 0);
  CHECK(boundary_loops(m.F).empty());
  check_oriented_manifold(m, true);
  check_uv(m);
  // The quads are planar isosceles trapezoids, so the mesh is a regular 64-gon of radius r swept
  // around a 128-gon: volume u·sin(2π/u) · R · (v/2) r² sin(2π/v) exactly (→ 2π²Rr²).
  const double exact = 128 * std::sin(2 * pi / 128) * R * 32 * r * r * std::sin(2 * pi / 64);
  CHECK_THAT(signed_volume(m), WithinRel(exact, 1e-13));
  CHECK_THAT(signed_volume(m), WithinRel(2 * pi * pi * R * r * r, 3e-3));
  // Every vertex is at distance r from the core circle.
  const Eigen::ArrayXd rho = m.V.leftCols(2).rowwise().norm().array();
  CHECK(((rho - R).square() + m.V.col(2).array().square() - r * r).abs().maxCoeff() < 1e-14);
}

TEST_CASE("grid: planar, CCW from +z, exact area and UV = normalised position", "[generators]") {
  const Mesh m = grid(Eigen::Vector2d(3.0, 2.0), Eigen::Vector2i(7, 5));
  CHECK(m.V.rows() == 35);
  CHECK(m.F.rows() == 2 * 6 * 4);
  CHECK(euler_characteristic(m) == 1);
  check_oriented_manifold(m, false);
  check_uv(m);
  CHECK(m.FUV == m.F);
  double area = 0;
  bool up = true;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    up &= n.z() > 0 && n.head<2>().norm() == 0;
    area += 0.5 * n.norm();
  }
  CHECK(up);
  CHECK_THAT(area, WithinRel(6.0, 1e-14));
  CHECK(m.V.col(0).minCoeff() == -1.5);
  CHECK(m.V.col(1).maxCoeff() == 1.0);
  CHECK(boundary_loops(m.F).size() == 1);
}

TEST_CASE("cross_bar: closed, outward, volume = length × area of the plus section", "[generators]") {
  const double len = 4.0, a = 0.5, w = 0.25;
  const Mesh m = cross_bar(len, a, w, 64);
  CHECK(euler_characteristic(m) == 2);
  check_oriented_manifold(m, true);
  check_uv(m);
  CHECK(min_face_area(m) > 0);
  CHECK_THAT(signed_volume(m), WithinRel(len * (2 * (2 * a) * w - w * w), 1e-13));
  CHECK(m.V.col(2).minCoeff() == 0.0);
  CHECK(m.V.col(2).maxCoeff() == len);
  CHECK(m.V.col(0).cwiseAbs().maxCoeff() == a);
  // Side walls are subdivided along the bar: 65 distinct z levels.
  std::vector<double> z(m.V.col(2).data(), m.V.col(2).data() + m.V.rows());
  std::sort(z.begin(), z.end());
  CHECK(std::unique(z.begin(), z.end()) - z.begin() == 65);
  const Mesh d = cross_bar();
  CHECK(d.V.rows() == m.V.rows());
}

TEST_CASE("generators reject bad parameters with spinmotor::Error", "[generators]") {
  CHECK_THROWS_AS(icosphere(-1), Error);
  CHECK_THROWS_AS(icosphere(11), Error);
  CHECK_THROWS_AS(icosphere(2, 0.0), Error);
  CHECK_THROWS_AS(uv_sphere(0, 8), Error);
  CHECK_THROWS_AS(uv_sphere(4, 2), Error);
  CHECK_THROWS_AS(grid(Eigen::Vector2d(1, 1), Eigen::Vector2i(1, 4)), Error);
  CHECK_THROWS_AS(grid(Eigen::Vector2d(1, -1), Eigen::Vector2i(4, 4)), Error);
  CHECK_THROWS_AS(torus(1.0, 1.0, 16, 8), Error);
  CHECK_THROWS_AS(torus(2.0, 1.0, 2, 8), Error);
  CHECK_THROWS_AS(tube(1.0, 2.0, 1, 8), Error);
  CHECK_THROWS_AS(tube(1.0, -2.0, 4, 8), Error);
  CHECK_THROWS_AS(capsule(1.0, 2.0, 4, 2), Error);
  CHECK_THROWS_AS(cross_bar(4.0, 0.5, 1.0, 8), Error);
  CHECK_THROWS_AS(cross_bar(4.0, 0.5, 0.25, 0), Error);
  CHECK_THROWS_WITH(torus(1.0, 2.0, 8, 8), Catch::Contains("torus") && Catch::Contains("r < R"));
  CHECK_THROWS_AS(uv_sphere(100000, 100000), Error);  // too large for int indices
}

}  // namespace test_generators
