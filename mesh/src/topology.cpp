#include "spinmotor/mesh/topology.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>

#include "union_find.hpp"

namespace spinmotor {
namespace {

using detail::UnionFind;

}  // namespace

EdgeTopology edge_topology(const Eigen::MatrixXi& F) {
  // Bucket every corner's opposite edge by its smaller vertex (a counting sort), then sort each short
  // bucket by (larger vertex, face, corner): O(m) plus tiny sorts, and the edges come out in
  // lexicographic order with their incident faces in increasing face order.
  const Eigen::Index m = F.rows();
  const Eigen::Index n = m ? F.maxCoeff() + 1 : 0;
  std::vector<int> offset(static_cast<size_t>(n) + 1, 0);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) ++offset[std::min(F(f, (c + 1) % 3), F(f, (c + 2) % 3)) + 1];
  for (Eigen::Index i = 0; i < n; ++i) offset[i + 1] += offset[i];
  // Entry key: (larger vertex) << 32 | (3 f + c), so one integer sort orders by vertex, then face.
  std::vector<std::uint64_t> entry(static_cast<size_t>(3 * m));
  std::vector<int> fill(offset.begin(), offset.end() - 1);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = F(f, (c + 1) % 3), b = F(f, (c + 2) % 3);
      entry[fill[std::min(a, b)]++] =
          (static_cast<std::uint64_t>(std::max(a, b)) << 32) | static_cast<std::uint64_t>(3 * f + c);
    }

  EdgeTopology t;
  t.FE.resize(m, 3);
  t.EF_face.resize(3 * m);
  std::vector<int> edge_offset, e0, e1;
  edge_offset.reserve(static_cast<size_t>(3 * m / 2 + 2));
  e0.reserve(static_cast<size_t>(3 * m / 2 + 1));
  e1.reserve(static_cast<size_t>(3 * m / 2 + 1));
  for (Eigen::Index a = 0; a < n; ++a) {
    const auto begin = entry.begin() + offset[a], end = entry.begin() + offset[a + 1];
    std::sort(begin, end);
    for (auto it = begin; it != end; ++it) {
      const auto i = static_cast<Eigen::Index>(it - entry.begin());
      const int b = static_cast<int>(*it >> 32), corner = static_cast<int>(*it & 0xffffffffu);
      if (it == begin || (*(it - 1) >> 32) != (*it >> 32)) {
        edge_offset.push_back(static_cast<int>(i));
        e0.push_back(static_cast<int>(a));
        e1.push_back(b);
      }
      t.FE(corner / 3, corner % 3) = static_cast<int>(e0.size() - 1);
      t.EF_face[i] = corner / 3;
    }
  }
  edge_offset.push_back(static_cast<int>(3 * m));
  t.E.resize(static_cast<Eigen::Index>(e0.size()), 2);
  for (size_t e = 0; e < e0.size(); ++e) t.E.row(static_cast<Eigen::Index>(e)) << e0[e], e1[e];
  t.EF_offset =
      Eigen::Map<Eigen::VectorXi>(edge_offset.data(), static_cast<Eigen::Index>(edge_offset.size()));
  return t;
}

Eigen::VectorXi vertex_components(const Eigen::MatrixXi& F, Eigen::Index n, int* count) {
  UnionFind uf(static_cast<std::size_t>(n));
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
