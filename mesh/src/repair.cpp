#include "spinmotor/mesh/repair.hpp"

#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

#include "spinmotor/core/error.hpp"

namespace spinmotor {
namespace {

void check_indices(const Mesh& mesh, const char* op) {
  const Eigen::Index n = mesh.V.rows();
  if (mesh.F.size() > 0 && mesh.F.cols() != 3)
    throw Error(std::string(op) + ": F has " + std::to_string(mesh.F.cols()) + " columns, expected 3");
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (mesh.F(f, c) < 0 || mesh.F(f, c) >= n)
        throw Error(std::string(op) + ": face " + std::to_string(f) + " references vertex " +
                    std::to_string(mesh.F(f, c)) + ", but the mesh has " + std::to_string(n) + " vertices");
}

// Renumbers F by map (old vertex -> new, −1 = dropped; the kept vertices are numbered 0..kept-1 in
// increasing old order) and keeps the first old vertex of each new index.
Mesh apply_map(const Mesh& mesh, const Eigen::VectorXi& map, Eigen::Index kept) {
  Mesh out;
  out.V.resize(kept, mesh.V.cols());
  for (Eigen::Index v = 0, k = 0; v < mesh.V.rows(); ++v)
    if (map[v] == k) out.V.row(k++) = mesh.V.row(v);
  out.F.resize(mesh.F.rows(), mesh.F.cols());
  for (Eigen::Index i = 0; i < mesh.F.size(); ++i) out.F.data()[i] = map[mesh.F.data()[i]];
  out.UV = mesh.UV;
  out.FUV = mesh.FUV;
  return out;
}

}  // namespace

Mesh remove_unreferenced_vertices(const Mesh& mesh, Eigen::VectorXi* old_to_new) {
  check_indices(mesh, "remove_unreferenced_vertices");
  const Eigen::Index n = mesh.V.rows();
  std::vector<char> used(static_cast<std::size_t>(n), 0);
  for (Eigen::Index i = 0; i < mesh.F.size(); ++i) used[mesh.F.data()[i]] = 1;
  Eigen::VectorXi map = Eigen::VectorXi::Constant(n, -1);
  int k = 0;
  for (Eigen::Index v = 0; v < n; ++v)
    if (used[v]) map[v] = k++;
  Mesh out = apply_map(mesh, map, k);
  if (old_to_new) *old_to_new = std::move(map);
  return out;
}

Mesh merge_duplicate_vertices(const Mesh& mesh, Eigen::VectorXi* old_to_new) {
  check_indices(mesh, "merge_duplicate_vertices");
  const Eigen::MatrixXd& V = mesh.V;
  const Eigen::Index n = V.rows();
  // rep[v]: the lowest-numbered vertex at v's position (v itself if none lower). Non-finite
  // vertices stay out of the sort (NaN would break its ordering) and are never merged.
  std::vector<int> order, rep(static_cast<std::size_t>(n));
  std::iota(rep.begin(), rep.end(), 0);
  order.reserve(static_cast<std::size_t>(n));
  for (Eigen::Index v = 0; v < n; ++v)
    if (V.row(v).allFinite()) order.push_back(static_cast<int>(v));
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    for (int k = 0; k < V.cols(); ++k)
      if (V(a, k) != V(b, k)) return V(a, k) < V(b, k);
    return a < b;
  });
  for (std::size_t i = 1, first = 0; i < order.size(); ++i) {
    if (V.row(order[i]) == V.row(order[first]))
      rep[order[i]] = order[first];  // ties are sorted by index, so order[first] is the lowest
    else
      first = i;
  }
  Eigen::VectorXi map(n);
  int k = 0;
  for (Eigen::Index v = 0; v < n; ++v) map[v] = rep[v] == v ? k++ : map[rep[v]];
  Mesh out = apply_map(mesh, map, k);
  if (old_to_new) *old_to_new = std::move(map);
  return out;
}

}  // namespace spinmotor
