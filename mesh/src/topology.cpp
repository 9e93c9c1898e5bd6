#include "spinmotor/mesh/topology.hpp"

#include <algorithm>
#include <array>
#include <numeric>

namespace spinmotor {
namespace {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(Eigen::Index n) : parent(static_cast<size_t>(n)) {
    std::iota(parent.begin(), parent.end(), 0);
  }
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

}  // namespace

EdgeTopology edge_topology(const Eigen::MatrixXi& F) {
  const Eigen::Index m = F.rows();
  // (min, max, face, corner) for every corner's opposite edge; sort to group equal edges.
  std::vector<std::array<int, 4>> h(static_cast<size_t>(3 * m));
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = F(f, (c + 1) % 3), b = F(f, (c + 2) % 3);
      h[3 * f + c] = {std::min(a, b), std::max(a, b), static_cast<int>(f), c};
    }
  std::sort(h.begin(), h.end());

  EdgeTopology t;
  t.FE.resize(m, 3);
  t.EF_face.resize(3 * m);
  std::vector<int> offsets;
  std::vector<std::array<int, 2>> edges;
  offsets.reserve(3 * m / 2 + 2);
  for (size_t i = 0; i < h.size(); ++i) {
    if (i == 0 || h[i][0] != h[i - 1][0] || h[i][1] != h[i - 1][1]) {
      offsets.push_back(static_cast<int>(i));
      edges.push_back({h[i][0], h[i][1]});
    }
    t.FE(h[i][2], h[i][3]) = static_cast<int>(edges.size() - 1);
    t.EF_face[static_cast<Eigen::Index>(i)] = h[i][2];
  }
  offsets.push_back(static_cast<int>(h.size()));
  t.E.resize(static_cast<Eigen::Index>(edges.size()), 2);
  for (size_t e = 0; e < edges.size(); ++e) {
    t.E(e, 0) = edges[e][0];
    t.E(e, 1) = edges[e][1];
  }
  t.EF_offset = Eigen::Map<Eigen::VectorXi>(offsets.data(), static_cast<Eigen::Index>(offsets.size()));
  return t;
}

Eigen::VectorXi vertex_components(const Eigen::MatrixXi& F, Eigen::Index n, int* count) {
  UnionFind uf(n);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    uf.unite(F(f, 0), F(f, 1));
    uf.unite(F(f, 0), F(f, 2));
  }
  Eigen::VectorXi label = Eigen::VectorXi::Constant(n, -1);
  std::vector<int> root_label(static_cast<size_t>(n), -1);
  int c = 0;
  for (Eigen::Index v = 0; v < n; ++v) {
    const int r = uf.find(static_cast<int>(v));
    if (root_label[r] < 0) root_label[r] = c++;
    label[v] = root_label[r];
  }
  if (count) *count = c;
  return label;
}

Eigen::VectorXi face_components(const Eigen::MatrixXi& F, int* count) {
  const Eigen::Index n = F.size() ? F.maxCoeff() + 1 : 0;
  const Eigen::VectorXi vl = vertex_components(F, n);
  Eigen::VectorXi label(F.rows());
  std::vector<int> renum(static_cast<size_t>(n), -1);
  int c = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    int& r = renum[vl[F(f, 0)]];
    if (r < 0) r = c++;
    label[f] = r;
  }
  if (count) *count = c;
  return label;
}

std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixXi& F) {
  const EdgeTopology t = edge_topology(F);
  // Boundary halfedges a->b oriented as in their one face, sorted by tail for lookup.
  std::vector<std::array<int, 2>> he;
  for (Eigen::Index e = 0; e < t.num_edges(); ++e) {
    if (t.valence(e) != 1) continue;
    const int f = t.EF_face[t.EF_offset[e]];
    for (int c = 0; c < 3; ++c)
      if (t.FE(f, c) == e) he.push_back({F(f, (c + 1) % 3), F(f, (c + 2) % 3)});
  }
  std::sort(he.begin(), he.end());
  std::vector<char> used(he.size(), 0);
  auto first_unused_from = [&](int v) -> int {
    auto it = std::lower_bound(he.begin(), he.end(), std::array<int, 2>{v, -1});
    for (; it != he.end() && (*it)[0] == v; ++it)
      if (!used[it - he.begin()]) return static_cast<int>(it - he.begin());
    return -1;
  };
  std::vector<std::vector<int>> loops;
  for (size_t s = 0; s < he.size(); ++s) {
    if (used[s]) continue;
    std::vector<int> loop;
    int h = static_cast<int>(s);
    const int start = he[s][0];
    while (h >= 0) {
      used[h] = 1;
      loop.push_back(he[h][0]);
      if (he[h][1] == start) break;
      h = first_unused_from(he[h][1]);
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

Eigen::VectorXi boundary_vertices(const Eigen::MatrixXi& F, Eigen::Index n) {
  const EdgeTopology t = edge_topology(F);
  std::vector<char> on(static_cast<size_t>(n), 0);
  for (Eigen::Index e = 0; e < t.num_edges(); ++e)
    if (t.valence(e) == 1) on[t.E(e, 0)] = on[t.E(e, 1)] = 1;
  std::vector<int> out;
  for (Eigen::Index v = 0; v < n; ++v)
    if (on[v]) out.push_back(static_cast<int>(v));
  return Eigen::Map<Eigen::VectorXi>(out.data(), static_cast<Eigen::Index>(out.size()));
}

Eigen::VectorXi interior_vertices(const Eigen::MatrixXi& F, Eigen::Index n) {
  const Eigen::VectorXi b = boundary_vertices(F, n);
  std::vector<char> flag(static_cast<size_t>(n), 0);  // 1 referenced, 2 boundary
  for (Eigen::Index i = 0; i < F.size(); ++i) flag[F.data()[i]] = 1;
  for (Eigen::Index i = 0; i < b.size(); ++i) flag[b[i]] = 2;
  std::vector<int> out;
  for (Eigen::Index v = 0; v < n; ++v)
    if (flag[v] == 1) out.push_back(static_cast<int>(v));
  return Eigen::Map<Eigen::VectorXi>(out.data(), static_cast<Eigen::Index>(out.size()));
}

}  // namespace spinmotor
