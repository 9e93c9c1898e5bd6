// Stanford PLY reader and writer (see io.hpp for the contract).
//
// Hand-written rather than OpenMesh::IO: OpenMesh 9 reads and writes PLY positions as float32 even
// when the file or the mesh holds doubles, and accepts a truncated ASCII PLY without an error.
// This reader parses the header into elements and properties, reads `vertex` x, y, z of any scalar
// type as double and `face` vertex_indices (or vertex_index) lists of any integer type, and skips
// every other property and element (lists included). ASCII elements are read one per line.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io_detail.hpp"
#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/mesh/io.hpp"

namespace spinmotor {
namespace fs = std::filesystem;
using namespace io_detail;

namespace {

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parse_type(std::string_view s, Type& t) {
  if (s == "char" || s == "int8")
    t = Type::Int8;
  else if (s == "uchar" || s == "uint8")
    t = Type::UInt8;
  else if (s == "short" || s == "int16")
    t = Type::Int16;
  else if (s == "ushort" || s == "uint16")
    t = Type::UInt16;
  else if (s == "int" || s == "int32")
    t = Type::Int32;
  else if (s == "uint" || s == "uint32")
    t = Type::UInt32;
  else if (s == "float" || s == "float32")
    t = Type::Float32;
  else if (s == "double" || s == "float64")
    t = Type::Float64;
  else
    return false;
  return true;
}

std::size_t type_size(Type t) {
  switch (t) {
    case Type::Int8:
    case Type::UInt8:
      return 1;
    case Type::Int16:
    case Type::UInt16:
      return 2;
    case Type::Int32:
    case Type::UInt32:
    case Type::Float32:
      return 4;
    case Type::Float64:
      return 8;
  }
  return 0;
}

bool is_integer(Type t) { return t != Type::Float32 && t != Type::Float64; }

struct Property {
  std::string name;
  Type type = Type::Float32;
  bool list = false;
  Type count_type = Type::UInt8;
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> props;
};

enum class Format { Ascii, BinaryLE, BinaryBE };

// Reads one binary scalar as double (every PLY integer type is exact in a double).
template <typename T>
T load(const char* p, bool swap) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if (swap) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    std::memcpy(&v, b, sizeof(T));
  }
  return v;
}

double load_scalar(Type t, const char* p, bool swap) {
  switch (t) {
    case Type::Int8:
      return load<std::int8_t>(p, swap);
    case Type::UInt8:
      return load<std::uint8_t>(p, swap);
    case Type::Int16:
      return load<std::int16_t>(p, swap);
    case Type::UInt16:
      return load<std::uint16_t>(p, swap);
    case Type::Int32:
      return load<std::int32_t>(p, swap);
    case Type::UInt32:
      return load<std::uint32_t>(p, swap);
    case Type::Float32:
      return load<float>(p, swap);
    case Type::Float64:
      return load<double>(p, swap);
  }
  return 0;
}

// What the reader extracts from the two elements it knows.
struct Roles {
  int x = -1, y = -1, z = -1;  // property indices in `vertex`
  int indices = -1;            // property index in `face`
};

// The header: the body's format and its elements in file order.
struct PlyHeader {
  Format format = Format::Ascii;
  std::vector<Element> elements;
};

// The two elements the reader keeps (pointers into PlyHeader::elements) and their properties of interest.
struct PlyLayout {
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  Roles roles;
};

// Parses one 'property' line (tokens `tok`, line `ln`) into a Property. Throws on a malformed line.
Property parse_property(const fs::path& path, std::size_t ln, const std::vector<std::string_view>& tok) {
  Property p;
  if (tok.size() == 5 && tok[1] == "list") {
    p.list = true;
    if (!parse_type(tok[2], p.count_type) || !is_integer(p.count_type))
      fail(path, ln, "bad list count type '" + std::string(tok[2]) + "'");
    if (!parse_type(tok[3], p.type)) fail(path, ln, "unknown property type '" + std::string(tok[3]) + "'");
    p.name = tok[4];
  } else if (tok.size() == 3) {
    if (!parse_type(tok[1], p.type)) fail(path, ln, "unknown property type '" + std::string(tok[1]) + "'");
    p.name = tok[2];
  } else {
    fail(path, ln, "expected 'property <type> <name>' or 'property list <type> <type> <name>'");
  }
  return p;
}

// Reads the header from the first line through 'end_header', leaving `lines` at the body's first
// line. Returns the format and the elements; throws on a missing 'ply' line, an unknown keyword, a
// malformed line, a header without 'end_header' or without 'format'.
PlyHeader read_header(const fs::path& path, LineReader& lines) {
  std::string_view line;
  std::vector<std::string_view> tok;
  if (!lines.next(line) || (split_tokens(line, tok, false), tok.size() != 1 || tok[0] != "ply"))
    fail(path, 1, "not a PLY file (the first line must be 'ply')");
  PlyHeader h;
  bool have_format = false, have_end = false;
  while (lines.next(line)) {
    const std::size_t ln = lines.line_number();
    split_tokens(line, tok, false);
    if (tok.empty()) continue;
    const std::string_view kw = tok[0];
    if (kw == "end_header") {
      have_end = true;
      break;
    } else if (kw == "comment" || kw == "obj_info") {
      continue;
    } else if (kw == "format") {
      if (tok.size() < 2) fail(path, ln, "incomplete 'format' line");
      if (tok[1] == "ascii")
        h.format = Format::Ascii;
      else if (tok[1] == "binary_little_endian")
        h.format = Format::BinaryLE;
      else if (tok[1] == "binary_big_endian")
        h.format = Format::BinaryBE;
      else
        fail(path, ln, "unknown PLY format '" + std::string(tok[1]) + "'");
      have_format = true;
    } else if (kw == "element") {
      long long count = 0;
      if (tok.size() != 3 || !parse_long(tok[2], count) || count < 0 || count > 2147483647LL)
        fail(path, ln, "expected 'element <name> <count>'");
      h.elements.push_back({std::string(tok[1]), count, {}});
    } else if (kw == "property") {
      if (h.elements.empty()) fail(path, ln, "'property' before any 'element'");
      h.elements.back().props.push_back(parse_property(path, ln, tok));
    } else {
      fail(path, ln, "unknown header keyword '" + std::string(kw) + "'");
    }
  }
  if (!have_end) fail(path, lines.line_number(), "unexpected end of file in the header (no 'end_header')");
  if (!have_format) fail(path, 0, "the header has no 'format' line");
  return h;
}

// Finds the 'vertex' element with its x, y, z properties and the 'face' element with its index list
// (the last element of each name is the one read). Throws when either is missing, the face element is
// empty or its list holds non-integers.
PlyLayout find_layout(const fs::path& path, const std::vector<Element>& elements) {
  PlyLayout l;
  for (const Element& e : elements) {
    if (e.name == "vertex") {
      l.vertex = &e;
      for (std::size_t i = 0; i < e.props.size(); ++i) {
        const Property& p = e.props[i];
        if (p.list) continue;
        if (p.name == "x") l.roles.x = static_cast<int>(i);
        if (p.name == "y") l.roles.y = static_cast<int>(i);
        if (p.name == "z") l.roles.z = static_cast<int>(i);
      }
    } else if (e.name == "face") {
      l.face = &e;
      for (std::size_t i = 0; i < e.props.size(); ++i)
        if (e.props[i].list && (e.props[i].name == "vertex_indices" || e.props[i].name == "vertex_index"))
          l.roles.indices = static_cast<int>(i);
    }
  }
  if (!l.vertex || l.roles.x < 0 || l.roles.y < 0 || l.roles.z < 0)
    fail(path, 0, "the header has no 'vertex' element with x, y and z properties");
  if (!l.face || l.face->count == 0)
    fail(path, 0, "no faces (the header has no 'face' element or it is empty)");
  if (l.roles.indices < 0) fail(path, 0, "the 'face' element has no 'vertex_indices' list");
  if (!is_integer(l.face->props[l.roles.indices].type))
    fail(path, 0, "the face 'vertex_indices' list has a non-integer item type");
  return l;
}

// The coordinate (0, 1, 2) vertex property `pi` holds, or -1 when it is none of x, y, z.
int coordinate_of(const Roles& roles, std::size_t pi) {
  const int i = static_cast<int>(pi);
  return i == roles.x ? 0 : i == roles.y ? 1 : i == roles.z ? 2 : -1;
}

// Appends face f's polygon `poly` to s.F, fan-triangulated, after checking it has at least 3 vertices
// and every index is below `vertex_count`; ln is its line (ASCII) or 0 (binary).
void add_polygon(const fs::path& path, const std::vector<long long>& poly, long long f, std::size_t ln,
                 long long vertex_count, Soup& s) {
  if (poly.size() < 3)
    fail(path, ln,
         "face " + std::to_string(f) + " has " + std::to_string(poly.size()) +
             " vertices (at least 3 needed)");
  for (long long i : poly)
    if (i < 0 || i >= vertex_count)
      fail(path, ln,
           "face " + std::to_string(f) + ": vertex index " + std::to_string(i) +
               " out of range (the file has " + std::to_string(vertex_count) + " vertices)");
  for (std::size_t c = 1; c + 1 < poly.size(); ++c) {
    s.F.push_back(static_cast<int>(poly[0]));
    s.F.push_back(static_cast<int>(poly[c]));
    s.F.push_back(static_cast<int>(poly[c + 1]));
  }
}

// Reads the ASCII body from `lines` (one item per non-blank line, elements in header order) into s.V
// and s.F. Throws on a missing line, too few values, or a value that does not parse.
void read_ascii_body(const fs::path& path, LineReader& lines, const PlyHeader& h, const PlyLayout& l,
                     Soup& s) {
  std::string_view line;
  std::vector<std::string_view> tok;
  std::vector<long long> poly;
  for (const Element& e : h.elements) {
    const bool is_v = &e == l.vertex, is_f = &e == l.face;
    for (long long i = 0; i < e.count; ++i) {
      do {
        if (!lines.next(line))
          fail(path, lines.line_number(),
               "unexpected end of file: element '" + e.name + "' announces " + std::to_string(e.count) +
                   ", the file holds " + std::to_string(i));
        split_tokens(line, tok, false);
      } while (tok.empty());
      const std::size_t ln = lines.line_number();
      std::size_t t = 0;
      double xyz[3] = {0, 0, 0};
      poly.clear();
      for (std::size_t pi = 0; pi < e.props.size(); ++pi) {
        const Property& p = e.props[pi];
        auto need = [&](std::size_t k) {
          if (t + k > tok.size())
            fail(path, ln,
                 "too few values for element '" + e.name + "' " + std::to_string(i) + " (property '" +
                     p.name + "')");
        };
        if (p.list) {
          need(1);
          long long k = 0;
          if (!parse_long(tok[t], k) || k < 0) fail(path, ln, "bad list size '" + std::string(tok[t]) + "'");
          ++t;
          need(static_cast<std::size_t>(k));
          if (is_f && static_cast<int>(pi) == l.roles.indices)
            for (long long c = 0; c < k; ++c) {
              long long idx = 0;
              if (!parse_long(tok[t + c], idx))
                fail(path, ln, "cannot parse '" + std::string(tok[t + c]) + "' as a vertex index");
              poly.push_back(idx);
            }
          t += static_cast<std::size_t>(k);
        } else {
          need(1);
          if (const int k = is_v ? coordinate_of(l.roles, pi) : -1; k >= 0) {
            double x = 0;
            if (!parse_double(tok[t], x))
              fail(path, ln, "cannot parse '" + std::string(tok[t]) + "' as a number");
            xyz[k] = x;
          }
          ++t;
        }
      }
      if (is_v) s.V.insert(s.V.end(), xyz, xyz + 3);
      if (is_f) add_polygon(path, poly, i, ln, l.vertex->count, s);
    }
  }
}

// Reads the binary body of `bytes` from byte `offset` (the end of the header; elements in header
// order, byte order from h.format) into s.V and s.F. Throws on a truncated file or a negative list size.
void read_binary_body(const fs::path& path, const std::string& bytes, std::size_t offset, const PlyHeader& h,
                      const PlyLayout& l, Soup& s) {
  const bool swap = (h.format == Format::BinaryBE) != (std::endian::native == std::endian::big);
  const char* p = bytes.data() + offset;
  const char* const end = bytes.data() + bytes.size();
  std::vector<long long> poly;
  for (const Element& e : h.elements) {
    // An element without properties takes no bytes: skip it rather than count to its (up to 2^31)
    // items, which a 200-byte file could ask for (found by fuzz_ply). Every other item takes at least
    // one byte, so the file size bounds the loop.
    if (e.props.empty()) continue;
    const bool is_v = &e == l.vertex, is_f = &e == l.face;
    for (long long i = 0; i < e.count; ++i) {
      double xyz[3] = {0, 0, 0};
      poly.clear();
      for (std::size_t pi = 0; pi < e.props.size(); ++pi) {
        const Property& pr = e.props[pi];
        auto need = [&](std::size_t nbytes) {
          if (static_cast<std::size_t>(end - p) < nbytes)
            fail(path, 0,
                 "unexpected end of file (truncated?) in element '" + e.name + "' " + std::to_string(i) +
                     " of " + std::to_string(e.count) + ", property '" + pr.name + "', byte offset " +
                     std::to_string(p - bytes.data()) + " of " + std::to_string(bytes.size()));
        };
        if (pr.list) {
          need(type_size(pr.count_type));
          const double kd = load_scalar(pr.count_type, p, swap);
          p += type_size(pr.count_type);
          if (kd < 0) fail(path, 0, "element '" + e.name + "' " + std::to_string(i) + ": negative list size");
          const std::size_t k = static_cast<std::size_t>(kd), sz = type_size(pr.type);
          need(k * sz);
          if (is_f && static_cast<int>(pi) == l.roles.indices)
            for (std::size_t c = 0; c < k; ++c)
              poly.push_back(static_cast<long long>(load_scalar(pr.type, p + c * sz, swap)));
          p += k * sz;
        } else {
          need(type_size(pr.type));
          if (const int k = is_v ? coordinate_of(l.roles, pi) : -1; k >= 0)
            xyz[k] = load_scalar(pr.type, p, swap);
          p += type_size(pr.type);
        }
      }
      if (is_v) s.V.insert(s.V.end(), xyz, xyz + 3);
      if (is_f) add_polygon(path, poly, i, 0, l.vertex->count, s);
    }
  }
}

}  // namespace

Mesh read_ply(const fs::path& path) {
  const std::string bytes = read_file_bytes(path);
  if (bytes.empty()) fail(path, 0, "the file is empty");
  LineReader lines(bytes);
  const PlyHeader header = read_header(path, lines);
  const PlyLayout layout = find_layout(path, header.elements);

  Soup s;
  // Every element takes at least one byte: never trust a (corrupt) header beyond the file size.
  s.V.reserve(3 * std::min<std::size_t>(static_cast<std::size_t>(layout.vertex->count), bytes.size()));
  s.F.reserve(3 * std::min<std::size_t>(static_cast<std::size_t>(layout.face->count), bytes.size()));
  if (header.format == Format::Ascii)
    read_ascii_body(path, lines, header, layout, s);
  else
    read_binary_body(path, bytes, lines.offset(), header, layout, s);
  return s.to_mesh();
}

void write_ply(const fs::path& path, const Mesh& mesh, bool binary) {
  check_writable(path, mesh);
  std::string out;
  out += "ply\nformat ";
  out += binary ? "binary_little_endian" : "ascii";
  out += " 1.0\ncomment spinmotor\nelement vertex " + std::to_string(mesh.V.rows()) +
         "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
         std::to_string(mesh.F.rows()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  if (binary) {
    const bool swap = std::endian::native == std::endian::big;
    auto put = [&](auto v) {
      char b[sizeof v];
      std::memcpy(b, &v, sizeof v);
      if (swap)
        for (std::size_t i = 0; i < sizeof v / 2; ++i) std::swap(b[i], b[sizeof v - 1 - i]);
      out.append(b, sizeof v);
    };
    out.reserve(out.size() + static_cast<std::size_t>(mesh.V.rows() * 24 + mesh.F.rows() * 13));
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
      for (int k = 0; k < 3; ++k) put(static_cast<double>(mesh.V(i, k)));
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
      put(static_cast<std::uint8_t>(3));
      for (int c = 0; c < 3; ++c) put(static_cast<std::int32_t>(mesh.F(f, c)));
    }
  } else {
    out.reserve(out.size() + static_cast<std::size_t>(mesh.V.rows() * 60 + mesh.F.rows() * 30));
    append_vertex_face_lines(out, mesh.V, mesh.F);
  }
  write_text_atomic(path, out);
}

}  // namespace spinmotor
