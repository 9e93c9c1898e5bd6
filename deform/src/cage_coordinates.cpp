#include "spinmotor/deform/cage_coordinates.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/huge_pages.hpp"
#include "spinmotor/core/memory_budget.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/deform/deformer.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/linalg/geometric_ordering.hpp"

namespace spinmotor {

namespace {

using Eigen::Index;
using Eigen::Vector3d;

/// Closest point of triangle abc to p as barycentric coordinates (Ericson, Real-Time Collision
/// Detection §5.1.5); returns the squared distance.
double closest_on_triangle(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c,
                           Vector3d& bary) {
  const Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) {
    bary = {1, 0, 0};
  } else {
    const Vector3d bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    const Vector3d cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
    if (d3 >= 0 && d4 <= d3) {
      bary = {0, 1, 0};
    } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
      const double v = d1 / (d1 - d3);
      bary = {1 - v, v, 0};
    } else if (d6 >= 0 && d5 <= d6) {
      bary = {0, 0, 1};
    } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
      const double w = d2 / (d2 - d6);
      bary = {1 - w, 0, w};
    } else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
      const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
      bary = {0, 1 - w, w};
    } else {
      const double denom = 1.0 / (va + vb + vc);
      const double v = vb * denom, w = vc * denom;
      bary = {1 - v - w, v, w};
    }
  }
  return (bary[0] * a + bary[1] * b + bary[2] * c - p).squaredNorm();
}

/// Signed solid angle of triangle abc seen from x (Van Oosterom & Strackee 1983).
double solid_angle(const Vector3d& x, const Vector3d& A, const Vector3d& B, const Vector3d& Cc) {
  const Vector3d a = A - x, b = B - x, c = Cc - x;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double num = a.dot(b.cross(c));
  const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
  return 2.0 * std::atan2(num, den);
}

double cage_scale(const Eigen::MatrixXd& C) {
  return (C.colwise().maxCoeff() - C.colwise().minCoeff()).maxCoeff();
}

/// Throws unless every point is inside the cage or on it (winding number ≥ ½, or within 1e-12 × scale
/// of a face), naming the first that is not.
void require_inside(const Eigen::MatrixXd& C, const Eigen::MatrixXi& CF, const Eigen::MatrixXd& X) {
  const Index n = X.rows();
  for (Index i = 0; i < n; ++i)
    if (!X.row(i).allFinite()) throw Error("point " + std::to_string(i) + " is not finite");
  Eigen::VectorXd w(n);
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kCageSum))
  for (Index i = 0; i < n; ++i) w[i] = cage_winding_number(C, CF, X.row(i).transpose());
  const double tol = 1e-12 * cage_scale(C);
  for (Index i = 0; i < n; ++i) {
    if (w[i] >= 0.5) continue;
    const Vector3d x = X.row(i).transpose();
    bool on = false;
    for (Index f = 0; f < CF.rows() && !on; ++f) {
      Vector3d b;
      on = closest_on_triangle(x, C.row(CF(f, 0)), C.row(CF(f, 1)), C.row(CF(f, 2)), b) <= tol * tol;
    }
    if (on) continue;
    std::ostringstream s;
    s << "point " << i << " (" << x.transpose() << ") is outside the cage (winding number " << w[i] << ")";
    throw Error(s.str());
  }
}

}  // namespace

void check_cage(const Eigen::MatrixXd& C, const Eigen::MatrixXi& CF) {
  const Index k = C.rows();
  if (C.cols() != 3 || CF.cols() != 3) throw Error("cage: vertices must be k×3 and faces m×3");
  if (k < 4 || CF.rows() < 4) throw Error("cage: a closed cage needs at least 4 vertices and 4 faces");
  for (Index j = 0; j < k; ++j)
    if (!C.row(j).allFinite()) throw Error("cage: vertex " + std::to_string(j) + " is not finite");
  std::map<std::pair<int, int>, std::vector<Index>> directed;
  for (Index f = 0; f < CF.rows(); ++f) {
    for (int c = 0; c < 3; ++c)
      if (CF(f, c) < 0 || CF(f, c) >= k)
        throw Error("cage: face " + std::to_string(f) + " has vertex index " + std::to_string(CF(f, c)) +
                    " out of range [0, " + std::to_string(k) + ")");
    if (CF(f, 0) == CF(f, 1) || CF(f, 1) == CF(f, 2) || CF(f, 0) == CF(f, 2))
      throw Error("cage: face " + std::to_string(f) + " repeats a vertex");
    const Vector3d a = C.row(CF(f, 0)), b = C.row(CF(f, 1)), c = C.row(CF(f, 2));
    if ((b - a).cross(c - a).norm() <= 1e-14 * std::pow(cage_scale(C), 2))
      throw Error("cage: face " + std::to_string(f) + " has zero area");
    for (int c2 = 0; c2 < 3; ++c2) directed[{CF(f, c2), CF(f, (c2 + 1) % 3)}].push_back(f);
  }
  for (const auto& [e, faces] : directed) {
    const std::string edge = "edge (" + std::to_string(e.first) + ", " + std::to_string(e.second) + ")";
    if (faces.size() > 1)
      throw Error("cage: not consistently oriented: " + edge + " has the same direction in faces " +
                  std::to_string(faces[0]) + " and " + std::to_string(faces[1]));
    const auto rev = directed.find({e.second, e.first});
    if (rev == directed.end())
      throw Error("cage: not closed: " + edge + " of face " + std::to_string(faces[0]) +
                  " has no opposite face (a boundary edge, or faces oriented inconsistently)");
  }
  double vol = 0.0;
  for (Index f = 0; f < CF.rows(); ++f)
    vol += Vector3d(C.row(CF(f, 0))).dot(Vector3d(C.row(CF(f, 1))).cross(Vector3d(C.row(CF(f, 2)))));
  if (!(vol > 0.0))
    throw Error("cage: the faces are oriented inwards (signed volume " + std::to_string(vol / 6) + " ≤ 0)");
}

double cage_winding_number(const Eigen::MatrixXd& C, const Eigen::MatrixXi& CF, const Eigen::Vector3d& x) {
  double w = 0.0;
  for (Index f = 0; f < CF.rows(); ++f)
    w += solid_angle(x, C.row(CF(f, 0)), C.row(CF(f, 1)), C.row(CF(f, 2)));
  return w / (4.0 * M_PI);
}

Eigen::MatrixXd mean_value_coordinates(const Eigen::MatrixXd& C, const Eigen::MatrixXi& CF,
                                       const Eigen::MatrixXd& X) {
  check_cage(C, CF);
  const Index n = X.rows(), k = C.rows();
  if (X.cols() != 3) throw Error("mean_value_coordinates: points must be n×3");
  // Dense n×k weights (1M points × 98 cage vertices: 0.8 GB), checked before the O(n k) work.
  require_memory(
      mul_sat(static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(k), sizeof(double)),
      "mean_value_coordinates: " + std::to_string(n) + " × " + std::to_string(k) + " dense weights");
  require_inside(C, CF, X);
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(n, k);
  const double eps = 1e-12 * cage_scale(C);
#pragma omp parallel for schedule(dynamic, 64) if (parallel::worth(n, parallel::kCageSum))
  for (Index i = 0; i < n; ++i) {
    const Vector3d x = X.row(i).transpose();
    Eigen::VectorXd d(k);
    Eigen::MatrixXd u(k, 3);
    bool done = false;
    for (Index j = 0; j < k && !done; ++j) {
      const Vector3d r = C.row(j).transpose() - x;
      d[j] = r.norm();
      if (d[j] < eps) {  // x at a cage vertex
        W(i, j) = 1.0;
        done = true;
      } else {
        u.row(j) = r.transpose() / d[j];
      }
    }
    if (done) continue;
    Eigen::RowVectorXd w = Eigen::RowVectorXd::Zero(k);
    for (Index f = 0; f < CF.rows() && !done; ++f) {
      const int p[3] = {CF(f, 0), CF(f, 1), CF(f, 2)};
      double l[3], th[3], c[3], s[3];
      for (int t = 0; t < 3; ++t) {
        l[t] = (u.row(p[(t + 1) % 3]) - u.row(p[(t + 2) % 3])).norm();
        th[t] = 2.0 * std::asin(std::min(1.0, 0.5 * l[t]));
      }
      const double h = 0.5 * (th[0] + th[1] + th[2]);
      if (M_PI - h < 1e-10) {  // x on the triangle: its 2D barycentric coordinates (Ju et al. Fig. 4)
        w.setZero();
        for (int t = 0; t < 3; ++t) w[p[t]] = std::sin(th[t]) * d[p[(t + 2) % 3]] * d[p[(t + 1) % 3]];
        done = true;
        break;
      }
      Eigen::Matrix3d U;
      U << u.row(p[0]), u.row(p[1]), u.row(p[2]);
      const double sign = U.determinant() < 0 ? -1.0 : 1.0;
      bool coplanar = false;
      for (int t = 0; t < 3; ++t) {
        c[t] = 2.0 * std::sin(h) * std::sin(h - th[t]) /
                   (std::sin(th[(t + 1) % 3]) * std::sin(th[(t + 2) % 3])) -
               1.0;
        s[t] = sign * std::sqrt(std::max(0.0, 1.0 - c[t] * c[t]));
        coplanar = coplanar || std::abs(s[t]) <= 1e-12;
      }
      if (coplanar) continue;  // x in the triangle's plane, outside it: no contribution
      for (int t = 0; t < 3; ++t) {
        const int a = (t + 1) % 3, b = (t + 2) % 3;  // i+1, i−1
        w[p[t]] += (th[t] - c[a] * th[b] - c[b] * th[a]) / (d[p[t]] * std::sin(th[a]) * s[b]);
      }
    }
    W.row(i) = w / w.sum();
  }
  if (!W.allFinite())
    throw numerical_error("mean_value_coordinates: non-finite coordinates (degenerate cage?)");
  return W;
}

double harmonic_interpolation_bound(const Eigen::MatrixXd& C, int grid) {
  return std::sqrt(3.0) * cage_scale(C) / grid;
}

namespace {

/// Estimated peak memory of harmonic_cage_coordinates on a grid of `nodes` nodes of spacing h, before
/// any of it is allocated: the per-node rasterization arrays (distance, face, barycentric coordinates,
/// class, index: 45 bytes), the right-hand sides and solutions (2 m k doubles), the 7-point matrix
/// and its triplets, the Cholesky factor, and the n×k result. The unknowns m are the nodes inside the
/// cage, |volume| / h³. Nested dissection of a 3D grid Laplacian fills the factor with about
/// c m^(4/3) nonzeros (George 1973); c measured (docs/performance.md, "Memory estimates") with the grid
/// nested dissection used below: 3.7-5.0 on balls and 3.9-5.2 on cubes, grids 16-96 (m up to 885k),
/// slowly growing with m; with CHOLMOD's METIS, which ordered it before: 4.1-7.2 and 4.3-7.7.
/// The estimate takes c = 8 up to 10^6 unknowns and grows it as (m / 10^6)^0.12 beyond (the growth
/// between the two largest cubes).
constexpr double kGridFactorFill = 8.0;
std::uint64_t harmonic_grid_memory(const Eigen::MatrixXd& C, const Eigen::MatrixXi& CF, Index nodes, double h,
                                   Index n) {
  double volume = 0;
  for (Index f = 0; f < CF.rows(); ++f)
    volume += Vector3d(C.row(CF(f, 0))).dot(Vector3d(C.row(CF(f, 1))).cross(Vector3d(C.row(CF(f, 2))))) / 6;
  const double m = std::min(static_cast<double>(nodes), std::abs(volume) / (h * h * h));
  const double k = static_cast<double>(C.rows());
  const double bytes =
      45.0 * static_cast<double>(nodes) + 2 * m * k * 8 + 4 * m * (16 + 12) +
      kGridFactorFill * std::max(1.0, std::pow(m / 1e6, 0.12)) * std::pow(m, 4.0 / 3.0) * 16 +
      static_cast<double>(n) * k * 8;
  return bytes >= 0x1p64 ? UINT64_MAX : static_cast<std::uint64_t>(bytes);
}

/// The grid of harmonic_cage_coordinates: N nodes per axis, spacing h, node (0, 0, 0) at `origin`.
struct CageGrid {
  Vector3d origin;
  double h = 0;
  Eigen::Array3i N;
  Index nodes = 0;  ///< N[0] N[1] N[2]
  /// The linear index of node (x, y, z).
  Index id(int x, int y, int z) const { return (static_cast<Index>(x) * N[1] + y) * N[2] + z; }
  /// The position of node (x, y, z).
  Vector3d pos(int x, int y, int z) const { return Vector3d(origin + h * Vector3d(x, y, z)); }
};

/// The six axis neighbours of a node.
constexpr int kGridNeighbours[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

/// A node's class: on the cage (within h/2), outside it, or not yet known (after classify_nodes: inside).
enum : unsigned char { kUnknown, kBoundary, kExterior };

/// The cage's faces rasterized into the grid nodes within √3 h: per node the distance to the closest
/// face (infinite beyond the band), that face (-1 beyond the band) and the barycentric coordinates of
/// the closest point.
struct CageRaster {
  std::vector<double> dist;
  std::vector<int> face;
  std::vector<Vector3d> bary;
};

/// The grid over the bounding box of the cage C, `grid` cells along its longest side plus 2 cells of
/// padding on every side.
CageGrid make_cage_grid(const Eigen::MatrixXd& C, int grid) {
  constexpr int pad = 2;
  CageGrid g;
  const Vector3d lo = C.colwise().minCoeff(), hi = C.colwise().maxCoeff();
  g.h = (hi - lo).maxCoeff() / grid;
  for (int a = 0; a < 3; ++a)
    g.N[a] = static_cast<int>(std::ceil((hi[a] - lo[a]) / g.h - 1e-9)) + 2 * pad + 1;
  g.origin = lo - Vector3d::Constant(pad * g.h);
  g.nodes = static_cast<Index>(g.N[0]) * g.N[1] * g.N[2];
  return g;
}

/// Rasterizes the faces CF of the cage C into the nodes of g within √3 h (closest face wins).
CageRaster rasterize_cage(const CageGrid& g, const Eigen::MatrixXd& C, const Eigen::MatrixXi& CF) {
  const double band = std::sqrt(3.0) * g.h * (1.0 + 1e-9);
  CageRaster r{std::vector<double>(g.nodes, INFINITY), std::vector<int>(g.nodes, -1),
               std::vector<Vector3d>(g.nodes)};
  for (Index f = 0; f < CF.rows(); ++f) {
    const Vector3d a = C.row(CF(f, 0)), b = C.row(CF(f, 1)), c = C.row(CF(f, 2));
    const Vector3d fmin = a.cwiseMin(b).cwiseMin(c) - Vector3d::Constant(band),
                   fmax = a.cwiseMax(b).cwiseMax(c) + Vector3d::Constant(band);
    Eigen::Array3i i0, i1;
    for (int t = 0; t < 3; ++t) {
      i0[t] = std::max(0, static_cast<int>(std::ceil((fmin[t] - g.origin[t]) / g.h)));
      i1[t] = std::min(g.N[t] - 1, static_cast<int>(std::floor((fmax[t] - g.origin[t]) / g.h)));
    }
    for (int x = i0[0]; x <= i1[0]; ++x)
      for (int y = i0[1]; y <= i1[1]; ++y)
        for (int z = i0[2]; z <= i1[2]; ++z) {
          Vector3d bc;
          const double dd = std::sqrt(closest_on_triangle(g.pos(x, y, z), a, b, c, bc));
          const Index v = g.id(x, y, z);
          if (dd <= band && dd < r.dist[v]) {
            r.dist[v] = dd;
            r.face[v] = static_cast<int>(f);
            r.bary[v] = bc;
          }
        }
  }
  return r;
}

/// The class of every node of g from the distances `dist`: boundary (≤ h/2), exterior (flood fill from
/// the border through non-boundary nodes), the rest kUnknown (the interior).
std::vector<unsigned char> classify_nodes(const CageGrid& g, const std::vector<double>& dist) {
  std::vector<unsigned char> cls(g.nodes, kUnknown);
  for (Index v = 0; v < g.nodes; ++v)
    if (dist[v] <= 0.5 * g.h * (1.0 + 1e-6)) cls[v] = kBoundary;
  std::vector<Index> stack;
  auto push = [&](Index v) {
    if (cls[v] == kUnknown) cls[v] = kExterior, stack.push_back(v);
  };
  push(g.id(0, 0, 0));
  const Eigen::Array3i& N = g.N;
  while (!stack.empty()) {
    const Index v = stack.back();
    stack.pop_back();
    const int x = static_cast<int>(v / (static_cast<Index>(N[1]) * N[2])),
              y = static_cast<int>((v / N[2]) % N[1]), z = static_cast<int>(v % N[2]);
    for (const auto& d : kGridNeighbours) {
      const int X2 = x + d[0], Y2 = y + d[1], Z2 = z + d[2];
      if (X2 >= 0 && Y2 >= 0 && Z2 >= 0 && X2 < N[0] && Y2 < N[1] && Z2 < N[2]) push(g.id(X2, Y2, Z2));
    }
  }
  return cls;
}

/// The unknowns of the solve: the interior nodes.
struct GridUnknowns {
  std::vector<Index> row;  ///< per node: its row among the unknowns, -1 for a boundary or exterior node
  Index m = 0;             ///< how many
};

/// Numbers the interior nodes of g (class kUnknown in `cls`) in the grid's nested-dissection order
/// (linalg/geometric_ordering.hpp), so that the factorization takes them as numbered, without a graph
/// partitioner. Throws when no node is inside (`grid` for the message).
GridUnknowns number_unknowns(const CageGrid& g, const std::vector<unsigned char>& cls, int grid) {
  std::vector<std::array<int, 3>> at;
  for (int x = 0; x < g.N[0]; ++x)
    for (int y = 0; y < g.N[1]; ++y)
      for (int z = 0; z < g.N[2]; ++z)
        if (cls[g.id(x, y, z)] == kUnknown) at.push_back({x, y, z});
  const auto m = static_cast<Index>(at.size());
  if (m == 0)
    throw Error("harmonic_cage_coordinates: no grid node inside the cage (grid " + std::to_string(grid) +
                " too coarse)");
  GridUnknowns u{std::vector<Index>(g.nodes, -1), m};
  const std::vector<int> order = grid_nested_dissection(at);
  for (Index r = 0; r < m; ++r) {
    const auto& [x, y, z] = at[static_cast<std::size_t>(order[static_cast<std::size_t>(r)])];
    u.row[g.id(x, y, z)] = r;
  }
  return u;
}

/// Solves the 7-point Laplacian on the interior nodes `u` (rows scaled by h²) with the boundary nodes'
/// values (the barycentric coordinates of their closest cage face CF, for each of the k cage vertices)
/// on the right-hand side. Returns the (u.m)×k interior values; throws when an interior node neighbours an
/// exterior one.
Eigen::MatrixXd solve_interior(const CageGrid& g, const std::vector<unsigned char>& cls,
                               const CageRaster& raster, const GridUnknowns& u, const Eigen::MatrixXi& CF,
                               Index k) {
  const std::vector<Index>& unknown = u.row;
  const Index m = u.m;
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(4 * m);
  Eigen::MatrixXd B(m, k);  // m × (cage vertices): ~95 MB at grid 64, advised before it is zeroed
  advise_huge_pages(B.data(), static_cast<std::size_t>(B.size()) * sizeof(double));
  B.setZero();
  for (int x = 0; x < g.N[0]; ++x)
    for (int y = 0; y < g.N[1]; ++y)
      for (int z = 0; z < g.N[2]; ++z) {
        const Index v = g.id(x, y, z), r = unknown[v];
        if (r < 0) continue;
        t.emplace_back(r, r, 6.0);
        for (const auto& d : kGridNeighbours) {
          const Index w = g.id(x + d[0], y + d[1], z + d[2]);  // never off the grid: the border is exterior
          if (unknown[w] >= 0) {
            if (unknown[w] < r) t.emplace_back(r, unknown[w], -1.0);  // lower triangle
          } else {
            if (cls[w] != kBoundary)
              throw numerical_error("harmonic_cage_coordinates: interior node next to an exterior node");
            for (int c = 0; c < 3; ++c) B(r, CF(raster.face[w], c)) += raster.bary[w][c];
          }
        }
      }
  Eigen::SparseMatrix<double> A(m, m);
  A.setFromTriplets(t.begin(), t.end());
  CholeskySolver solver({.ordering = CholeskySolver::Ordering::Natural});  // numbered in ND order above
  solver.compute(A);
  return solver.solve(B);
}

/// Trilinear interpolation at the points X of the node values: rows of U for the interior nodes `u`, the
/// closest face's barycentric coordinates for the rasterized ones. Returns the n×k coordinates; throws
/// when a point's cell has a node with neither.
Eigen::MatrixXd interpolate_nodes(const CageGrid& g, const Eigen::MatrixXd& X, const GridUnknowns& u,
                                  const CageRaster& raster, const Eigen::MatrixXd& U,
                                  const Eigen::MatrixXi& CF, Index k) {
  const std::vector<Index>& unknown = u.row;
  const Index n = X.rows();
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(n, k);
  bool missing = false;
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend)) \
    reduction(||                                                                         \
              : missing)
  for (Index i = 0; i < n; ++i) {
    const Vector3d s = (X.row(i).transpose() - g.origin) / g.h;
    int c0[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
      c0[a] = std::clamp(static_cast<int>(std::floor(s[a])), 0, g.N[a] - 2);
      f[a] = s[a] - c0[a];
    }
    for (int corner = 0; corner < 8; ++corner) {
      const int ox = corner & 1, oy = (corner >> 1) & 1, oz = (corner >> 2) & 1;
      const double w = (ox ? f[0] : 1 - f[0]) * (oy ? f[1] : 1 - f[1]) * (oz ? f[2] : 1 - f[2]);
      if (w == 0.0) continue;
      const Index v = g.id(c0[0] + ox, c0[1] + oy, c0[2] + oz);
      if (unknown[v] >= 0) {
        W.row(i) += w * U.row(unknown[v]);
      } else if (raster.face[v] >= 0) {
        for (int c = 0; c < 3; ++c) W(i, CF(raster.face[v], c)) += w * raster.bary[v][c];
      } else {
        missing = true;
      }
    }
  }
  if (missing) throw numerical_error("harmonic_cage_coordinates: a point's cell has a node without a value");
  return W;
}

}  // namespace

Eigen::MatrixXd harmonic_cage_coordinates(const Eigen::MatrixXd& C, const Eigen::MatrixXi& CF,
                                          const Eigen::MatrixXd& X, int grid) {
  check_cage(C, CF);
  if (grid < 4 || grid > 512)
    throw Error("harmonic_cage_coordinates: grid " + std::to_string(grid) + " (must be in [4, 512])");
  const Index n = X.rows(), k = C.rows();
  if (X.cols() != 3) throw Error("harmonic_cage_coordinates: points must be n×3");
  require_inside(C, CF, X);
  const CageGrid g = make_cage_grid(C, grid);
  require_memory(
      harmonic_grid_memory(C, CF, g.nodes, g.h, n),
      "harmonic_cage_coordinates: grid " + std::to_string(grid) + " (" + std::to_string(g.nodes) + " nodes)");
  const CageRaster raster = rasterize_cage(g, C, CF);
  const std::vector<unsigned char> cls = classify_nodes(g, raster.dist);
  const GridUnknowns u = number_unknowns(g, cls, grid);
  const Eigen::MatrixXd U = solve_interior(g, cls, raster, u, CF, k);
  return interpolate_nodes(g, X, u, raster, U, CF, k);
}

}  // namespace spinmotor
