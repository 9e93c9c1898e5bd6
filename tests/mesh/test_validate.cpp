// Validation (mesh/validate.hpp), require() and the opt-in repairs (mesh/repair.hpp), on small
// meshes whose defects are built by hand and on generated surfaces of known topology.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/repair.hpp"
#include "spinmotor/mesh/validate.hpp"

namespace test_validate {

using namespace spinmotor;

namespace {

Mesh make(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Mesh m;
  m.V = V;
  m.F = F;
  return m;
}

// Regular tetrahedron, faces counter-clockwise seen from outside.
Mesh tetrahedron() {
  Eigen::MatrixXd V(4, 3);
  V << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  Eigen::MatrixXi F(4, 3);
  F << 0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2;
  return make(V, F);
}

// Two tetrahedra sharing vertex 0 (the second one translated and mirrored through vertex 0).
Mesh two_tetrahedra_touching() {
  const Mesh t = tetrahedron();
  Eigen::MatrixXd V(7, 3);
  V.topRows(4) = t.V;
  for (int i = 1; i < 4; ++i)
    V.row(3 + i) = 2 * t.V.row(0) - t.V.row(i);  // point reflection: keeps orientation
  Eigen::MatrixXi F(8, 3);
  F.topRows(4) = t.F;
  for (int f = 0; f < 4; ++f)
    for (int c = 0; c < 3; ++c) F(4 + f, c) = t.F(f, c) == 0 ? 0 : t.F(f, c) + 3;
  return make(V, F);
}

// A strip of n quads closed into a Möbius band (the last rung joined after a half twist).
Mesh moebius(int n) {
  Eigen::MatrixXd V(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n, w = 0.3 * std::cos(t / 2), h = 0.3 * std::sin(t / 2);
    for (int s = 0; s < 2; ++s) {
      const double sgn = s ? 1 : -1;
      V.row(2 * i + s) << (1 + sgn * w) * std::cos(t), (1 + sgn * w) * std::sin(t), sgn * h;
    }
  }
  Eigen::MatrixXi F(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i, b = 2 * i + 1;
    int c = 2 * (i + 1), d = 2 * (i + 1) + 1;
    if (i == n - 1) c = 1, d = 0;  // the half twist swaps the two sides
    F.row(2 * i) << a, c, b;
    F.row(2 * i + 1) << b, c, d;
  }
  return make(V, F);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("surfaces of known topology: counts, Euler characteristic, genus", "[validate]") {
  SECTION("tetrahedron") {
    const MeshReport r = validate(tetrahedron());
    CHECK(r.vertices == 4);
    CHECK(r.faces == 4);
    CHECK(r.edges == 6);
    CHECK(r.components == 1);
    CHECK(r.euler_characteristic == 2);
    CHECK(r.genus == 0);
    CHECK(r.genus_note.empty());
    CHECK(r.is_closed());
    CHECK(r.is_manifold());
    CHECK(r.is_oriented());
    CHECK_FALSE(r.has_defects());
    CHECK(r.defects_summary().empty());
    CHECK(r.mean_face_area == Approx(2 * std::sqrt(3.0)));  // edge 2√2: area (√3/4)·8
  }
  SECTION("icosphere level 3: V − E + F = 2") {
    const MeshReport r = validate(icosphere(3));
    CHECK(r.vertices == 642);
    CHECK(r.edges == 1920);
    CHECK(r.euler_characteristic == 2);
    CHECK(r.genus == 0);
    CHECK_FALSE(r.has_defects());
  }
  SECTION("torus: χ = 0, genus 1; two disjoint tori: genus 2, two components") {
    const Mesh t = torus(2.0, 0.5, 12, 8);
    const MeshReport r = validate(t);
    CHECK(r.euler_characteristic == 0);
    CHECK(r.genus == 1);
    CHECK(r.is_closed());
    Mesh two;
    two.V.resize(2 * t.V.rows(), 3);
    two.V << t.V, t.V.rowwise() + Eigen::RowVector3d(10, 0, 0);
    two.F.resize(2 * t.F.rows(), 3);
    two.F << t.F, t.F.array() + static_cast<int>(t.V.rows());
    const MeshReport r2 = validate(two);
    CHECK(r2.components == 2);
    CHECK(r2.genus == 2);
    CHECK(r2.euler_characteristic == 0);
  }
  SECTION("open surfaces: a grid is a disk, an open tube an annulus; boundaries are not defects") {
    const MeshReport g = validate(grid({2.0, 1.0}, {5, 4}));
    CHECK(g.boundary_edges == 2 * (4 + 3));
    CHECK(g.boundary_loops == 1);
    CHECK(g.first_boundary_edge == std::array<int, 2>{0, 1});
    CHECK(g.euler_characteristic == 1);
    CHECK(g.genus == 0);
    CHECK_FALSE(g.is_closed());
    CHECK_FALSE(g.has_defects());
    const MeshReport t = validate(tube(1.0, 2.0, 5, 10));
    CHECK(t.boundary_loops == 2);
    CHECK(t.boundary_edges == 20);
    CHECK(t.euler_characteristic == 0);
    CHECK(t.genus == 0);  // 2 − χ − b = 0
  }
  SECTION("empty mesh") {
    const MeshReport r = validate(Mesh{});
    CHECK(r.faces == 0);
    CHECK(r.components == 0);
    CHECK(r.genus == -1);
  }
}

TEST_CASE("each defect is found and its first offender named", "[validate]") {
  SECTION("non-manifold edge: three faces on edge (0, 1); its vertices are not also non-manifold vertices") {
    Eigen::MatrixXd V(5, 3);
    V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1;
    Eigen::MatrixXi F(3, 3);
    F << 0, 1, 2, 1, 0, 3, 0, 1, 4;
    const MeshReport r = validate(make(V, F));
    CHECK(r.non_manifold_edges == 1);
    CHECK(r.first_non_manifold_edge == std::array<int, 2>{0, 1});
    CHECK(r.non_manifold_edge_faces == 3);
    CHECK(r.non_manifold_vertices == 0);
    CHECK(r.inconsistent_orientation == 0);  // orientation is not defined across a non-manifold edge
    CHECK(r.genus == -1);
    CHECK(r.genus_note == "not a manifold");
    CHECK(r.defects_summary() == "1 non-manifold edge: edge (0, 1) is shared by 3 faces");
  }
  SECTION("non-manifold vertex: two tetrahedra touching at a vertex, and a bow tie") {
    const MeshReport r = validate(two_tetrahedra_touching());
    CHECK(r.non_manifold_vertices == 1);
    CHECK(r.first_non_manifold_vertex == 0);
    CHECK(r.non_manifold_vertex_fans == 2);
    CHECK(r.non_manifold_edges == 0);
    CHECK(r.components == 1);
    CHECK(r.is_closed());
    CHECK(r.euler_characteristic == 3);  // two spheres (4) sharing one vertex
    CHECK(r.inconsistent_orientation == 0);
    Eigen::MatrixXd V(5, 3);
    V << 0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0;
    Eigen::MatrixXi F(2, 3);
    F << 0, 1, 2, 0, 3, 4;
    const MeshReport b = validate(make(V, F));
    CHECK(b.non_manifold_vertices == 1);  // pinched boundary
    CHECK(b.first_non_manifold_vertex == 0);
    CHECK(b.boundary_edges == 6);
  }
  SECTION("inconsistent orientation: one flipped face of a tetrahedron flags its three edges") {
    Mesh t = tetrahedron();
    t.F.row(2) = t.F.row(2).reverse().eval();
    const MeshReport r = validate(t);
    CHECK(r.inconsistent_orientation == 3);
    CHECK((r.inconsistent_edge_faces[0] == 2 || r.inconsistent_edge_faces[1] == 2));
    CHECK(r.genus == -1);
    CHECK(r.genus_note == "not consistently oriented");
    CHECK_FALSE(r.is_oriented());
  }
  SECTION("a Möbius band cannot be oriented: some edge is inconsistent") {
    const MeshReport r = validate(moebius(12));
    CHECK(r.inconsistent_orientation >= 1);
    CHECK(r.boundary_loops == 1);  // its boundary is one loop of twice the length
    CHECK(r.boundary_edges == 24);
    CHECK(r.euler_characteristic == 0);
  }
  SECTION("degenerate faces: repeated index, collinear corners, tiny relative area; not NaN faces") {
    Mesh t = tetrahedron();
    Eigen::MatrixXd V(8, 3);
    V << t.V, 0, 0, 0, 1, 1, 1, 2, 2, 2, 1e-6, 0, 0;
    Eigen::MatrixXi F(7, 3);
    F << t.F, 0, 0, 1,  // repeated index
        4, 5, 6,        // collinear (0,0,0), (1,1,1), (2,2,2)
        4, 7, 0;        // area ~ 1e-6 · |v0| / 2 · sin: relative to mean ~ 1.5e-7: not degenerate
    const MeshReport r = validate(make(V, F));
    CHECK(r.degenerate_faces == 2);
    CHECK(r.first_degenerate_face == 4);
    CHECK(r.first_degenerate_area == 0);
    V(7, 0) = 1e-12;  // now ~1e-13 of the mean: degenerate
    CHECK(validate(make(V, F)).degenerate_faces == 3);
    V(5, 0) = std::nan("");
    const MeshReport n = validate(make(V, F));
    CHECK(n.nonfinite_vertices == 1);
    CHECK(n.first_nonfinite_vertex == 5);
    CHECK(n.degenerate_faces == 2);  // the collinear face now has a NaN corner: reported via the vertex
    CHECK(std::isfinite(n.mean_face_area));
  }
  SECTION("duplicate vertices: k coincident count k − 1; 0.0 == −0.0; NaN never") {
    Eigen::MatrixXd V(7, 3);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0, -0.0, 0, 0, nan, 0, 0, nan, 0, 0;
    Eigen::MatrixXi F(1, 3);
    F << 0, 1, 2;
    const MeshReport r = validate(make(V, F));
    CHECK(r.duplicate_vertices == 2);
    CHECK(r.first_duplicate_vertex == 3);
    CHECK(r.first_duplicate_of == 1);
    CHECK(r.unreferenced_vertices == 4);
    CHECK(r.first_unreferenced_vertex == 3);
    CHECK(r.nonfinite_vertices == 2);
    CHECK(r.has_defects());
  }
  SECTION("malformed meshes throw naming the face") {
    Mesh t = tetrahedron();
    t.F(2, 1) = 4;
    CHECK_THAT(error_of([&] { validate(t); }),
               Catch::Contains("face 2 references vertex 4") && Catch::Contains("4 vertices"));
    t.F(2, 1) = -1;
    CHECK_THROWS_AS(validate(t), Error);
  }
}

TEST_CASE("require(): each requirement names the operation and the first offending element", "[validate]") {
  const Mesh tet = tetrahedron();
  CHECK_NOTHROW(require(tet,
                        {.manifold = true,
                         .oriented = true,
                         .no_degenerate = true,
                         .closed = true,
                         .genus0 = true,
                         .single_component = true,
                         .no_unreferenced = true,
                         .no_duplicates = true,
                         .min_faces = 4},
                        "op"));
  const MeshReport ok = require(tet, {}, "op");
  CHECK(ok.genus == 0);

  const Mesh g = grid({1.0, 1.0}, {3, 3});
  CHECK(error_of([&] { require(g, {.closed = true}, "spin_transform"); }) ==
        "spin_transform needs a closed mesh: edge (0, 1) is on a boundary (8 boundary edges in 1 loop)");
  CHECK_NOTHROW(require(g, {.manifold = true, .genus0 = true}, "op"));  // a disk has genus 0
  CHECK(error_of([&] { require(g, {.min_faces = 100}, "op"); }) ==
        "op needs at least 100 faces: the mesh has 8");

  CHECK_THAT(error_of([&] { require(two_tetrahedra_touching(), {.manifold = true}, "arap"); }),
             Catch::StartsWith("arap needs a manifold mesh: vertex 0 joins 2 separate fans of faces"));
  CHECK_THAT(error_of([&] { require(two_tetrahedra_touching(), {.genus0 = true}, "snap"); }),
             Catch::StartsWith("snap needs a manifold mesh"));
  Mesh flipped = tet;
  flipped.F.row(0) = flipped.F.row(0).reverse().eval();
  CHECK_THAT(error_of([&] { require(flipped, {.oriented = true}, "op"); }),
             Catch::StartsWith("op needs consistently oriented faces: faces ") &&
                 Catch::Contains("in the same direction"));
  CHECK_THAT(error_of([&] { require(torus(2, 0.5, 8, 6), {.genus0 = true}, "op"); }),
             Catch::Equals("op needs a genus-0 surface: the mesh has genus 1"));
  Mesh nan = tet;
  nan.V(3, 1) = std::nan("");
  CHECK(error_of([&] { require(nan, {}, "op"); }) ==
        "op needs finite vertex coordinates: vertex 3 has a NaN or infinite coordinate (1 such vertex)");
  CHECK_NOTHROW(require(nan, {.finite = false}, "op"));
  Mesh extra = tet;
  extra.V.conservativeResize(6, 3);
  extra.V.row(4) << 5, 5, 5;
  extra.V.row(5) = extra.V.row(0);
  CHECK_THAT(
      error_of([&] { require(extra, {.no_unreferenced = true}, "op"); }),
      Catch::StartsWith("op needs every vertex in a face: vertex 4 is in no face (2 unreferenced vertices"));
  CHECK_THAT(
      error_of([&] { require(extra, {.no_duplicates = true}, "op"); }),
      Catch::StartsWith("op needs distinct vertex positions: vertex 5 has the same coordinates as vertex 0"));
  Mesh apart = tet;
  apart.V.conservativeResize(8, 3);
  apart.V.bottomRows(4) = tet.V.rowwise() + Eigen::RowVector3d(5, 0, 0);
  apart.F.conservativeResize(8, 3);
  apart.F.bottomRows(4) = tet.F.array() + 4;
  CHECK(error_of([&] { require(apart, {.single_component = true}, "op"); }) ==
        "op needs a single connected component: the mesh has 2");
  Mesh bad = tet;
  bad.F(1, 1) = 9;
  CHECK_THAT(error_of([&] { require(bad, {}, "op"); }),
             Catch::StartsWith("op: invalid mesh: face 1 references vertex 9"));
  Mesh degenerate = tet;
  degenerate.F.row(3) << 1, 1, 2;
  CHECK_THAT(error_of([&] { require(degenerate, {.no_degenerate = true}, "op"); }),
             Catch::StartsWith("op needs non-degenerate faces: face 3 has zero area"));
}

TEST_CASE("repairs: remove unreferenced vertices, merge exact duplicates", "[validate][repair]") {
  SECTION("remove_unreferenced_vertices keeps order, positions of every corner, and UV") {
    Mesh m = tetrahedron();
    Eigen::MatrixXd V(6, 3);
    V << 9, 9, 9, m.V.topRows(2), 8, 8, 8, m.V.bottomRows(2);
    m.V = V;  // unreferenced vertices 0 and 3
    m.F = (m.F.array() + 1).unaryExpr([](int i) { return i >= 3 ? i + 1 : i; });
    m.UV = Eigen::MatrixXd::Random(5, 2);
    m.FUV = Eigen::MatrixXi::Constant(4, 3, 4);
    CHECK(validate(m).unreferenced_vertices == 2);
    Eigen::VectorXi map;
    const Mesh r = remove_unreferenced_vertices(m, &map);
    CHECK(r.V.rows() == 4);
    CHECK(r.V == tetrahedron().V);
    CHECK(r.F == tetrahedron().F);
    CHECK(map == (Eigen::VectorXi(6) << -1, 0, 1, -1, 2, 3).finished());
    CHECK(r.UV == m.UV);
    CHECK(r.FUV == m.FUV);
    CHECK_FALSE(validate(r).has_defects());
  }
  SECTION("merge_duplicate_vertices welds an exploded octahedron back into a closed sphere") {
    Eigen::MatrixXd P(6, 3);
    P << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
    Eigen::MatrixXi T(8, 3);
    T << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
    Mesh soup;  // one vertex per corner, as STL stores it
    soup.V.resize(24, 3);
    soup.F.resize(8, 3);
    for (int f = 0; f < 8; ++f)
      for (int c = 0; c < 3; ++c) {
        soup.V.row(3 * f + c) = P.row(T(f, c));
        soup.F(f, c) = 3 * f + c;
      }
    REQUIRE(soup.V(5, 0) == 0.0);
    soup.V(5, 0) = -0.0;  // a -0.0 still merges with 0.0
    soup.UV = Eigen::MatrixXd::Random(24, 2);
    soup.FUV = soup.F;
    const MeshReport before = validate(soup);
    CHECK(before.duplicate_vertices == 18);
    CHECK(before.components == 8);
    Eigen::VectorXi map;
    const Mesh w = merge_duplicate_vertices(soup, &map);
    CHECK(w.V.rows() == 6);
    CHECK(map.maxCoeff() == 5);
    for (int f = 0; f < 8; ++f)
      for (int c = 0; c < 3; ++c) CHECK(w.V.row(w.F(f, c)) == soup.V.row(soup.F(f, c)));
    CHECK(w.UV == soup.UV);  // per-corner texture coordinates are untouched
    CHECK(w.FUV == soup.FUV);
    const MeshReport after = validate(w);
    CHECK(after.duplicate_vertices == 0);
    CHECK(after.components == 1);
    CHECK(after.genus == 0);
    CHECK(after.is_closed());
    CHECK_FALSE(after.has_defects());
  }
  SECTION("merging never touches non-finite vertices and keeps faces that become degenerate") {
    Eigen::MatrixXd V(5, 3);
    V << 0, 0, 0, 1, 0, 0, 0, 0, 0, NAN, 0, 0, NAN, 0, 0;
    Eigen::MatrixXi F(2, 3);
    F << 0, 1, 2, 1, 3, 4;
    Eigen::VectorXi map;
    const Mesh w = merge_duplicate_vertices(make(V, F), &map);
    CHECK(w.V.rows() == 4);
    CHECK(map == (Eigen::VectorXi(5) << 0, 1, 0, 2, 3).finished());
    CHECK(w.F.row(0) == Eigen::RowVector3i(0, 1, 0));
    CHECK(validate(w).degenerate_faces == 1);
  }
  SECTION("bad indices throw") {
    Mesh t = tetrahedron();
    t.F(0, 0) = 7;
    CHECK_THROWS_AS(remove_unreferenced_vertices(t), Error);
    CHECK_THROWS_AS(merge_duplicate_vertices(t), Error);
  }
}

}  // namespace test_validate
