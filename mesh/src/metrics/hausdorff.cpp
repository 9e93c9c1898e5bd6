#include "spinmotor/mesh/metrics/hausdorff.hpp"

#include <Eigen/Geometry>
#include <array>
#include <numeric>
#include <vector>

#include "metric_checks.hpp"

namespace spinmotor {
namespace {

using Vec3 = Eigen::Vector3d;

// Closest point on segment ab to p, squared distance.
double segment_sq_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).squaredNorm();
}

// Squared distance from p to triangle abc (Ericson 2005, §5.1.5, ClosestPtPointTriangle: Voronoi
// regions of the vertices, then of the edges, else the face interior).
double triangle_sq_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double area2 = ab.cross(ac).squaredNorm();
  const double l2 = std::max({ab.squaredNorm(), ac.squaredNorm(), (c - b).squaredNorm()});
  if (!(area2 > kDegenerateFace * kDegenerateFace * l2 * l2))  // degenerate: nearest edge
    return std::min(
        {segment_sq_distance(p, a, b), segment_sq_distance(p, b, c), segment_sq_distance(p, c, a)});
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();  // vertex a
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();  // vertex b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (a + d1 / (d1 - d3) * ab - p).squaredNorm();  // edge ab
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();  // vertex c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (a + d2 / (d2 - d6) * ac - p).squaredNorm();  // edge ac
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)  // edge bc
    return (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b) - p).squaredNorm();
  const double denom = 1.0 / (va + vb + vc);  // interior: barycentric (u, v, w) = (va, vb, vc)/Σ
  return (a + ab * (vb * denom) + ac * (vc * denom) - p).squaredNorm();
}

// Bounding-volume hierarchy over the triangles: a node covers the packed triangles [begin, end);
// leaves hold ≤ 4. Triangles are split at the median centroid along the widest centroid extent, and
// their corners are stored contiguously in tree order so that a leaf is one cache-friendly read.
class TriangleTree {
 public:
  TriangleTree(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
    const int m = static_cast<int>(F.rows());
    std::vector<Item> items(static_cast<size_t>(m));
    for (int f = 0; f < m; ++f)
      items[f] = {(V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3.0, f};
    nodes_.reserve(static_cast<size_t>(2 * m / kLeaf + 2));
    build(items, 0, m);
    face_.resize(static_cast<size_t>(m));
    corners_.resize(static_cast<size_t>(m));
    for (int k = 0; k < m; ++k) {
      face_[k] = items[k].face;
      for (int c = 0; c < 3; ++c) corners_[k][c] = V.row(F(items[k].face, c)).transpose();
    }
    fit_boxes(0);
  }

  // Squared distance from p to the surface and the closest face.
  std::pair<double, int> nearest(const Vec3& p) const {
    double best = std::numeric_limits<double>::infinity();
    int best_k = -1;
    // Median splits keep the depth ≤ log2(m) + 1 ≤ 32, and the stack holds at most one pending
    // sibling per level plus the current pair: 128 entries suffice for any int-indexed mesh.
    std::array<int, 128> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& nd = nodes_[stack[--top]];
      if (box_sq_distance(nd, p) >= best) continue;
      if (nd.left < 0) {
        for (int k = nd.begin; k < nd.end; ++k) {
          const double d = triangle_sq_distance(p, corners_[k][0], corners_[k][1], corners_[k][2]);
          if (d < best) best = d, best_k = k;
        }
        continue;
      }
      // Visit the nearer child first: push it last.
      const double dl = box_sq_distance(nodes_[nd.left], p), dr = box_sq_distance(nodes_[nd.right], p);
      const int first = dl <= dr ? nd.left : nd.right, second = dl <= dr ? nd.right : nd.left;
      stack[top++] = second;
      stack[top++] = first;
    }
    return {best, best_k < 0 ? -1 : face_[best_k]};
  }

 private:
  static constexpr int kLeaf = 4;
  struct Item {
    Vec3 centroid;
    int face;
  };
  struct Node {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // the bounding box, set by build()
    int begin = 0, end = 0, left = -1, right = -1;
  };

  static double box_sq_distance(const Node& nd, const Vec3& p) {
    return (nd.lo - p).cwiseMax(p - nd.hi).cwiseMax(0.0).squaredNorm();
  }

  int build(std::vector<Item>& items, int begin, int end) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.push_back({});
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    if (end - begin <= kLeaf) return id;
    Vec3 lo = items[begin].centroid, hi = lo;
    for (int k = begin + 1; k < end; ++k) {
      lo = lo.cwiseMin(items[k].centroid);
      hi = hi.cwiseMax(items[k].centroid);
    }
    int axis;
    (hi - lo).maxCoeff(&axis);
    const int mid = begin + (end - begin) / 2;
    std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end,
                     [axis](const Item& a, const Item& b) { return a.centroid[axis] < b.centroid[axis]; });
    const int left = build(items, begin, mid);
    const int right = build(items, mid, end);
    nodes_[id].left = left;
    nodes_[id].right = right;
    return id;
  }

  // Boxes bottom-up: a leaf bounds its triangles, an inner node its two children.
  void fit_boxes(int id) {
    Node& nd = nodes_[id];
    if (nd.left < 0) {
      nd.lo = corners_[nd.begin][0];
      nd.hi = nd.lo;
      for (int k = nd.begin; k < nd.end; ++k)
        for (int c = 0; c < 3; ++c) {
          nd.lo = nd.lo.cwiseMin(corners_[k][c]);
          nd.hi = nd.hi.cwiseMax(corners_[k][c]);
        }
      return;
    }
    fit_boxes(nd.left);
    fit_boxes(nd.right);
    nd.lo = nodes_[nd.left].lo.cwiseMin(nodes_[nd.right].lo);
    nd.hi = nodes_[nd.left].hi.cwiseMax(nodes_[nd.right].hi);
  }

  std::vector<Node> nodes_;
  std::vector<int> face_;                     // face index of each packed triangle
  std::vector<std::array<Vec3, 3>> corners_;  // packed triangle corners, tree order
};

void check_surface(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const char* who, const char* name) {
  detail::check_points(V, who, name);
  if (F.cols() != 3 || F.rows() == 0) throw Error(std::string(who) + ": " + name + " has no m×3 faces");
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (F(f, c) < 0 || F(f, c) >= V.rows())
        throw Error(std::string(who) + ": " + name + " face " + std::to_string(f) + " has vertex index " +
                    std::to_string(F(f, c)) + " out of range [0, " + std::to_string(V.rows()) + ")");
}

// Max and mean distance from the vertices referenced by FA to surface B.
std::pair<double, double> one_sided(const Eigen::MatrixXd& VA, const Eigen::MatrixXi& FA,
                                    const TriangleTree& B) {
  std::vector<char> used(static_cast<size_t>(VA.rows()), 0);
  for (Eigen::Index k = 0; k < FA.size(); ++k) used[FA.data()[k]] = 1;
  const Eigen::Index n = VA.rows();
  Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
#pragma omp parallel for schedule(dynamic, 256)
  for (Eigen::Index i = 0; i < n; ++i)
    if (used[i]) d[i] = std::sqrt(B.nearest(VA.row(i).transpose()).first);
  double mx = 0, sum = 0;
  Eigen::Index count = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (used[i]) mx = std::max(mx, d[i]), sum += d[i], ++count;
  return {mx, count > 0 ? sum / static_cast<double>(count) : 0.0};
}

}  // namespace

Eigen::VectorXd point_mesh_distances(const Eigen::MatrixXd& P, const Eigen::MatrixXd& V,
                                     const Eigen::MatrixXi& F, Eigen::VectorXi* closest_face) {
  detail::check_points(P, "point_mesh_distances", "query");
  check_surface(V, F, "point_mesh_distances", "surface");
  const TriangleTree tree(V, F);
  Eigen::VectorXd d(P.rows());
  if (closest_face) closest_face->resize(P.rows());
#pragma omp parallel for schedule(dynamic, 256)
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    const auto [d2, f] = tree.nearest(P.row(i).transpose());
    d[i] = std::sqrt(d2);
    if (closest_face) (*closest_face)[i] = f;
  }
  return d;
}

HausdorffDistance hausdorff_distance(const Eigen::MatrixXd& VA, const Eigen::MatrixXi& FA,
                                     const Eigen::MatrixXd& VB, const Eigen::MatrixXi& FB) {
  check_surface(VA, FA, "hausdorff_distance", "mesh A");
  check_surface(VB, FB, "hausdorff_distance", "mesh B");
  HausdorffDistance h;
  {
    const TriangleTree B(VB, FB);
    std::tie(h.a_to_b, h.mean_a_to_b) = one_sided(VA, FA, B);
  }
  {
    const TriangleTree A(VA, FA);
    std::tie(h.b_to_a, h.mean_b_to_a) = one_sided(VB, FB, A);
  }
  h.hausdorff = std::max(h.a_to_b, h.b_to_a);
  return h;
}

}  // namespace spinmotor
