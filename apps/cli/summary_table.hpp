#pragma once
// A plain-text table for command summaries: columns sized to their widest cell, numbers right-aligned.
#include <algorithm>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

namespace spinmotor::cli {

class SummaryTable {
 public:
  explicit SummaryTable(std::vector<std::string> header) : header_(std::move(header)) {}

  void add_row(std::vector<std::string> row) {
    row.resize(header_.size());
    rows_.push_back(std::move(row));
  }

  void print(std::ostream& out) const {
    std::vector<size_t> width(header_.size());
    for (size_t c = 0; c < header_.size(); ++c) {
      width[c] = header_[c].size();
      for (const auto& r : rows_) width[c] = std::max(width[c], r[c].size());
    }
    auto line = [&](const std::vector<std::string>& r) {
      for (size_t c = 0; c < r.size(); ++c) {
        const size_t pad = width[c] - r[c].size();
        const bool text = c == 0 || c + 1 == r.size();  // first and last columns are labels
        if (c > 0) out << "  ";
        if (text)
          out << r[c] << (c + 1 == r.size() ? std::string() : std::string(pad, ' '));
        else
          out << std::string(pad, ' ') << r[c];
      }
      out << '\n';
    };
    line(header_);
    size_t total = 0;
    for (size_t w : width) total += w + 2;
    out << std::string(total - 2, '-') << '\n';
    for (const auto& r : rows_) line(r);
  }

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

/// Fixed-point formatting with `digits` decimals ("-" for a NaN placeholder).
inline std::string fmt(double x, int digits = 3) {
  if (x != x) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

}  // namespace spinmotor::cli
