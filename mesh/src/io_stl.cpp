// STL (stereolithography) reader and writer (see io.hpp for the contract).
//
// Hand-written rather than OpenMesh::IO: OpenMesh's STL reader silently drops degenerate triangles
// (validation must count them), accepts a truncated binary file, and its writer rounds ASCII output
// to 10 significant digits. An STL file stores each triangle with its own three corners; this reader
// merges corners whose positions are exactly equal (==, so 0.0 and -0.0 merge and NaN never does)
// into one vertex, numbered in order of first appearance, and keeps every triangle.
// Binary vs ASCII: a binary file is exactly 84 + 50·n bytes (n = the count at byte 80); anything
// else that starts with "solid" is ASCII; anything else is a binary file of the wrong size.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include "io_detail.hpp"
#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/mesh/io.hpp"

namespace spinmotor {
namespace fs = std::filesystem;
using namespace io_detail;

namespace {

// Vertex welding by exact position.
class Welder {
 public:
  explicit Welder(Soup& s) : s_(s) {}
  int add(double x, double y, double z) {
    const std::array<double, 3> key{x + 0.0, y + 0.0, z + 0.0};  // + 0.0 turns -0.0 into 0.0
    const bool finite = std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
    if (finite) {
      const auto it = map_.find(key);
      if (it != map_.end()) return it->second;
    }
    const int id = static_cast<int>(s_.V.size() / 3);
    s_.V.insert(s_.V.end(), {x, y, z});
    if (finite) map_.emplace(key, id);
    return id;
  }

 private:
  struct Hash {
    std::size_t operator()(const std::array<double, 3>& a) const {
      std::size_t h = 0;
      for (double d : a) h = h * 1000003u ^ std::hash<std::uint64_t>{}(std::bit_cast<std::uint64_t>(d));
      return h;
    }
  };
  Soup& s_;
  std::unordered_map<std::array<double, 3>, int, Hash> map_;
};

std::uint32_t load_u32_le(const char* p) {
  unsigned char b[4];
  std::memcpy(b, p, 4);
  return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 |
         std::uint32_t(b[3]) << 24;
}

float load_f32_le(const char* p) { return std::bit_cast<float>(load_u32_le(p)); }

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(x) == std::tolower(y);
         });
}

bool starts_with_solid(const std::string& bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
  return bytes.size() - i >= 5 && iequals(std::string_view(bytes).substr(i, 5), "solid");
}

Mesh read_stl_binary(const fs::path& path, const std::string& bytes) {
  if (bytes.size() < 84)
    fail(path, 0,
         "truncated binary STL: " + std::to_string(bytes.size()) + " bytes, shorter than the 84-byte header");
  const std::uint64_t n = load_u32_le(bytes.data() + 80);
  const std::uint64_t expected = 84 + 50 * n;
  if (bytes.size() < expected)
    fail(path, 0,
         "truncated binary STL: the header announces " + std::to_string(n) + " triangles (" +
             std::to_string(expected) + " bytes), the file has " + std::to_string(bytes.size()) + " bytes (" +
             std::to_string((bytes.size() - 84) / 50) + " complete triangles)");
  if (n == 0) fail(path, 0, "no faces (the binary STL header announces 0 triangles)");
  Soup s;
  s.F.reserve(3 * n);
  Welder weld(s);
  for (std::uint64_t t = 0; t < n; ++t) {
    const char* p = bytes.data() + 84 + 50 * t + 12;  // skip the stored normal
    for (int c = 0; c < 3; ++c, p += 12)
      s.F.push_back(weld.add(load_f32_le(p), load_f32_le(p + 4), load_f32_le(p + 8)));
  }
  return s.to_mesh();
}

Mesh read_stl_ascii(const fs::path& path, const std::string& bytes) {
  Soup s;
  Welder weld(s);
  LineReader lines(bytes);
  std::string_view line;
  std::vector<std::string_view> tok;
  enum class State { Outside, Solid, Facet, Loop, LoopDone } st = State::Outside;
  int corners = 0;
  int tri[3] = {0, 0, 0};
  bool any_solid = false;
  while (lines.next(line)) {
    split_tokens(line, tok, false);
    if (tok.empty()) continue;
    const std::size_t ln = lines.line_number();
    const std::string_view kw = tok[0];
    auto expect = [&](State want, const char* what) {
      if (st != want) fail(path, ln, "unexpected '" + std::string(kw) + "' (expected " + what + ")");
    };
    if (iequals(kw, "solid")) {
      expect(State::Outside, "'facet' or 'endsolid'");
      st = State::Solid;
      any_solid = true;
    } else if (iequals(kw, "endsolid")) {
      expect(State::Solid, "'facet' or 'endsolid'");
      st = State::Outside;
    } else if (iequals(kw, "facet")) {
      expect(State::Solid, "'facet' or 'endsolid'");
      st = State::Facet;
    } else if (iequals(kw, "outer")) {
      expect(State::Facet, "'outer loop'");
      st = State::Loop;
      corners = 0;
    } else if (iequals(kw, "vertex")) {
      expect(State::Loop, "'vertex' inside 'outer loop'");
      if (corners == 3) fail(path, ln, "a facet has more than 3 vertices (STL holds triangles only)");
      if (tok.size() < 4) fail(path, ln, "vertex needs 3 coordinates, got " + std::to_string(tok.size() - 1));
      double x[3];
      for (int k = 0; k < 3; ++k)
        if (!parse_double(tok[k + 1], x[k]))
          fail(path, ln, "cannot parse '" + std::string(tok[k + 1]) + "' as a number");
      tri[corners++] = weld.add(x[0], x[1], x[2]);
    } else if (iequals(kw, "endloop")) {
      expect(State::Loop, "'endloop' after 3 vertices");
      if (corners != 3) fail(path, ln, "a facet has " + std::to_string(corners) + " vertices (3 needed)");
      s.F.insert(s.F.end(), tri, tri + 3);
      st = State::LoopDone;
    } else if (iequals(kw, "endfacet")) {
      expect(State::LoopDone, "'endloop' before 'endfacet'");
      st = State::Solid;
    } else {
      fail(path, ln, "unknown ASCII STL keyword '" + std::string(kw) + "'");
    }
  }
  if (!any_solid) fail(path, 0, "not an STL file");
  if (st != State::Outside)
    fail(path, lines.line_number(),
         "unexpected end of file (truncated?): no 'endsolid' after the last facet");
  if (s.F.empty()) fail(path, 0, "no faces (the file holds no facet)");
  return s.to_mesh();
}

}  // namespace

Mesh read_stl(const fs::path& path) {
  const std::string bytes = read_file_bytes(path);
  if (bytes.empty()) fail(path, 0, "the file is empty");
  if (bytes.size() >= 84 && bytes.size() == 84 + 50 * std::uint64_t(load_u32_le(bytes.data() + 80)))
    return read_stl_binary(path, bytes);
  if (starts_with_solid(bytes)) return read_stl_ascii(path, bytes);
  return read_stl_binary(path, bytes);
}

void write_stl(const fs::path& path, const Mesh& mesh, bool binary) {
  check_writable(path, mesh);
  auto normal = [&](Eigen::Index f) -> Eigen::Vector3d {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                          c = mesh.V.row(mesh.F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    return len > 0 && std::isfinite(len) ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
  };
  std::string out;
  if (binary) {
    if (mesh.F.rows() > 0xffffffffLL)
      throw Error("cannot write '" + path.string() + "': too many faces for STL");
    out.reserve(84 + 50 * static_cast<std::size_t>(mesh.F.rows()));
    std::string header = "binary STL written by spinmotor";  // must not start with "solid"
    header.resize(80, ' ');
    out += header;
    auto put_u32 = [&](std::uint32_t v) {
      const char b[4] = {char(v & 0xff), char(v >> 8 & 0xff), char(v >> 16 & 0xff), char(v >> 24 & 0xff)};
      out.append(b, 4);
    };
    auto put_f32 = [&](double x) { put_u32(std::bit_cast<std::uint32_t>(static_cast<float>(x))); };
    put_u32(static_cast<std::uint32_t>(mesh.F.rows()));
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      const Eigen::Vector3d n = normal(f);
      for (int k = 0; k < 3; ++k) put_f32(n[k]);
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) put_f32(mesh.V(mesh.F(f, c), k));
      out.append(2, '\0');  // attribute byte count
    }
  } else {
    out.reserve(static_cast<std::size_t>(mesh.F.rows() * 250 + 64));
    out += "solid spinmotor\n";
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      const Eigen::Vector3d n = normal(f);
      out += "facet normal";
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        append_double(out, n[k]);
      }
      out += "\n  outer loop\n";
      for (int c = 0; c < 3; ++c) {
        out += "    vertex";
        for (int k = 0; k < 3; ++k) {
          out += ' ';
          append_double(out, mesh.V(mesh.F(f, c), k));
        }
        out += '\n';
      }
      out += "  endloop\nendfacet\n";
    }
    out += "endsolid spinmotor\n";
  }
  write_text_atomic(path, out);
}

}  // namespace spinmotor
