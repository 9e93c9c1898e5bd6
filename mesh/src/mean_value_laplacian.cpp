#include "spinmotor/mesh/mean_value_laplacian.hpp"

#include <cmath>

#include "operator_assembly.hpp"

namespace spinmotor {

Eigen::SparseMatrix<double> mean_value_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  constexpr const char* who = "mean_value_laplacian";
  detail::check_mesh(V, F, who);
  const Eigen::Index m = F.rows();
  // w(f, c) = contribution of face f to the weight from corner c to corner c+1 (column c) and to
  // corner c+2 (column 3+c): tan(θ_c/2) / |edge|, Floater 2003. tan(θ/2) = |a×b| / (|a||b| + a·b).
  Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> w(m, 6);
  detail::for_each_face(V, F, true, who, [&](Eigen::Index f, const detail::FaceFrame& fr) {
    double l[3];
    for (int c = 0; c < 3; ++c) l[c] = std::sqrt(fr.l2[c]);
    for (int c = 0; c < 3; ++c) {
      const double ln = l[(c + 2) % 3], lp = l[(c + 1) % 3];  // |x_{c+1} − x_c|, |x_{c+2} − x_c|
      const double t = fr.dbl_area / (ln * lp + fr.dot[c]);
      w(f, c) = t / ln;
      w(f, 3 + c) = t / lp;
    }
  });
  // Row r of the element matrix belongs to corner r: K(r, r+1) = −w(r→r+1), K(r, r+2) = −w(r→r+2),
  // K(r, r) = w(r→r+1) + w(r→r+2).
  return detail::assemble_vertex_operator(F, V.rows(), [&](int f, int r, int c) {
    if (r == c) return w(f, c) + w(f, 3 + c);
    return (c == (r + 1) % 3) ? -w(f, r) : -w(f, 3 + r);
  });
}

}  // namespace spinmotor
