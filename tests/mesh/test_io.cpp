// Mesh I/O (mesh/io.hpp) and atomic output (mesh/atomic_file.hpp): round trips keep positions and
// texture coordinates bit for bit, parse errors name file:line, failed writes leave no file behind,
// and OpenMesh's independent readers/writers agree with ours.
#include <unistd.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/openmesh_interop.hpp"

namespace test_io {

using namespace spinmotor;
namespace fs = std::filesystem;

namespace {

// A fresh directory per test case, removed at the end.
struct TempDir {
  fs::path path;
  TempDir() {
    static int counter = 0;
    path = fs::temp_directory_path() /
           ("spinmotor_test_io_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  fs::path operator/(const std::string& name) const { return path / name; }
  std::size_t entries() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(path), fs::directory_iterator()));
  }
};

void write_bytes(const fs::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary);
  out << s;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// An octahedron whose coordinates are not representable in float nor short decimals, with
// per-corner texture coordinates that have a seam (8 uv for 6 vertices).
Mesh octahedron() {
  Mesh m;
  const double a = 1.0 / 3.0, b = std::sqrt(2.0), c = -std::exp(1.0) * 1e-7;
  m.V.resize(6, 3);
  m.V << b, c, a, -b, a, c, a, b, c, c, -b, a, a, c, b, -a, -c, -b;
  m.F.resize(8, 3);
  m.F << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  m.UV.resize(8, 2);
  for (int i = 0; i < 8; ++i) m.UV.row(i) << i / 7.0, std::sin(i + 0.5);
  m.FUV = m.F;
  m.FUV(7, 0) = 6;  // a seam: vertex 0 has two uv
  m.FUV(6, 2) = 7;
  return m;
}

// Every corner of `b` sits where the same corner of `a` does (vertex numbering may differ: STL
// renumbers vertices in order of first appearance).
void check_same_corners(const Mesh& a, const Mesh& b, double tol) {
  REQUIRE(b.F.rows() == a.F.rows());
  for (Eigen::Index f = 0; f < a.F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) CHECK(std::abs(a.V(a.F(f, c), k) - b.V(b.F(f, c), k)) <= tol);
}

// Plain loop (GCC 12 warns falsely about Eigen's AVX-512 reductions on small dynamic matrices).
double max_abs_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  double d = 0;
  for (Eigen::Index i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a.data()[i] - b.data()[i]));
  return d;
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

// ---- AtomicFile ----------------------------------------------------------------------------------

TEST_CASE("AtomicFile: commit publishes the file, parent directories are created", "[io][atomic]") {
  TempDir dir;
  const fs::path target = dir / "a/b/out.txt";
  {
    AtomicFile f(target);
    f.stream() << "hello";
    CHECK_FALSE(fs::exists(target));  // nothing visible before commit
    CHECK(fs::exists(f.temp_path()));
    CHECK(f.temp_path().parent_path() == target.parent_path());
    f.commit();
  }
  CHECK(read_bytes(target) == "hello");
  CHECK(std::distance(fs::directory_iterator(target.parent_path()), fs::directory_iterator()) == 1);
  write_text_atomic(target, "replaced");
  CHECK(read_bytes(target) == "replaced");
}

TEST_CASE("AtomicFile: an exception before commit leaves neither target nor temporary", "[io][atomic]") {
  TempDir dir;
  const fs::path target = dir / "out.txt";
  fs::path temp;
  try {
    AtomicFile f(target);
    temp = f.temp_path();
    f.stream() << "partial";
    throw std::runtime_error("writer failed half-way");
  } catch (const std::runtime_error&) {
  }
  CHECK_FALSE(temp.empty());
  CHECK_FALSE(fs::exists(temp));
  CHECK_FALSE(fs::exists(target));
  CHECK(dir.entries() == 0);

  // An existing file is left untouched by a failed rewrite.
  write_text_atomic(target, "old");
  try {
    AtomicFile f(target);
    f.stream() << "new, but never committed";
    throw std::runtime_error("fail");
  } catch (const std::runtime_error&) {
  }
  CHECK(read_bytes(target) == "old");
  CHECK(dir.entries() == 1);
}

TEST_CASE("AtomicFile: unwritable targets throw Error naming the path", "[io][atomic]") {
  TempDir dir;
  fs::create_directories(dir / "sub");
  CHECK_THAT(error_of([&] { AtomicFile f(dir / "sub"); }),
             Catch::Contains("sub") && Catch::Contains("directory"));
  write_text_atomic(dir / "file", "x");  // a file where a directory is needed
  CHECK_THAT(error_of([&] { write_text_atomic(dir / "file/inside.txt", "y"); }),
             Catch::Contains("inside.txt"));
  CHECK(dir.entries() == 2);
}

// ---- formats -------------------------------------------------------------------------------------

TEST_CASE("mesh_format: by extension, case-insensitive, anything else is an Error", "[io]") {
  CHECK(mesh_format("a/b.obj") == MeshFormat::Obj);
  CHECK(mesh_format("B.OBJ") == MeshFormat::Obj);
  CHECK(mesh_format("x.Off") == MeshFormat::Off);
  CHECK(mesh_format("x.PLY") == MeshFormat::Ply);
  CHECK(mesh_format("x.stl") == MeshFormat::Stl);
  CHECK_THAT(error_of([] { mesh_format("dir/mesh.xyz"); }),
             Catch::Contains("unsupported mesh format '.xyz'") && Catch::Contains("dir/mesh.xyz"));
  CHECK_THAT(error_of([] { mesh_format("noext"); }), Catch::Contains("unsupported mesh format ''"));
  TempDir dir;
  CHECK_THROWS_AS(write_mesh(dir / "m.xyz", octahedron()), Error);
  CHECK(dir.entries() == 0);
}

TEST_CASE("round trips: OBJ, OFF and ASCII/binary PLY are bit-exact, OBJ keeps UV and FUV", "[io]") {
  TempDir dir;
  const Mesh m = octahedron();
  SECTION("obj") {
    write_mesh(dir / "m.obj", m);
    const Mesh r = read_mesh(dir / "m.obj");
    CHECK(r.V == m.V);
    CHECK(r.F == m.F);
    CHECK(r.UV == m.UV);
    CHECK(r.FUV == m.FUV);
    CHECK(r.has_uv());
  }
  SECTION("off") {
    write_mesh(dir / "m.off", m);
    const Mesh r = read_mesh(dir / "m.off");
    CHECK(r.V == m.V);
    CHECK(r.F == m.F);
    CHECK(r.UV.size() == 0);
  }
  SECTION("ply binary and ascii") {
    write_mesh(dir / "b.ply", m);
    write_mesh(dir / "a.ply", m, {.binary = false});
    CHECK(read_bytes(dir / "b.ply").find("binary_little_endian") != std::string::npos);
    CHECK(read_bytes(dir / "a.ply").find("format ascii") != std::string::npos);
    for (const char* name : {"b.ply", "a.ply"}) {
      const Mesh r = read_mesh(dir / name);
      CHECK(r.V == m.V);
      CHECK(r.F == m.F);
    }
  }
  SECTION("stl: ascii exact, binary rounded to float32, equal positions merged") {
    write_mesh(dir / "a.stl", m, {.binary = false});
    write_mesh(dir / "b.stl", m);
    CHECK(fs::file_size(dir / "b.stl") == 84 + 50 * 8);
    const Mesh ra = read_mesh(dir / "a.stl");
    CHECK(ra.V.rows() == 6);  // 24 corners welded back into 6 vertices
    check_same_corners(m, ra, 0.0);
    const Mesh rb = read_mesh(dir / "b.stl");
    CHECK(rb.V.rows() == 6);
    Mesh mf = m;
    mf.V = m.V.cast<float>().cast<double>();
    check_same_corners(mf, rb, 0.0);
  }
  CHECK(dir.entries() >= 1);
  for (const auto& e : fs::directory_iterator(dir.path))  // no temporaries left behind
    CHECK(e.path().extension() != ".tmp");
}

TEST_CASE("OBJ reader: polygons, negative indices, v//vn, v/vt/vn, comments, CRLF", "[io][obj]") {
  TempDir dir;
  write_bytes(dir / "q.obj",
              "# a unit square as one quad, then a triangle with relative indices\r\n"
              "mtllib none.mtl\r\no square\r\n"
              "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0 1.0\r\nv +0 1 0 0.5 0.5 0.5  # with colour\r\n"
              "vt 0 0\r\nvt 1 0 0\r\nvt 1 1\r\nvt 0.25\r\n"
              "vn 0 0 1\r\ng g1\r\nusemtl m\r\ns off\r\n"
              "f 1/1/1 2/2/1 3/3/1 4/4/1\r\n"
              "f -4/-4/-1 -2/-2/-1 -1/-1/-1\r\n"
              "l 1 2\r\n");
  const Mesh m = read_mesh(dir / "q.obj");
  REQUIRE(m.V.rows() == 4);
  REQUIRE(m.F.rows() == 3);
  Eigen::MatrixXi F(3, 3), FUV(3, 3);
  F << 0, 1, 2, 0, 2, 3, 0, 2, 3;  // the quad fans from its first corner
  CHECK(m.F == F);
  CHECK(m.FUV == F);
  CHECK(m.UV.rows() == 4);
  CHECK(m.UV(3, 0) == 0.25);
  CHECK(m.UV(3, 1) == 0.0);  // a missing v defaults to 0
  CHECK(m.V(2, 2) == 0.0);

  write_bytes(dir / "n.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n");
  const Mesh n = read_mesh(dir / "n.obj");
  CHECK(n.F.rows() == 1);
  CHECK(n.FUV.size() == 0);
  CHECK_FALSE(n.has_uv());
}

TEST_CASE("OBJ reader keeps non-manifold and degenerate faces (a faithful soup)", "[io][obj]") {
  TempDir dir;
  write_bytes(dir / "nm.obj",
              "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 0\n"
              "f 1 2 3\nf 2 1 4\nf 1 2 5\nf 1 1 2\nf 1 2 3\n");
  const Mesh m = read_mesh(dir / "nm.obj");
  CHECK(m.V.rows() == 6);  // vertex 6 duplicates vertex 1 and is kept
  CHECK(m.F.rows() == 5);  // three faces on edge (1,2), a repeated index and a repeated face
}

TEST_CASE("OBJ reader: errors name file:line", "[io][obj]") {
  TempDir dir;
  const auto err = [&](const std::string& text) {
    write_bytes(dir / "e.obj", text);
    return error_of([&] { read_mesh(dir / "e.obj"); });
  };
  CHECK_THAT(err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"),
             Catch::Contains("e.obj:4:") && Catch::Contains("vertex index 4 out of range"));
  CHECK_THAT(err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 0 1 2\n"),
             Catch::Contains("e.obj:5:") && Catch::Contains("index 0"));
  CHECK_THAT(err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"),
             Catch::Contains("e.obj:4:") && Catch::Contains("relative"));
  CHECK_THAT(err("v 0 0 0\nv 1 0 zero\n"), Catch::Contains("e.obj:2:") && Catch::Contains("'zero'"));
  CHECK_THAT(err("v 0 0\n"), Catch::Contains("e.obj:1:") && Catch::Contains("3 coordinates"));
  CHECK_THAT(err("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n\nf 1/1 2/1 3\n"),
             Catch::Contains("e.obj:6:") && Catch::Contains("texture coordinates on 2 of its 3 corners"));
  CHECK_THAT(err("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1 2 3\n"),
             Catch::Contains("e.obj:6:") && Catch::Contains("line 5"));
  CHECK_THAT(err("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/2\n"),
             Catch::Contains("e.obj:5:") && Catch::Contains("texture coordinate index 2 out of range"));
  CHECK_THAT(err("v 0 0 0\nv 1 0 0\nf 1 2\n"), Catch::Contains("e.obj:3:") && Catch::Contains("at least 3"));
  CHECK_THAT(err(""), Catch::Contains("e.obj: the file is empty"));
  CHECK_THAT(err("v 0 0 0\n# no faces\n"), Catch::Contains("no faces"));
  CHECK_THAT(error_of([&] { read_mesh(dir / "missing.obj"); }),
             Catch::Contains("cannot open") && Catch::Contains("missing.obj"));
}

TEST_CASE("OFF, PLY and STL readers: variants and errors", "[io]") {
  TempDir dir;
  SECTION("OFF: header with counts, COFF colours, polygons, comments") {
    write_bytes(dir / "a.off",
                "COFF 4 1 0\n# comment\n0 0 0 255 0 0 255\n1 0 0 1 2 3 4\n1 1 0 0 0 0 0\n0 1 0 0 0 0 0\n4 0 "
                "1 2 3 9 9 9\n");
    const Mesh m = read_mesh(dir / "a.off");
    CHECK(m.V.rows() == 4);
    CHECK(m.F.rows() == 2);
    CHECK(m.F(1, 2) == 3);
    write_bytes(dir / "t.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n");
    CHECK_THAT(error_of([&] { read_mesh(dir / "t.off"); }),
               Catch::Contains("t.off:5:") && Catch::Contains("announces 4 vertices, the file holds 3"));
    write_bytes(dir / "r.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1 3\n");
    CHECK_THAT(error_of([&] { read_mesh(dir / "r.off"); }),
               Catch::Contains("r.off:6:") && Catch::Contains("out of range"));
  }
  SECTION("PLY: big-endian binary with float/uchar and extra properties and elements") {
    std::string s =
        "ply\nformat binary_big_endian 1.0\ncomment x\nelement vertex 3\nproperty float x\n"
        "property uchar flag\nproperty float y\nproperty float z\nproperty list uchar float extra\n"
        "element face 1\nproperty uchar flags\nproperty list uchar uint vertex_indices\n"
        "element edge 1\nproperty int a\nproperty int b\nend_header\n";
    auto be32 = [&](std::uint32_t v) {
      for (int k = 3; k >= 0; --k) s += char(v >> (8 * k) & 0xff);
    };
    auto bef = [&](float f) { be32(std::bit_cast<std::uint32_t>(f)); };
    for (int i = 0; i < 3; ++i) {
      bef(0.5f * i);
      s += char(7);
      bef(1.0f + i);
      bef(-2.0f);
      s += char(1);
      bef(9.0f);
    }
    s += char(0);
    s += char(3);
    be32(2), be32(0), be32(1);
    be32(0), be32(1);
    write_bytes(dir / "be.ply", s);
    const Mesh m = read_mesh(dir / "be.ply");
    REQUIRE(m.V.rows() == 3);
    CHECK(m.V(2, 0) == 1.0);
    CHECK(m.V(1, 1) == 2.0);
    CHECK(m.V(0, 2) == -2.0);
    CHECK(m.F.rows() == 1);
    CHECK(m.F(0, 0) == 2);
    write_bytes(dir / "cut.ply", s.substr(0, s.size() - 20));
    CHECK_THAT(error_of([&] { read_mesh(dir / "cut.ply"); }),
               Catch::Contains("cut.ply") && Catch::Contains("truncated"));
  }
  SECTION("PLY: ASCII truncated and out-of-range index name the line") {
    write_bytes(dir / "a.ply",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                "property double z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
                "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    CHECK_THAT(error_of([&] { read_mesh(dir / "a.ply"); }), Catch::Contains("unexpected end of file"));
    write_bytes(dir / "b.ply",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
    CHECK_THAT(error_of([&] { read_mesh(dir / "b.ply"); }),
               Catch::Contains("b.ply:13:") && Catch::Contains("out of range"));
  }
  SECTION("STL: binary truncated, ASCII truncated, degenerate triangles kept") {
    write_mesh(dir / "m.stl", octahedron());
    const std::string b = read_bytes(dir / "m.stl");
    write_bytes(dir / "cut.stl", b.substr(0, b.size() - 7));
    CHECK_THAT(error_of([&] { read_mesh(dir / "cut.stl"); }),
               Catch::Contains("truncated binary STL") && Catch::Contains("announces 8 triangles"));
    write_mesh(dir / "a.stl", octahedron(), {.binary = false});
    const std::string a = read_bytes(dir / "a.stl");
    write_bytes(dir / "acut.stl", a.substr(0, a.size() / 2));
    CHECK_THAT(error_of([&] { read_mesh(dir / "acut.stl"); }), Catch::Contains("acut.stl:"));
    write_bytes(dir / "d.stl",
                "solid d\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 0\n"
                "endloop\nendfacet\nendsolid d\n");
    const Mesh d = read_mesh(dir / "d.stl");
    CHECK(d.V.rows() == 2);
    CHECK(d.F.rows() == 1);
    CHECK(d.F(0, 0) == d.F(0, 2));  // kept, for validation to report
  }
}

TEST_CASE("write_mesh rejects malformed meshes and leaves no file", "[io]") {
  TempDir dir;
  Mesh m = octahedron();
  m.F(3, 1) = 6;
  CHECK_THAT(error_of([&] { write_mesh(dir / "bad.obj", m); }),
             Catch::Contains("bad.obj") && Catch::Contains("face 3 references vertex 6"));
  m = octahedron();
  m.FUV.conservativeResize(7, 3);
  CHECK_THAT(error_of([&] { write_mesh(dir / "bad.obj", m); }), Catch::Contains("FUV"));
  CHECK_THROWS_AS(write_mesh(dir / "empty.ply", Mesh{}), Error);
  CHECK(dir.entries() == 0);
}

// ---- OpenMesh as an independent reader and writer ------------------------------------------------

TEST_CASE("OpenMesh reads what we write, and we read what OpenMesh writes", "[io][openmesh]") {
  using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<>;
  TempDir dir;
  const Mesh m = octahedron();
  for (const char* name : {"m.obj", "m.off", "m.ply", "m.stl"}) {
    INFO(name);
    write_mesh(dir / name, m);
    PolyMesh om;
    OpenMesh::IO::Options opt;
    REQUIRE(OpenMesh::IO::read_mesh(om, (dir / name).string(), opt));
    CHECK(om.n_vertices() == 6);
    CHECK(om.n_faces() == 8);
    for (const auto fh : om.faces()) {  // OpenMesh keeps our face order; corners may be rotated
      const Eigen::Index f = fh.idx();
      for (const auto vh : om.fv_ccw_range(fh)) {
        const auto p = om.point(vh);
        bool found = false;
        for (int k = 0; k < 3; ++k)
          found |= (Eigen::Vector3d(p[0], p[1], p[2]) - m.V.row(m.F(f, k)).transpose()).norm() < 1e-6;
        CHECK(found);
      }
    }
  }
  // OpenMesh writes float PLY (binary) and OFF; our readers get the same float positions.
  PolyMesh om;
  std::vector<PolyMesh::VertexHandle> vh;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    vh.push_back(om.add_vertex(PolyMesh::Point(m.V(i, 0), m.V(i, 1), m.V(i, 2))));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) om.add_face(vh[m.F(f, 0)], vh[m.F(f, 1)], vh[m.F(f, 2)]);
  OpenMesh::IO::Options bin(OpenMesh::IO::Options::Binary);
  REQUIRE(OpenMesh::IO::write_mesh(om, (dir / "om.ply").string(), bin));
  REQUIRE(OpenMesh::IO::write_mesh(om, (dir / "om.off").string()));
  Mesh mf = m;
  mf.V = m.V.cast<float>().cast<double>();
  const Mesh rp = read_mesh(dir / "om.ply");
  CHECK(rp.V == mf.V);
  CHECK(rp.F == m.F);
  const Mesh ro = read_mesh(dir / "om.off");
  CHECK(ro.F == m.F);
  CHECK(max_abs_diff(ro.V, mf.V) < 1e-5);  // OpenMesh prints OFF with 6 significant digits
}

TEST_CASE("every truncation of every format reads or throws Error, never anything else", "[io][robust]") {
  TempDir dir;
  const Mesh m = octahedron();
  for (const auto& [name, binary] : {std::pair<const char*, bool>{"m.obj", false},
                                     {"m.off", false},
                                     {"m.ply", true},
                                     {"a.ply", false},
                                     {"m.stl", true},
                                     {"a.stl", false}}) {
    INFO(name);
    write_mesh(dir / name, m, {.binary = binary});
    const std::string full = read_bytes(dir / name);
    int errors = 0;
    for (std::size_t len = 0; len < full.size(); ++len) {
      // A new name each time: rewriting one file makes ext4 flush it on close (slow on a busy disk).
      const fs::path cut = dir / ("cut" + std::to_string(len) + fs::path(name).extension().string());
      write_bytes(cut, full.substr(0, len));
      try {
        const Mesh r = read_mesh(cut);
        CHECK(r.F.rows() <= m.F.rows());  // a prefix that parses holds a prefix of the faces
      } catch (const Error&) {
        ++errors;
      } catch (const std::exception& e) {
        FAIL("length " << len << ": unexpected exception " << e.what());
      }
      fs::remove(cut);
    }
    CHECK(errors > 0);
  }
}

TEST_CASE("a corrupt header announcing 2^31 elements is a truncation error, not bad_alloc", "[io][robust]") {
  TempDir dir;
  write_bytes(dir / "big.off", "OFF\n2000000000 2000000000 0\n0 0 0\n");
  CHECK_THAT(error_of([&] { read_mesh(dir / "big.off"); }), Catch::Contains("unexpected end of file"));
  write_bytes(dir / "big.ply",
              "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty float x\n"
              "property float y\nproperty float z\nelement face 2000000000\n"
              "property list uchar int vertex_indices\nend_header\n0123456789");
  CHECK_THAT(error_of([&] { read_mesh(dir / "big.ply"); }), Catch::Contains("truncated"));
}

TEST_CASE("openmesh_interop: to_openmesh and back keeps positions, faces (up to rotation) and UVs",
          "[io][openmesh]") {
  const Mesh m = octahedron();
  const OpenMeshTriMesh om = to_openmesh(m);
  CHECK(om.n_vertices() == 6);
  CHECK(om.n_faces() == 8);
  CHECK(om.n_edges() == 12);
  for (const auto vh : om.vertices()) CHECK_FALSE(om.is_boundary(vh));
  const Mesh r = from_openmesh(om);
  CHECK(r.V == m.V);  // doubles kept exactly (OpenMeshTraits points are Vec3d)
  REQUIRE(r.F.rows() == 8);
  for (Eigen::Index f = 0; f < 8; ++f) {
    int shift = 0;  // the rotation of face f's corners
    while (shift < 3 && r.F(f, 0) != m.F(f, shift)) ++shift;
    REQUIRE(shift < 3);
    for (int c = 0; c < 3; ++c) {
      CHECK(r.F(f, c) == m.F(f, (c + shift) % 3));
      CHECK(r.UV.row(r.FUV(f, c)) == m.UV.row(m.FUV(f, (c + shift) % 3)));
    }
  }
  CHECK(r.UV.rows() == 8);  // the octahedron's 8 distinct UVs

  Mesh nm = m;  // a third face on edge (0, 2): OpenMesh refuses it, the error names it
  nm.F.conservativeResize(9, 3);
  nm.F.row(8) << 0, 2, 5;
  nm.FUV.resize(0, 3);
  CHECK_THAT(error_of([&] { to_openmesh(nm); }), Catch::Contains("cannot add face 8 (0, 2, 5)"));
}

}  // namespace test_io
