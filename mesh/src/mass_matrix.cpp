#include "spinmotor/mesh/mass_matrix.hpp"

#include "operator_assembly.hpp"

namespace spinmotor {

Eigen::VectorXd vertex_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, MassType type) {
  constexpr const char* who = "mass_matrix";
  detail::check_mesh(V, F, who);
  const Eigen::Index m = F.rows(), n = V.rows();
  // Per-corner areas first (parallel over faces), then a serial scatter (cheap, deterministic).
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> a(m, 3);
  if (type == MassType::Barycentric) {
    detail::for_each_face(V, F, false, who, [&](Eigen::Index f, const detail::FaceFrame& fr) {
      a.row(f).setConstant(fr.dbl_area / 6.0);
    });
  } else {
    // Meyer et al. 2003, Fig. 4 (mixed area) with eq. 7 for the Voronoi part.
    detail::for_each_face(V, F, true, who, [&](Eigen::Index f, const detail::FaceFrame& fr) {
      const double area = 0.5 * fr.dbl_area;
      int obtuse = -1;
      for (int c = 0; c < 3; ++c)
        if (fr.dot[c] < 0) obtuse = c;
      if (obtuse < 0) {
        for (int c = 0; c < 3; ++c) {
          const int cn = (c + 1) % 3, cp = (c + 2) % 3;
          // edge c→c+1 is opposite corner c+2 and vice versa; cot = dot / (2A)
          a(f, c) = (fr.l2[cp] * fr.dot[cp] + fr.l2[cn] * fr.dot[cn]) / (8.0 * fr.dbl_area);
        }
      } else {
        a.row(f).setConstant(0.25 * area);
        a(f, obtuse) = 0.5 * area;
      }
    });
  }
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(n);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) mass[F(f, c)] += a(f, c);
  return mass;
}

Eigen::SparseMatrix<double> mass_matrix(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, MassType type) {
  const Eigen::VectorXd a = vertex_areas(V, F, type);
  const Eigen::Index n = a.size();
  Eigen::SparseMatrix<double> M(n, n);
  M.resizeNonZeros(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    M.outerIndexPtr()[i] = static_cast<int>(i);
    M.innerIndexPtr()[i] = static_cast<int>(i);
    M.valuePtr()[i] = a[i];
  }
  M.outerIndexPtr()[n] = static_cast<int>(n);
  return M;
}

Eigen::VectorXd barycentric_vertex_areas(const Eigen::MatrixXi& F, const Eigen::VectorXd& face_area,
                                         Eigen::Index n) {
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) w[F(f, c)] += face_area[f] / 3.0;
  return w;
}

}  // namespace spinmotor
