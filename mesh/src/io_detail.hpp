#pragma once
// Private helpers shared by the mesh readers and writers (io_*.cpp): whole-file reads, line-aware
// tokenizing, locale-independent number parsing and shortest round-trip number printing, error
// messages naming file:line, and the soup builder.
#include <charconv>
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor::io_detail {

/// The whole file as bytes. Throws Error naming the path if it cannot be opened or read.
std::string read_file_bytes(const std::filesystem::path& path);

/// "file:line: msg" (line > 0) or "file: msg".
[[noreturn]] void fail(const std::filesystem::path& path, std::size_t line, const std::string& msg);

/// Parses a whole token as a double (accepts a leading '+', "nan", "inf"). Locale-independent.
inline bool parse_double(std::string_view s, double& out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && !s.empty();
}

/// Parses a whole token as a (possibly negative) integer.
inline bool parse_long(std::string_view s, long long& out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && !s.empty();
}

/// Appends the shortest decimal form of x that parses back to exactly x.
inline void append_double(std::string& out, double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  out.append(buf, r.ptr);
}

inline void append_int(std::string& out, long long x) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  out.append(buf, r.ptr);
}

/// The vertex and face lines shared by OFF and ASCII PLY: "x y z" per vertex, then "3 a b c" per face.
inline void append_vertex_face_lines(std::string& out, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (k) out += ' ';
      append_double(out, V(i, k));
    }
    out += '\n';
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    out += '3';
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      append_int(out, F(f, c));
    }
    out += '\n';
  }
}

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// Splits a line (no '\n') into whitespace-separated tokens, stopping at '#' when `hash_comments`.
inline void split_tokens(std::string_view line, std::vector<std::string_view>& tokens, bool hash_comments) {
  tokens.clear();
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && is_space(line[i])) ++i;
    if (i >= n || (hash_comments && line[i] == '#')) break;
    const std::size_t start = i;
    while (i < n && !is_space(line[i]) && !(hash_comments && line[i] == '#')) ++i;
    tokens.emplace_back(line.data() + start, i - start);
  }
}

/// Iterates over the lines of a text buffer, counting them from 1.
class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(text) {}
  /// Next line without its '\n' (a trailing '\r' is kept; is_space() treats it as blank).
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = text_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line = text_.substr(pos_, stop - pos_);
    pos_ = end == std::string_view::npos ? text_.size() : end + 1;
    ++line_;
    return true;
  }
  std::size_t line_number() const { return line_; }
  std::size_t offset() const { return pos_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

/// Vertex and face lists as they are read, turned into a Mesh at the end.
struct Soup {
  std::vector<double> V;   // 3 per vertex
  std::vector<int> F;      // 3 per triangle
  std::vector<double> UV;  // 2 per texture coordinate
  std::vector<int> FUV;    // 3 per triangle, or empty
  Mesh to_mesh() const;
};

/// Structural checks before writing: V has 3 columns, F has 3 columns and at least one row, every
/// F index is in [0, n), and UV/FUV (if present) are consistent. Throws Error naming `path` and the
/// first bad face.
void check_writable(const std::filesystem::path& path, const Mesh& mesh);

}  // namespace spinmotor::io_detail
