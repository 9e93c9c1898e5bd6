// Wavefront OBJ reader and writer (see io.hpp for the contract).
//
// Hand-written rather than OpenMesh::IO: OpenMesh's reader builds a halfedge mesh, so it drops or
// splits faces that would make an edge non-manifold (validation must see them), it re-indexes `vt`
// per halfedge (a round trip must keep the file's vt list and each corner's vt index), and it
// reports no line numbers.
#include <string>
#include <vector>

#include "io_detail.hpp"
#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/mesh/io.hpp"

namespace spinmotor {
namespace fs = std::filesystem;
using namespace io_detail;

namespace {

struct Corner {
  int v;
  int vt;  // -1 when the corner has none
};

// Resolves an OBJ index token (1-based, or negative = relative to the `count` elements so far).
// Positive indices are range-checked at the end of the file (a face may precede its vertices).
int resolve_index(const fs::path& path, std::size_t line, std::string_view tok, long long count,
                  const char* what) {
  long long i = 0;
  if (!parse_long(tok, i))
    fail(path, line, "cannot parse '" + std::string(tok) + "' as a " + what + " index");
  if (i == 0) fail(path, line, std::string(what) + " index 0 (OBJ indices start at 1)");
  if (i < 0) {
    const long long r = count + i;
    if (r < 0)
      fail(path, line,
           "relative " + std::string(what) + " index " + std::to_string(i) + " points before the first " +
               what + " (only " + std::to_string(count) + " so far)");
    return static_cast<int>(r);
  }
  if (i > 2147483647LL) fail(path, line, std::string(what) + " index " + std::string(tok) + " is too large");
  return static_cast<int>(i - 1);
}

}  // namespace

Mesh read_obj(const fs::path& path) {
  const std::string bytes = read_file_bytes(path);
  if (bytes.empty()) fail(path, 0, "the file is empty");
  Soup s;
  s.V.reserve(bytes.size() / 16);
  s.F.reserve(bytes.size() / 8);
  std::vector<std::size_t> tri_line;  // line of each triangle, for the final range check
  std::vector<std::string_view> tok;
  std::vector<Corner> corners;
  int file_uv = -1;  // -1 no face seen yet, 0 faces without vt, 1 faces with vt
  std::size_t file_uv_line = 0;

  LineReader lines(bytes);
  std::string_view line;
  while (lines.next(line)) {
    split_tokens(line, tok, true);
    if (tok.empty()) continue;
    const std::size_t ln = lines.line_number();
    const std::string_view kw = tok[0];
    if (kw == "v") {
      if (tok.size() < 4) fail(path, ln, "vertex needs 3 coordinates, got " + std::to_string(tok.size() - 1));
      for (int k = 1; k <= 3; ++k) {
        double x = 0;
        if (!parse_double(tok[k], x))
          fail(path, ln, "cannot parse '" + std::string(tok[k]) + "' as a number");
        s.V.push_back(x);
      }
    } else if (kw == "vt") {
      if (tok.size() < 2) fail(path, ln, "texture coordinate needs at least 1 value, got 0");
      double uv[2] = {0, 0};
      for (std::size_t k = 1; k <= 2 && k < tok.size(); ++k)
        if (!parse_double(tok[k], uv[k - 1]))
          fail(path, ln, "cannot parse '" + std::string(tok[k]) + "' as a number");
      s.UV.push_back(uv[0]);
      s.UV.push_back(uv[1]);
    } else if (kw == "f") {
      if (tok.size() < 4)
        fail(path, ln, "face needs at least 3 vertices, got " + std::to_string(tok.size() - 1));
      const long long nv = static_cast<long long>(s.V.size() / 3),
                      nt = static_cast<long long>(s.UV.size() / 2);
      corners.clear();
      int with_vt = 0;
      for (std::size_t k = 1; k < tok.size(); ++k) {
        const std::string_view c = tok[k];
        const std::size_t s1 = c.find('/');
        Corner cr{resolve_index(path, ln, c.substr(0, s1), nv, "vertex"), -1};
        if (s1 != std::string_view::npos) {
          const std::size_t s2 = c.find('/', s1 + 1);
          const std::string_view t =
              c.substr(s1 + 1, s2 == std::string_view::npos ? std::string_view::npos : s2 - s1 - 1);
          if (!t.empty()) cr.vt = resolve_index(path, ln, t, nt, "texture coordinate");
        }
        with_vt += cr.vt >= 0;
        corners.push_back(cr);
      }
      if (with_vt != 0 && with_vt != static_cast<int>(corners.size()))
        fail(path, ln,
             "face has texture coordinates on " + std::to_string(with_vt) + " of its " +
                 std::to_string(corners.size()) + " corners (all or none)");
      const int has_vt = with_vt > 0;
      if (file_uv < 0) {
        file_uv = has_vt;
        file_uv_line = ln;
      } else if (file_uv != has_vt) {
        fail(path, ln,
             std::string("face ") + (has_vt ? "has" : "has no") +
                 " texture coordinates but the face on line " + std::to_string(file_uv_line) +
                 (has_vt ? " has none" : " has them") +
                 " (texture coordinates must be on every face or none)");
      }
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {  // fan (c0, ck, ck+1)
        for (const Corner* c : {&corners[0], &corners[k], &corners[k + 1]}) {
          s.F.push_back(c->v);
          if (has_vt) s.FUV.push_back(c->vt);
        }
        tri_line.push_back(ln);
      }
    }
    // Everything else (vn, vp, o, g, s, usemtl, mtllib, l, p, ...) carries nothing a Mesh holds.
  }

  if (s.F.empty())
    fail(path, 0,
         "no faces (the file has " + std::to_string(s.V.size() / 3) + " vertices and no 'f' statement)");
  const std::size_t nv = s.V.size() / 3, nt = s.UV.size() / 2;
  for (std::size_t i = 0; i < s.F.size(); ++i) {
    if (static_cast<std::size_t>(s.F[i]) >= nv)
      fail(path, tri_line[i / 3],
           "vertex index " + std::to_string(s.F[i] + 1) + " out of range (the file has " +
               std::to_string(nv) + " vertices)");
    if (!s.FUV.empty() && static_cast<std::size_t>(s.FUV[i]) >= nt)
      fail(path, tri_line[i / 3],
           "texture coordinate index " + std::to_string(s.FUV[i] + 1) + " out of range (the file has " +
               std::to_string(nt) + " texture coordinates)");
  }
  return s.to_mesh();
}

void write_obj(const fs::path& path, const Mesh& mesh,
               const std::vector<std::pair<std::string, Eigen::Index>>& objects) {
  check_writable(path, mesh);
  for (size_t k = 0; k < objects.size(); ++k)
    if (objects[k].second < 0 || objects[k].second >= mesh.F.rows() ||
        (k > 0 && objects[k].second <= objects[k - 1].second) ||
        objects[k].first.find_first_of("\n\r") != std::string::npos)
      throw Error(path.string() + ": object " + std::to_string(k) + " ('" + objects[k].first +
                  "') has a first face out of order or a line break in its name");
  size_t next = 0;
  const bool uv = mesh.FUV.rows() > 0;
  std::string out;
  out.reserve(static_cast<std::size_t>(mesh.V.rows() * 60 + mesh.UV.rows() * 40 + mesh.F.rows() * 40 + 100));
  out += "# spinmotor: " + std::to_string(mesh.V.rows()) + " vertices, " + std::to_string(mesh.F.rows()) +
         " triangles\n";
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    out += "v";
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_double(out, mesh.V(i, k));
    }
    out += '\n';
  }
  for (Eigen::Index i = 0; i < mesh.UV.rows(); ++i) {
    out += "vt ";
    append_double(out, mesh.UV(i, 0));
    out += ' ';
    append_double(out, mesh.UV(i, 1));
    out += '\n';
  }
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    if (next < objects.size() && objects[next].second == f) out += "o " + objects[next++].first + '\n';
    out += 'f';
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      append_int(out, mesh.F(f, c) + 1LL);
      if (uv) {
        out += '/';
        append_int(out, mesh.FUV(f, c) + 1LL);
      }
    }
    out += '\n';
  }
  write_text_atomic(path, out);
}

}  // namespace spinmotor
