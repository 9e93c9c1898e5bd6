#include "spinmotor/spin/dirac_operator.hpp"

#include <sstream>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/spin/quaternion_matrix.hpp"

namespace spinmotor {

namespace {

using Triplet = Eigen::Triplet<double>;

void check_faces(const Eigen::MatrixXi& F, Eigen::Index n, const char* who) {
  if (F.cols() != 3) throw Error(std::string(who) + ": F must have 3 columns");
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (F(f, c) < 0 || F(f, c) >= n) {
        std::ostringstream s;
        s << who << ": face " << f << " has vertex index " << F(f, c) << " outside [0, " << n << ")";
        throw Error(s.str());
      }
}

void push_block(std::vector<Triplet>& t, Eigen::Index r, Eigen::Index c, const Eigen::Matrix4d& X) {
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      if (X(i, j) != 0.0) t.emplace_back(4 * r + i, 4 * c + j, X(i, j));
}

}  // namespace

Eigen::SparseMatrix<double> quaternion_diagonal(const Eigen::VectorXd& d) {
  const Eigen::Index k = d.size();
  Eigen::SparseMatrix<double> M(4 * k, 4 * k);
  M.reserve(Eigen::VectorXi::Ones(4 * k));
  for (Eigen::Index i = 0; i < 4 * k; ++i) M.insert(i, i) = d[i / 4];
  M.makeCompressed();
  return M;
}

Eigen::SparseMatrix<double> dirac_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  check_faces(F, V.rows(), "dirac_operator");
  const Eigen::VectorXd area = face_areas(V, F);
  std::vector<Triplet> t;
  t.reserve(static_cast<std::size_t>(F.rows()) * 3 * 12);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (!(area[f] > 0)) {
      std::ostringstream s;
      s << "dirac_operator: face " << f << " is degenerate (area " << area[f] << ")";
      throw Error(s.str());
    }
    for (int c = 0; c < 3; ++c) {
      // eq. 5: D_fj = −e_j / (2A), e_j = x(c+2) − x(c+1) (counter-clockwise, opposite corner c)
      const Eigen::Vector3d e = V.row(F(f, (c + 2) % 3)) - V.row(F(f, (c + 1) % 3));
      push_block(t, f, F(f, c), quaternion_block(ga::imaginary(-e / (2.0 * area[f]))));
    }
  }
  Eigen::SparseMatrix<double> D(4 * F.rows(), 4 * V.rows());
  D.setFromTriplets(t.begin(), t.end());
  return D;
}

Eigen::SparseMatrix<double> face_vertex_average(const Eigen::MatrixXi& F, Eigen::Index n) {
  return curvature_change_operator(F, n, Eigen::VectorXd::Ones(F.rows()));
}

Eigen::SparseMatrix<double> curvature_change_operator(const Eigen::MatrixXi& F, Eigen::Index n,
                                                      const Eigen::VectorXd& rho) {
  check_faces(F, n, "curvature_change_operator");
  if (rho.size() != F.rows()) {
    std::ostringstream s;
    s << "curvature_change_operator: rho has " << rho.size() << " values for " << F.rows() << " faces";
    throw Error(s.str());
  }
  std::vector<Triplet> t;
  t.reserve(static_cast<std::size_t>(F.rows()) * 12);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 4; ++k)
        t.emplace_back(4 * f + k, 4 * F(f, c) + k, rho[f] / 3.0);  // (PB)_fj = ρ_f/3
  Eigen::SparseMatrix<double> R(4 * F.rows(), 4 * n);
  R.setFromTriplets(t.begin(), t.end());
  return R;
}

Eigen::SparseMatrix<double> dirac_minus_rho(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                            const Eigen::VectorXd& rho) {
  Eigen::SparseMatrix<double> A = dirac_operator(V, F) - curvature_change_operator(F, V.rows(), rho);
  A.prune(0.0);
  return A;
}

Eigen::SparseMatrix<double> dirac_adjoint(const Eigen::SparseMatrix<double>& X,
                                          const Eigen::VectorXd& face_areas) {
  if (X.rows() != 4 * face_areas.size()) {
    std::ostringstream s;
    s << "dirac_adjoint: X has " << X.rows() << " rows, expected 4 × " << face_areas.size() << " faces";
    throw Error(s.str());
  }
  Eigen::SparseMatrix<double> Xt = X.transpose();
  return Xt * quaternion_diagonal(face_areas);
}

}  // namespace spinmotor
