// Object File Format (OFF) reader and writer (see io.hpp for the contract).
//
// Hand-written for the same reasons as the OBJ reader (OpenMesh's reader cannot hold non-manifold
// faces and gives no line numbers). The reader expects one element per line, as every OFF writer
// emits: the header keyword, then "nv nf ne", then nv vertex lines whose first three numbers are
// x y z (colours, normals or texture values after them are skipped), then nf face lines
// "k i1 ... ik [colour]". '#' starts a comment. Binary OFF is not supported.
#include <algorithm>
#include <string>
#include <vector>

#include "io_detail.hpp"
#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/mesh/io.hpp"

namespace spinmotor {
namespace fs = std::filesystem;
using namespace io_detail;

namespace {

long long parse_count(const fs::path& path, std::size_t ln, std::string_view t, const char* what) {
  long long v = 0;
  if (!parse_long(t, v) || v < 0 || v > 2147483647LL)
    fail(path, ln, "cannot parse '" + std::string(t) + "' as the number of " + what);
  return v;
}

}  // namespace

Mesh read_off(const fs::path& path) {
  const std::string bytes = read_file_bytes(path);
  if (bytes.empty()) fail(path, 0, "the file is empty");
  LineReader lines(bytes);
  std::string_view line;
  std::vector<std::string_view> tok;
  auto next_tokens = [&]() -> bool {  // next non-blank, non-comment line
    while (lines.next(line)) {
      split_tokens(line, tok, true);
      if (!tok.empty()) return true;
    }
    return false;
  };

  // Header: [ST][C][N]OFF, optionally followed by the counts on the same line.
  if (!next_tokens()) fail(path, 0, "no OFF header (the file holds only blanks or comments)");
  const std::string_view kw = tok[0];
  if (kw.size() < 3 || kw.substr(kw.size() - 3) != "OFF")
    fail(path, lines.line_number(), "expected the OFF header keyword, got '" + std::string(kw) + "'");
  const std::string_view prefix = kw.substr(0, kw.size() - 3);
  if (prefix.find('4') != std::string_view::npos || prefix.find('n') != std::string_view::npos)
    fail(path, lines.line_number(), "'" + std::string(kw) + "' (4D / n-dimensional OFF) is not supported");
  std::size_t first = 1;
  if (tok.size() > 1 && tok[1] == "BINARY") fail(path, lines.line_number(), "binary OFF is not supported");
  if (tok.size() == 1) {
    if (!next_tokens())
      fail(path, lines.line_number(), "unexpected end of file: expected the counts 'nv nf ne'");
    first = 0;
  }
  if (tok.size() < first + 2) fail(path, lines.line_number(), "expected the counts 'nv nf ne'");
  const long long nv = parse_count(path, lines.line_number(), tok[first], "vertices");
  const long long nf = parse_count(path, lines.line_number(), tok[first + 1], "faces");

  Soup s;
  // Every element takes at least one byte: never trust a (corrupt) header beyond the file size.
  s.V.reserve(3 * std::min<std::size_t>(static_cast<std::size_t>(nv), bytes.size()));
  s.F.reserve(3 * std::min<std::size_t>(static_cast<std::size_t>(nf), bytes.size()));
  for (long long i = 0; i < nv; ++i) {
    if (!next_tokens())
      fail(path, lines.line_number(),
           "unexpected end of file: the header announces " + std::to_string(nv) +
               " vertices, the file holds " + std::to_string(i));
    if (tok.size() < 3)
      fail(path, lines.line_number(),
           "vertex " + std::to_string(i) + " needs 3 coordinates, got " + std::to_string(tok.size()));
    for (int k = 0; k < 3; ++k) {
      double x = 0;
      if (!parse_double(tok[k], x))
        fail(path, lines.line_number(), "cannot parse '" + std::string(tok[k]) + "' as a number");
      s.V.push_back(x);
    }
  }
  std::vector<int> poly;
  for (long long f = 0; f < nf; ++f) {
    if (!next_tokens())
      fail(path, lines.line_number(),
           "unexpected end of file: the header announces " + std::to_string(nf) + " faces, the file holds " +
               std::to_string(f));
    const std::size_t ln = lines.line_number();
    long long k = 0;
    if (!parse_long(tok[0], k)) fail(path, ln, "cannot parse '" + std::string(tok[0]) + "' as a face size");
    if (k < 3)
      fail(path, ln,
           "face " + std::to_string(f) + " has " + std::to_string(k) + " vertices (at least 3 needed)");
    if (k > static_cast<long long>(tok.size()) - 1)  // not k + 1 > size: k may be LLONG_MAX
      fail(path, ln,
           "face " + std::to_string(f) + " announces " + std::to_string(k) + " vertices, the line holds " +
               std::to_string(tok.size() - 1));
    poly.clear();
    for (long long c = 1; c <= k; ++c) {
      long long i = 0;
      if (!parse_long(tok[c], i))
        fail(path, ln, "cannot parse '" + std::string(tok[c]) + "' as a vertex index");
      if (i < 0 || i >= nv)
        fail(path, ln,
             "vertex index " + std::to_string(i) + " out of range (the file has " + std::to_string(nv) +
                 " vertices, indices start at 0)");
      poly.push_back(static_cast<int>(i));
    }
    for (std::size_t c = 1; c + 1 < poly.size(); ++c) {  // fan (c0, ck, ck+1)
      s.F.push_back(poly[0]);
      s.F.push_back(poly[c]);
      s.F.push_back(poly[c + 1]);
    }
  }
  if (s.F.empty()) fail(path, 0, "no faces (the header announces 0 faces)");
  return s.to_mesh();
}

void write_off(const fs::path& path, const Mesh& mesh) {
  check_writable(path, mesh);
  std::string out;
  out.reserve(static_cast<std::size_t>(mesh.V.rows() * 60 + mesh.F.rows() * 30 + 64));
  out += "OFF\n";
  append_int(out, mesh.V.rows());
  out += ' ';
  append_int(out, mesh.F.rows());
  out += " 0\n";
  append_vertex_face_lines(out, mesh.V, mesh.F);
  write_text_atomic(path, out);
}

}  // namespace spinmotor
