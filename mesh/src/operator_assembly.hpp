#pragma once
// Internal to spinmotor_mesh (not installed): input checks and the parallel assembly of n×n vertex
// operators from per-face 3×3 element matrices, shared by the operator sources.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <Eigen/SparseCore>
#include <algorithm>
#include <limits>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/huge_pages.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/mesh/face_geometry.hpp"  // kDegenerateFace

namespace spinmotor::detail {

/// Throws Error (prefixed with `who`) unless V is n×3 and finite and F is m×3 with indices in [0, n).
void check_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const char* who);

/// The error thrown for degenerate face f.
[[noreturn]] void throw_degenerate(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::Index f,
                                   const char* who);

/// Per-face quantities every operator needs, computed once in parallel.
/// e(c) = x_{c+2} − x_{c+1} (edge opposite corner c, counter-clockwise), dot(c) = −e(c+1)·e(c+2)
/// (= a·b of the edges leaving corner c), l2(c) = |e(c)|², dbl_area = |e(1)×e(2)|.
struct FaceFrame {
  Eigen::Vector3d e[3];
  double dot[3];
  double l2[3];
  double dbl_area;
  Eigen::Vector3d cross;  ///< e(2)×(−e(1)) = (x1−x0)×(x2−x0), length dbl_area
  bool degenerate() const {
    const double lmax = std::max({l2[0], l2[1], l2[2]});
    return !(dbl_area > kDegenerateFace * lmax);
  }
};

inline FaceFrame face_frame(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::Index f) {
  FaceFrame r;
  const Eigen::Vector3d x0 = V.row(F(f, 0)).transpose(), x1 = V.row(F(f, 1)).transpose(),
                        x2 = V.row(F(f, 2)).transpose();
  r.e[0] = x2 - x1;
  r.e[1] = x0 - x2;
  r.e[2] = x1 - x0;
  for (int c = 0; c < 3; ++c) {
    r.dot[c] = -r.e[(c + 1) % 3].dot(r.e[(c + 2) % 3]);
    r.l2[c] = r.e[c].squaredNorm();
  }
  r.cross = r.e[2].cross(-r.e[1]);
  r.dbl_area = r.cross.norm();
  return r;
}

/// Computes per-face data in parallel with `fill(f, frame)`; throws the degenerate-face error for the
/// smallest degenerate face index (deterministic) when `need_nondegenerate`.
template <class Fill>
void for_each_face(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, bool need_nondegenerate,
                   const char* who, Fill&& fill) {
  const Eigen::Index m = F.rows();
  Eigen::Index bad = m;
#pragma omp parallel for schedule(static) reduction(min : bad) if (parallel::worth(m, parallel::kAssembly))
  for (Eigen::Index f = 0; f < m; ++f) {
    const FaceFrame fr = face_frame(V, F, f);
    if (need_nondegenerate && fr.degenerate()) {
      bad = std::min(bad, f);
      continue;
    }
    fill(f, fr);
  }
  if (bad < m) throw_degenerate(V, F, bad, who);
}

/// std::vector<T>(n, value), its pages faulted in by one system call first (core/huge_pages.hpp): the
/// n-sized scratch arrays of the assembly are fresh memory on every call.
template <class T>
std::vector<T> filled_vector(std::size_t n, T value) {
  std::vector<T> v;
  v.reserve(n);
  populate_pages(v.data(), n * sizeof(T));
  v.assign(n, value);
  return v;
}

/// Corners incident to each vertex (CSR): corner[offset[v] .. offset[v+1]) holds 3f+c with F(f,c) = v,
/// in increasing face order.
struct VertexCorners {
  std::vector<int> offset;
  std::vector<int> corner;
};
VertexCorners vertex_corners(const Eigen::MatrixXi& F, Eigen::Index n);

/// Sorts (row, value) pairs by row, stably, then merges duplicate rows in place (summing in order:
/// deterministic). Returns the number of unique rows.
int sort_and_merge(std::vector<std::pair<int, double>>& buf);

/// Assembles the n×n column-major matrix Σ_f P_fᵀ K_f P_f, with K_f the 3×3 element matrix of face f
/// given by entry(f, r, c) = K_f(r, c) (r, c corners). Column j gathers its entries from the corners
/// of j (parallel over columns, no triplets, no atomics, sums in a fixed order whatever the thread
/// count), rows sorted and unique; the diagonal is always stored. Requires every face to have three
/// distinct vertices.
template <class Entry>
Eigen::SparseMatrix<double> assemble_vertex_operator(const Eigen::MatrixXi& F, Eigen::Index n,
                                                     Entry&& entry) {
  const VertexCorners vc = vertex_corners(F, n);
  Eigen::SparseMatrix<double> A(n, n);
  std::vector<int> col_nnz = filled_vector(static_cast<size_t>(n), 0);
  // Pass 1: number of distinct rows per column (the diagonal plus the distinct one-ring neighbours),
  // deduplicated with a per-thread slot array (slot[row] ≥ 0 while row is in the current column).
#pragma omp parallel if (parallel::worth(n, parallel::kAssembly))
  {
    std::vector<int> slot = filled_vector(static_cast<size_t>(n), -1), rows;
#pragma omp for schedule(static)
    for (Eigen::Index j = 0; j < n; ++j) {
      rows.assign(1, static_cast<int>(j));
      slot[j] = 0;
      for (int k = vc.offset[j]; k < vc.offset[j + 1]; ++k) {
        const int f = vc.corner[k] / 3, c = vc.corner[k] % 3;
        for (int d = 1; d < 3; ++d) {
          const int r = F(f, (c + d) % 3);
          if (slot[r] < 0) slot[r] = static_cast<int>(rows.size()), rows.push_back(r);
        }
      }
      col_nnz[j] = static_cast<int>(rows.size());
      for (int r : rows) slot[r] = -1;
    }
  }
  int* outer = A.outerIndexPtr();
  outer[0] = 0;
  for (Eigen::Index j = 0; j < n; ++j) outer[j + 1] = outer[j] + col_nnz[j];
  A.resizeNonZeros(outer[n]);
  int* inner = A.innerIndexPtr();
  double* value = A.valuePtr();
  prepare_fresh(inner, sizeof(int) * static_cast<std::size_t>(outer[n]));  // written whole below
  prepare_fresh(value, sizeof(double) * static_cast<std::size_t>(outer[n]));
  // Pass 2: accumulate each column's entries in gather order (deterministic sums), then sort the few
  // distinct rows and write them.
#pragma omp parallel if (parallel::worth(n, parallel::kAssembly))
  {
    std::vector<int> slot = filled_vector(static_cast<size_t>(n), -1);
    std::vector<std::pair<int, double>> buf;
#pragma omp for schedule(static)
    for (Eigen::Index j = 0; j < n; ++j) {
      buf.assign(1, {static_cast<int>(j), 0.0});
      slot[j] = 0;
      for (int k = vc.offset[j]; k < vc.offset[j + 1]; ++k) {
        const int f = vc.corner[k] / 3, c = vc.corner[k] % 3;
        for (int d = 0; d < 3; ++d) {
          const int r = (c + d) % 3, row = F(f, r);
          if (slot[row] < 0) slot[row] = static_cast<int>(buf.size()), buf.emplace_back(row, 0.0);
          buf[slot[row]].second += entry(f, r, c);
        }
      }
      for (const auto& e : buf) slot[e.first] = -1;
      const int cnt = sort_and_merge(buf);
      int pos = outer[j];
      for (int k = 0; k < cnt; ++k, ++pos) {
        inner[pos] = buf[k].first;
        value[pos] = buf[k].second;
      }
    }
  }
  return A;
}

}  // namespace spinmotor::detail
