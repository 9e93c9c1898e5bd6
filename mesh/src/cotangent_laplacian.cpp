#include "spinmotor/mesh/cotangent_laplacian.hpp"

#include "operator_assembly.hpp"

namespace spinmotor {

Eigen::SparseMatrix<double> cotangent_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  constexpr const char* who = "cotangent_laplacian";
  detail::check_mesh(V, F, who);
  const Eigen::Index m = F.rows();
  // h(f,c) = ½ cot of the angle at corner c: the weight of the edge opposite c (Meyer et al. 2003, eq. 8).
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> h(m, 3);
  prepare_fresh(h.data(), sizeof(double) * static_cast<std::size_t>(h.size()));  // written whole
  detail::for_each_face(V, F, true, who, [&](Eigen::Index f, const detail::FaceFrame& fr) {
    for (int c = 0; c < 3; ++c) h(f, c) = 0.5 * fr.dot[c] / fr.dbl_area;
  });
  // Element matrix: K(r,c) = −h(opposite corner) for r ≠ c, K(c,c) = h(c+1) + h(c+2).
  return detail::assemble_vertex_operator(F, V.rows(), [&](int f, int r, int c) {
    if (r == c) return h(f, (c + 1) % 3) + h(f, (c + 2) % 3);
    return -h(f, 3 - r - c);
  });
}

}  // namespace spinmotor
