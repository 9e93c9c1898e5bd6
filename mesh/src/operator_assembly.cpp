#include "operator_assembly.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "spinmotor/core/parallel.hpp"

namespace spinmotor::detail {

void check_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const char* who) {
  if (V.cols() != 3) {
    std::ostringstream s;
    s << who << ": V must have 3 columns (x, y, z), got " << V.rows() << "x" << V.cols();
    throw Error(s.str());
  }
  if (F.cols() != 3) {
    std::ostringstream s;
    s << who << ": F must have 3 columns (triangles), got " << F.rows() << "x" << F.cols();
    throw Error(s.str());
  }
  const Eigen::Index n = V.rows(), m = F.rows();
  if (n > std::numeric_limits<int>::max() / 2 || m > std::numeric_limits<int>::max() / 3)
    throw Error(std::string(who) + ": mesh too large for 32-bit sparse indices");
  Eigen::Index bad_v = n, bad_f = m;
#pragma omp parallel for schedule(static) reduction(min : bad_v) if (parallel::worth(n, parallel::kAssembly))
  for (Eigen::Index v = 0; v < n; ++v)
    if (!V.row(v).allFinite()) bad_v = std::min(bad_v, v);
#pragma omp parallel for schedule(static) reduction(min : bad_f) if (parallel::worth(m, parallel::kAssembly))
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c)
      if (F(f, c) < 0 || F(f, c) >= n) bad_f = std::min(bad_f, f);
  if (bad_f < m) {
    std::ostringstream s;
    s << who << ": face " << bad_f << " (vertices " << F(bad_f, 0) << ", " << F(bad_f, 1) << ", "
      << F(bad_f, 2) << ") refers to a vertex out of range [0, " << n << ")";
    throw Error(s.str());
  }
  if (bad_v < n) {
    std::ostringstream s;
    s << who << ": vertex " << bad_v << " has a non-finite coordinate (" << V(bad_v, 0) << ", " << V(bad_v, 1)
      << ", " << V(bad_v, 2) << ")";
    throw Error(s.str());
  }
}

void throw_degenerate(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::Index f, const char* who) {
  const FaceFrame fr = face_frame(V, F, f);
  std::ostringstream s;
  s << who << ": face " << f << " (vertices " << F(f, 0) << ", " << F(f, 1) << ", " << F(f, 2)
    << ") is degenerate (area " << 0.5 * fr.dbl_area << ", longest edge "
    << std::sqrt(std::max({fr.l2[0], fr.l2[1], fr.l2[2]}))
    << "): its angles are undefined; remove or collapse it first";
  throw Error(s.str());
}

VertexCorners vertex_corners(const Eigen::MatrixXi& F, Eigen::Index n) {
  VertexCorners vc;
  const Eigen::Index m = F.rows();
  vc.offset = filled_vector(static_cast<size_t>(n) + 1, 0);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) ++vc.offset[F(f, c) + 1];
  for (Eigen::Index v = 0; v < n; ++v) vc.offset[v + 1] += vc.offset[v];
  vc.corner = filled_vector(static_cast<size_t>(3 * m), 0);
  std::vector<int> cursor = filled_vector(static_cast<size_t>(n), 0);
  std::copy(vc.offset.begin(), vc.offset.end() - 1, cursor.begin());
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) vc.corner[cursor[F(f, c)]++] = static_cast<int>(3 * f + c);
  return vc;
}

int sort_and_merge(std::vector<std::pair<int, double>>& buf) {
  const int k = static_cast<int>(buf.size());
  if (k <= 64) {  // insertion sort: one-rings are small
    for (int a = 1; a < k; ++a) {
      const auto x = buf[a];
      int b = a;
      for (; b > 0 && buf[b - 1].first > x.first; --b) buf[b] = buf[b - 1];
      buf[b] = x;
    }
  } else {
    std::stable_sort(buf.begin(), buf.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  }
  int out = 0;
  for (int a = 0; a < k; ++a) {
    if (out > 0 && buf[out - 1].first == buf[a].first)
      buf[out - 1].second += buf[a].second;
    else
      buf[out++] = buf[a];
  }
  return out;
}

}  // namespace spinmotor::detail
