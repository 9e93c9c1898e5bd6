#pragma once
// Private to mesh/: disjoint sets over 0..n−1 (path halving, the smaller index as the root, so a
// component's root is its lowest element and component numbering follows vertex order).
#include <algorithm>
#include <cstddef>
#include <numeric>
#include <vector>

namespace spinmotor::detail {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace spinmotor::detail
