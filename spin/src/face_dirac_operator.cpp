#include "spinmotor/spin/face_dirac_operator.hpp"

#include <cmath>
#include <sstream>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/ga/quaternion.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/spin/quaternion_matrix.hpp"

namespace spinmotor {

namespace {

// Hamilton product of (w, x, y, z) quaternions.
Eigen::Vector4d qmul(const Eigen::Vector4d& p, const Eigen::Vector4d& q) {
  return {p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],  //
          p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],  //
          p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],  //
          p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0]};
}
Eigen::Vector4d qconj(const Eigen::Vector4d& q) { return {q[0], -q[1], -q[2], -q[3]}; }

void add_block(std::vector<Eigen::Triplet<double>>& t, Eigen::Index r, Eigen::Index c,
               const Eigen::Matrix4d& B) {
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      if (B(a, b) != 0.0) t.emplace_back(4 * r + a, 4 * c + b, B(a, b));
}

}  // namespace

Eigen::SparseMatrix<double> face_dirac_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                FaceDiracKind kind) {
  return face_dirac_operator(V, F, edge_constraint_net(V, F), kind);
}

Eigen::SparseMatrix<double> face_dirac_operator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                const EdgeConstraintNet& net, FaceDiracKind kind) {
  const Eigen::Index m = F.rows();
  if (net.adjacent.rows() != m) throw Error("face_dirac_operator: the net was built for a different mesh");
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(m) * (kind == FaceDiracKind::Extrinsic ? 52 : 48));
  for (Eigen::Index f = 0; f < m; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int g = net.adjacent(f, c);
      if (g < 0) continue;
      Eigen::Vector4d E = 0.5 * net.hyperedge(V, F, f, c);
      if (kind == FaceDiracKind::Intrinsic) E *= std::cos(0.5 * net.theta(f, c));  // eq. 19
      add_block(t, f, g, quaternion_block(ga::Quat(E[0], E[1], E[2], E[3])));      // eq. 13 / 19
    }
    if (kind == FaceDiracKind::Extrinsic)
      for (int a = 0; a < 4; ++a) t.emplace_back(4 * f + a, 4 * f + a, -net.H[f]);  // eq. 13: −H_i φ_i
  }
  Eigen::SparseMatrix<double> D(4 * m, 4 * m);
  D.setFromTriplets(t.begin(), t.end());
  return D;
}

Eigen::SparseMatrix<double> face_vertex_averaging(const Eigen::MatrixXi& F, Eigen::Index n) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(F.rows()) * 12);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      if (F(f, c) < 0 || F(f, c) >= n) {
        std::ostringstream s;
        s << "face_vertex_averaging: face " << f << " has vertex index " << F(f, c) << " outside [0, " << n
          << ")";
        throw Error(s.str());
      }
      for (int a = 0; a < 4; ++a) t.emplace_back(4 * f + a, 4 * F(f, c) + a, 1.0 / 3.0);
    }
  Eigen::SparseMatrix<double> A(4 * F.rows(), 4 * n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

Eigen::MatrixXd face_spin_transform(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                    const Eigen::MatrixXd& phi, FaceDiracKind kind, double* residual) {
  const EdgeConstraintNet net = edge_constraint_net(V, F);
  const Eigen::Index n = V.rows(), m = F.rows();
  if (phi.rows() != m || phi.cols() != 4) {
    std::ostringstream s;
    s << "face_spin_transform: phi is " << phi.rows() << "x" << phi.cols() << ", expected " << m << "x4";
    throw Error(s.str());
  }
  for (Eigen::Index f = 0; f < m; ++f)
    if (!phi.row(f).allFinite() || !(phi.row(f).norm() > 1e-300)) {
      std::ostringstream s;
      s << "face_spin_transform: phi of face " << f << " is "
        << (phi.row(f).allFinite() ? "zero" : "not finite");
      throw Error(s.str());
    }
  // One equation per undirected edge: from the face that traverses it (the lower face index when shared).
  std::vector<Eigen::Triplet<double>> bt;
  std::vector<Eigen::Vector3d> rhs;
  bt.reserve(static_cast<std::size_t>(m) * 3);
  rhs.reserve(static_cast<std::size_t>(m) * 3 / 2 + 8);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) {
      const int g = net.adjacent(f, c);
      if (g >= 0 && g < f) continue;
      const Eigen::Vector4d pf = phi.row(f).transpose();
      const Eigen::Vector4d pg = g >= 0 ? Eigen::Vector4d(phi.row(g).transpose()) : pf;
      Eigen::Vector4d Et = qmul(qconj(pf), qmul(net.hyperedge(V, F, f, c), pg));    // eq. 15
      if (kind == FaceDiracKind::Intrinsic) Et *= std::cos(0.5 * net.theta(f, c));  // eq. 21
      const Eigen::Index r = static_cast<Eigen::Index>(rhs.size());
      bt.emplace_back(r, F(f, (c + 2) % 3), 1.0);
      bt.emplace_back(r, F(f, (c + 1) % 3), -1.0);
      rhs.push_back(Et.tail<3>());
    }
  const Eigen::Index k = static_cast<Eigen::Index>(rhs.size());
  Eigen::SparseMatrix<double> B(k, n);
  B.setFromTriplets(bt.begin(), bt.end());
  Eigen::MatrixXd e(k, 3);
  for (Eigen::Index r = 0; r < k; ++r) e.row(r) = rhs[static_cast<std::size_t>(r)].transpose();
  // §4.3: least squares with vertex 0 pinned (the graph Laplacian BᵀB minus its first row and column).
  const Eigen::SparseMatrix<double> Lf = B.transpose() * B;
  const Eigen::SparseMatrix<double> L = Lf.bottomRightCorner(n - 1, n - 1);
  CholeskySolver solver;
  solver.analyze(L);
  solver.factorize(L);
  const Eigen::MatrixXd rhs_v = (B.transpose() * e).bottomRows(n - 1);
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n, 3);
  X.bottomRows(n - 1) = solver.solve(rhs_v);
  if (residual) {
    const double en = std::sqrt(e.squaredNorm() / static_cast<double>(k));
    *residual = std::sqrt((B * X - e).squaredNorm() / static_cast<double>(k)) / en;
  }
  X.rowwise() += V.colwise().mean() - X.colwise().mean();
  if (!X.allFinite()) throw numerical_error("face_spin_transform: the recovered positions are not finite");
  return X;
}

}  // namespace spinmotor
