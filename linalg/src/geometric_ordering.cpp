#include "spinmotor/linalg/geometric_ordering.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>

#include "spinmotor/core/error.hpp"

namespace spinmotor {

namespace {

/// Appends the order of `nodes` to `order`; `label` (size n) is scratch: unlabelled nodes hold -1.
void dissect(const Eigen::Ref<const Eigen::MatrixXd>& P, std::span<const int> off, std::span<const int> nbr,
             std::vector<int>& nodes, std::vector<int>& label, int& next_label, std::vector<int>& order) {
  constexpr std::size_t kLeaf = 32;
  if (nodes.size() <= kLeaf) {
    order.insert(order.end(), nodes.begin(), nodes.end());
    return;
  }
  Eigen::RowVector3d lo = P.row(nodes[0]), hi = lo;
  for (int v : nodes) lo = lo.cwiseMin(P.row(v)), hi = hi.cwiseMax(P.row(v));
  int axis;
  (hi - lo).maxCoeff(&axis);
  const std::size_t mid = nodes.size() / 2;
  std::nth_element(nodes.begin(), nodes.begin() + static_cast<std::ptrdiff_t>(mid), nodes.end(),
                   [&](int a, int b) { return P(a, axis) < P(b, axis); });
  const int L = next_label++, R = next_label++;
  for (std::size_t k = 0; k < nodes.size(); ++k) label[nodes[k]] = k < mid ? L : R;
  const auto touches = [&](int v, int other) {
    for (int k = off[v]; k < off[v + 1]; ++k)
      if (label[nbr[k]] == other) return true;
    return false;
  };
  std::vector<int> left, right, sep_left, sep_right;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const int v = nodes[k];
    const bool is_left = k < mid;
    (touches(v, is_left ? R : L) ? (is_left ? sep_left : sep_right) : (is_left ? left : right)).push_back(v);
  }
  // Keep the shorter boundary as separator; the other goes back to its half.
  std::vector<int>& sep = sep_left.size() <= sep_right.size() ? sep_left : sep_right;
  if (&sep == &sep_left)
    right.insert(right.end(), sep_right.begin(), sep_right.end());
  else
    left.insert(left.end(), sep_left.begin(), sep_left.end());
  const int S = next_label++;
  for (int v : sep) label[v] = S;
  if (left.empty() || right.empty()) {  // no progress (e.g. coincident coordinates): stop here
    order.insert(order.end(), nodes.begin(), nodes.end());
    return;
  }
  std::vector<int>().swap(nodes);
  dissect(P, off, nbr, left, label, next_label, order);
  dissect(P, off, nbr, right, label, next_label, order);
  order.insert(order.end(), sep.begin(), sep.end());
}

/// grid_nested_dissection's directions a: s = a·x changes by at most one along a 7-point edge.
constexpr std::array<std::array<int, 3>, 7> kGridDirections{
    {{1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {-1, 1, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};

/// Appends the nested-dissection order of `region` (indices into x) to `order`; `s` is scratch.
void dissect_grid(std::span<const std::array<int, 3>> x, std::vector<int>& region, std::vector<long>& s,
                  std::vector<int>& order) {
  constexpr std::size_t kLeaf = 32;
  if (region.size() <= kLeaf) {
    order.insert(order.end(), region.begin(), region.end());
    return;
  }
  const auto along = [&](const std::array<int, 3>& a, int v) {
    return long{a[0]} * x[v][0] + long{a[1]} * x[v][1] + long{a[2]} * x[v][2];
  };
  // Per direction, the plane s = a·x through the median, moved off either end so that both sides
  // keep unknowns, and the unknowns on it. The fewest on the plane win among the planes that leave at
  // most 3/4 of the region on either side (a median plane does, unless it had to move); without
  // one, the most even split (so that the recursion stays O(log m) deep on any input).
  int best = -1;
  long best_plane = 0;
  std::size_t best_cost = SIZE_MAX;
  const std::size_t size = region.size();
  const auto mid = static_cast<std::ptrdiff_t>(size / 2);
  for (int d = 0; d < static_cast<int>(kGridDirections.size()); ++d) {
    s.clear();
    for (int v : region) s.push_back(along(kGridDirections[d], v));
    const auto [lo, hi] = std::minmax_element(s.begin(), s.end());
    if (*hi - *lo < 2) continue;
    const long first = *lo, last = *hi;
    std::nth_element(s.begin(), s.begin() + mid, s.end());
    const long plane = std::clamp(s[static_cast<std::size_t>(mid)], first + 1, last - 1);
    std::size_t below = 0, on = 0;
    for (long sv : s) below += sv < plane, on += sv == plane;
    const std::size_t larger = std::max(below, size - below - on);
    const std::size_t cost = 4 * larger <= 3 * size ? on : size + larger;
    if (cost < best_cost) best = d, best_plane = plane, best_cost = cost;
  }
  if (best < 0) {  // a region no more than two layers thick in every direction: keep it whole
    order.insert(order.end(), region.begin(), region.end());
    return;
  }
  std::vector<int> below, above, plane;
  for (int v : region) {
    const long sv = along(kGridDirections[best], v);
    (sv < best_plane ? below : sv > best_plane ? above : plane).push_back(v);
  }
  std::vector<int>().swap(region);
  dissect_grid(x, below, s, order);
  dissect_grid(x, above, s, order);
  order.insert(order.end(), plane.begin(), plane.end());
}

}  // namespace

std::vector<int> grid_nested_dissection(std::span<const std::array<int, 3>> nodes) {
  if (nodes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw Error("grid_nested_dissection: more than 2^31 - 1 unknowns");
  std::vector<int> region(nodes.size()), order;
  std::vector<long> s;
  std::iota(region.begin(), region.end(), 0);
  order.reserve(nodes.size());
  dissect_grid(nodes, region, s, order);
  return order;
}

std::vector<int> geometric_nested_dissection(const Eigen::Ref<const Eigen::MatrixXd>& P,
                                             std::span<const int> off, std::span<const int> nbr,
                                             std::span<const char> excluded) {
  const Eigen::Index n = P.rows();
  if (P.cols() != 3 || off.size() != static_cast<std::size_t>(n) + 1 ||
      excluded.size() != static_cast<std::size_t>(n) || (n > 0 && off[0] != 0) ||
      static_cast<std::size_t>(off[static_cast<std::size_t>(n)]) > nbr.size())
    throw Error(
        "geometric_nested_dissection: P must be n×3, off hold n + 1 offsets into nbr, excluded n flags");
  std::vector<int> nodes, order;
  for (int i = 0; i < static_cast<int>(n); ++i)
    if (!excluded[static_cast<std::size_t>(i)]) nodes.push_back(i);
  order.reserve(nodes.size());
  std::vector<int> label(static_cast<std::size_t>(n), -1);  // excluded unknowns never match a label
  int next_label = 0;
  dissect(P, off, nbr, nodes, label, next_label, order);
  return order;
}

}  // namespace spinmotor
