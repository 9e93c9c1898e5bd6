#include "spinmotor/mesh/metrics/willmore.hpp"

#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/mass_matrix.hpp"
#include "spinmotor/mesh/topology.hpp"

namespace spinmotor {

Eigen::VectorXd willmore_density(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(V, F);  // validates V and F
  const Eigen::VectorXd A = vertex_areas(V, F, MassType::Voronoi);
  // W = ∫ H² dA (Crane et al. 2011, §7.3); (L V)_i ≈ 2 H_i N_i A_i (Meyer et al. 2003, eq. 8)
  const Eigen::MatrixXd LV = L * V;
  Eigen::VectorXd w = Eigen::VectorXd::Zero(V.rows());
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (A[i] > 0) w[i] = LV.row(i).squaredNorm() / (4.0 * A[i]);  // H_i² A_i
  const Eigen::VectorXi boundary = boundary_vertices(F, V.rows());
  for (Eigen::Index k = 0; k < boundary.size(); ++k) w[boundary[k]] = 0.0;  // H is undefined there
  return w;
}

double willmore_energy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  return willmore_density(V, F).sum();
}

}  // namespace spinmotor
