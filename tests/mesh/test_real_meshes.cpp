// The real meshes of the shared folder (meshes/) load and validate with the counts their README states.
// Each file is parsed and validated once (a static cache) so the whole file stays fast.
// `test_real_meshes "[.print]"` prints the full table of reports.
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "shared_data.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/validate.hpp"

namespace test_real_meshes {

using namespace spinmotor;
namespace fs = std::filesystem;

namespace {

struct Loaded {
  Mesh mesh;
  MeshReport report;
};

const Loaded& load(const std::string& name) {
  static std::map<std::string, Loaded> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    Loaded l;
    l.mesh = read_mesh(fs::path(SPINMOTOR_MESHES_DIR) / name);
    l.report = validate(l.mesh);
    it = cache.emplace(name, std::move(l)).first;
  }
  return it->second;
}

const MeshReport& report(const std::string& name) { return load(name).report; }

// Independent of validate(): on a closed triangle mesh every edge has two faces, so E = 3F/2 and
// genus 0 means V − 3F/2 + F = 2.
void check_closed_genus0(const std::string& name, Eigen::Index v, Eigen::Index f) {
  INFO(name);
  const MeshReport& r = report(name);
  CHECK(r.vertices == v);
  CHECK(r.faces == f);
  CHECK(r.is_closed());
  CHECK(r.boundary_loops == 0);
  CHECK(r.components == 1);
  CHECK(r.genus == 0);
  CHECK(r.euler_characteristic == 2);
  CHECK(f % 2 == 0);
  CHECK(v - 3 * f / 2 + f == 2);
  CHECK(r.edges == 3 * f / 2);
  CHECK_FALSE(r.has_defects());
}

long count_lines_starting(const fs::path& p, const std::string& prefix) {
  std::ifstream in(p);
  long n = 0;
  for (std::string line; std::getline(in, line);) n += line.rfind(prefix, 0) == 0;
  return n;
}

}  // namespace

TEST_CASE("every mesh in the shared folder loads and validates", "[real]") {
  SPINMOTOR_REQUIRE_MESHES();
  int count = 0;
  for (const auto& e : fs::recursive_directory_iterator(SPINMOTOR_MESHES_DIR)) {
    if (e.path().extension() != ".obj") continue;
    const std::string rel = fs::relative(e.path(), SPINMOTOR_MESHES_DIR).string();
    INFO(rel);
    CHECK_NOTHROW(load(rel));
    CHECK(load(rel).mesh.F.rows() > 0);
    ++count;
  }
  CHECK(count >= 13);
}

TEST_CASE("closed genus-0 meshes: spot, homer, fandisk, cheburashka, nefertiti, sphere", "[real]") {
  SPINMOTOR_REQUIRE_MESHES();
  check_closed_genus0("spot.obj", 2930, 5856);
  check_closed_genus0("homer.obj", 6002, 12000);
  check_closed_genus0("fandisk.obj", 6475, 12946);
  check_closed_genus0("cheburashka.obj", 6669, 13334);
  check_closed_genus0("nefertiti.obj", 49971, 99938);
  check_closed_genus0("spinxform/sphere.obj", 4002, 8000);
  check_closed_genus0("spinxform/bumpy_reference.obj", 4002, 8000);
}

TEST_CASE("cow: no boundary, Euler characteristic 1, a pinched (non-manifold) vertex", "[real]") {
  SPINMOTOR_REQUIRE_MESHES();
  const MeshReport& r = report("cow.obj");
  CHECK(r.vertices == 2903);
  CHECK(r.faces == 5804);
  CHECK(r.boundary_edges == 0);
  CHECK(r.euler_characteristic == 1);
  CHECK(r.non_manifold_vertices == 1);
  CHECK(r.first_non_manifold_vertex == 253);
  CHECK(r.non_manifold_vertex_fans == 2);
  CHECK(r.non_manifold_edges == 0);
  CHECK(r.genus == -1);  // not defined on a non-manifold
  CHECK(r.has_defects());
  // Splitting the pinched vertex into its two fans would give V' = 2904, χ' = 2: a sphere.
  CHECK(r.vertices + 1 - r.edges + r.faces == 2);
}

TEST_CASE("beetle: 47 non-manifold edges, 296 boundary edges", "[real]") {
  SPINMOTOR_REQUIRE_MESHES();
  const MeshReport& r = report("beetle.obj");
  CHECK(r.vertices == 1148);
  CHECK(r.faces == 2053);
  CHECK(r.non_manifold_edges == 47);
  CHECK(r.boundary_edges == 296);
  CHECK(r.has_defects());
}

TEST_CASE("alligator: open, 433 boundary edges, a disk", "[real]") {
  SPINMOTOR_REQUIRE_MESHES();
  const MeshReport& r = report("alligator.obj");
  CHECK(r.vertices == 3208);
  CHECK(r.faces == 5981);
  CHECK(r.boundary_edges == 433);
  CHECK(r.boundary_loops == 1);
  CHECK(r.euler_characteristic == 1);
  CHECK(r.genus == 0);
  CHECK_FALSE(r.has_defects());  // a boundary is a property, not a defect
}

TEST_CASE("teapot: 1036 boundary edges, several components", "[real]") {
  SPINMOTOR_REQUIRE_MESHES();
  const MeshReport& r = report("teapot.obj");
  CHECK(r.vertices == 3644);
  CHECK(r.faces == 6320);
  CHECK(r.boundary_edges == 1036);
  CHECK(r.components == 4);
  // Not in the README: the pieces are not welded where they meet.
  CHECK(r.duplicate_vertices == 403);
  CHECK(r.non_manifold_vertices == 38);
}

TEST_CASE("stanford bunny: 223 boundary edges, 1113 unreferenced vertices", "[real]") {
  SPINMOTOR_REQUIRE_MESHES();
  const MeshReport& r = report("stanford-bunny.obj");
  CHECK(r.vertices == 35947);
  CHECK(r.faces == 69451);
  CHECK(r.boundary_edges == 223);
  CHECK(r.boundary_loops == 5);
  CHECK(r.unreferenced_vertices == 1113);
  CHECK(r.components == 1);
  CHECK(r.genus == 0);  // a sphere with 5 holes: χ = 2 − 5
  CHECK(r.euler_characteristic == -3);
}

TEST_CASE("ogre: 44 components, degenerate faces insensitive to the threshold", "[real]") {
  SPINMOTOR_REQUIRE_MESHES();
  const Loaded& l = load("ogre.obj");
  const MeshReport& r = l.report;
  CHECK(r.vertices == 62194);
  CHECK(r.components == 44);
  CHECK(r.degenerate_faces == 4);
  // Independent area computation: the count is the same for every ratio from 1e-16 to 1e-4, so the
  // choice kDegenerateAreaRatio = 1e-10 is not what decides it.
  const Mesh& m = l.mesh;
  std::vector<double> a(static_cast<std::size_t>(m.F.rows()));
  double sum = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d p = m.V.row(m.F(f, 0)), q = m.V.row(m.F(f, 1)), s = m.V.row(m.F(f, 2));
    sum += a[f] = 0.5 * (q - p).cross(s - p).norm();
  }
  const double mean = sum / static_cast<double>(a.size());
  for (double t = 1e-16; t < 2e-4; t *= 10) {
    INFO("ratio " << t);
    CHECK(std::count_if(a.begin(), a.end(), [&](double x) { return x <= t * mean; }) == 4);
  }
}

TEST_CASE("spot and sphere: OBJ round trip keeps every vt and every face's vt index", "[real][io]") {
  SPINMOTOR_REQUIRE_MESHES();
  const fs::path dir = fs::temp_directory_path() / ("spinmotor_test_real_" + std::to_string(::getpid()));
  for (const auto& [name, nvt] :
       {std::pair<std::string, long>{"spot.obj", 3225}, {"spinxform/sphere.obj", 4242}}) {
    INFO(name);
    const Mesh& m = load(name).mesh;
    CHECK(m.UV.rows() == nvt);
    CHECK(count_lines_starting(fs::path(SPINMOTOR_MESHES_DIR) / name, "vt ") == nvt);
    REQUIRE(m.has_uv());
    const fs::path out = dir / "copy.obj";
    write_mesh(out, m);
    CHECK(count_lines_starting(out, "vt ") == nvt);
    const Mesh r = read_mesh(out);
    CHECK(r.V == m.V);
    CHECK(r.F == m.F);
    CHECK(r.UV == m.UV);
    CHECK(r.FUV == m.FUV);
  }
  fs::remove_all(dir);
}

TEST_CASE("print the reports of every real mesh", "[.print]") {
  SPINMOTOR_REQUIRE_MESHES();
  std::printf("%-30s %6s %6s %5s %5s %6s %5s %5s %4s %4s %5s %5s %5s %6s %4s\n", "mesh", "V", "F", "comp",
              "loops", "bedges", "chi", "genus", "nmE", "nmV", "degen", "dup", "unref", "nonfin", "flip");
  for (const char* name : {"spot.obj", "cow.obj", "beetle.obj", "alligator.obj", "teapot.obj", "homer.obj",
                           "fandisk.obj", "cheburashka.obj", "stanford-bunny.obj", "nefertiti.obj",
                           "ogre.obj", "spinxform/sphere.obj", "spinxform/bumpy_reference.obj"}) {
    const MeshReport& r = report(name);
    std::printf("%-30s %6ld %6ld %5d %5d %6ld %5lld %5d %4ld %4ld %5ld %5ld %5ld %6ld %4ld\n", name,
                (long)r.vertices, (long)r.faces, r.components, r.boundary_loops, (long)r.boundary_edges,
                r.euler_characteristic, r.genus, (long)r.non_manifold_edges, (long)r.non_manifold_vertices,
                (long)r.degenerate_faces, (long)r.duplicate_vertices, (long)r.unreferenced_vertices,
                (long)r.nonfinite_vertices, (long)r.inconsistent_orientation);
    if (r.has_defects()) std::printf("    %s\n", r.defects_summary().c_str());
    if (r.genus < 0) std::printf("    genus undefined: %s\n", r.genus_note.c_str());
  }
}

}  // namespace test_real_meshes
