#include "spinmotor/mesh/gradient.hpp"

#include <algorithm>

#include "operator_assembly.hpp"

namespace spinmotor {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Row-major 3m×n gradient, each row scaled by `area_weight ? A_f : 1`. Row 3f+k holds the k-th
// coordinate of ∇φ for the three corners of f, columns sorted.
RowSparse gradient_rows(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, bool area_weight,
                        const char* who) {
  detail::check_mesh(V, F, who);
  const Eigen::Index m = F.rows(), n = V.rows();
  RowSparse G(3 * m, n);
  G.resizeNonZeros(9 * m);
  int* outer = G.outerIndexPtr();
  int* inner = G.innerIndexPtr();
  double* value = G.valuePtr();
  for (Eigen::Index r = 0; r <= 3 * m; ++r) outer[r] = static_cast<int>(3 * r);
  detail::for_each_face(V, F, true, who, [&](Eigen::Index f, const detail::FaceFrame& fr) {
    const Eigen::Vector3d N = fr.cross / fr.dbl_area;
    const double s = (area_weight ? 0.5 * fr.dbl_area : 1.0) / fr.dbl_area;
    int order[3] = {0, 1, 2};  // corners by increasing vertex index (sorted inner indices)
    std::sort(order, order + 3, [&](int a, int b) { return F(f, a) < F(f, b); });
    Eigen::Vector3d g[3];
    for (int c = 0; c < 3; ++c) g[c] = s * N.cross(fr.e[c]);  // ∇φ_c = N × e_c / (2A)
    for (int k = 0; k < 3; ++k)
      for (int t = 0; t < 3; ++t) {
        const Eigen::Index pos = 9 * f + 3 * k + t;
        inner[pos] = F(f, order[t]);
        value[pos] = g[order[t]][k];
      }
  });
  return G;
}

}  // namespace

Eigen::SparseMatrix<double> gradient(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  return Eigen::SparseMatrix<double>(gradient_rows(V, F, false, "gradient"));
}

Eigen::SparseMatrix<double> divergence(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  RowSparse AG = gradient_rows(V, F, true, "divergence");
  AG *= -1.0;
  // The row-major storage of the 3m×n matrix −diag(A)G is the column-major storage of its n×3m
  // transpose D: no transposition needed.
  return Eigen::SparseMatrix<double>(Eigen::Map<const Eigen::SparseMatrix<double>>(
      AG.cols(), AG.rows(), AG.nonZeros(), AG.outerIndexPtr(), AG.innerIndexPtr(), AG.valuePtr()));
}

}  // namespace spinmotor
