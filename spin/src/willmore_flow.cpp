#include "spinmotor/spin/willmore_flow.hpp"

#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <chrono>
#include <cmath>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/mass_matrix.hpp"
#include "spinmotor/mesh/metrics/willmore.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/spin/curvature_change.hpp"

namespace spinmotor {

Eigen::VectorXd vertex_mean_curvature(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  const Eigen::Index n = V.rows();
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(V, F);  // validates F and V
  const Eigen::VectorXd A = vertex_areas(V, F, MassType::Voronoi);
  const Eigen::MatrixXd LV = L * V;  // ≈ 2 H N A (cotangent_laplacian.hpp)
  // Area-weighted vertex normals: the unnormalised face normal is 2·area·n_f.
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(n, 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector3d a = V.row(F(f, 1)) - V.row(F(f, 0));
    const Eigen::RowVector3d b = V.row(F(f, 2)) - V.row(F(f, 0));
    const Eigen::RowVector3d c = a.cross(b);
    for (int k = 0; k < 3; ++k) N.row(F(f, k)) += c;
  }
  Eigen::VectorXd H = Eigen::VectorXd::Zero(n);
  std::vector<char> boundary(n, 0);
  for (Eigen::Index i : boundary_vertices(F, n)) boundary[i] = 1;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double nn = N.row(i).norm();
    if (boundary[i] || !(A[i] > 0) || !(nn > 0)) continue;
    H[i] = LV.row(i).dot(N.row(i)) / (2.0 * A[i] * nn);  // HN = Δf (§7.3), signed
  }
  // Boundary vertices: mean over interior neighbours (edges of the faces around them).
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(n);
  Eigen::VectorXi count = Eigen::VectorXi::Zero(n);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int i = F(f, k);
      if (!boundary[i]) continue;
      for (int l = 1; l < 3; ++l) {
        const int j = F(f, (k + l) % 3);
        if (boundary[j]) continue;
        sum[i] += H[j];  // an interior edge is shared by two faces: each neighbour is counted twice
        ++count[i];
      }
    }
  for (Eigen::Index i = 0; i < n; ++i)
    if (boundary[i] && count[i] > 0) H[i] = sum[i] / count[i];
  return H;
}

Eigen::VectorXd face_mean_curvature(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  return face_rho_from_vertices(F, vertex_mean_curvature(V, F));
}

SpinTransformResult willmore_flow_step(const Mesh& mesh, double tau, const SpinTransformOptions& options) {
  if (!std::isfinite(tau)) throw Error("willmore_flow: step tau = " + std::to_string(tau) + " is not finite");
  SpinTransform st(mesh, options);  // validates the mesh before H is computed on it
  const Eigen::VectorXd rho = -tau * face_mean_curvature(mesh.V, mesh.F);  // §7.3: ρ = −τ H
  if (!rho.allFinite()) throw numerical_error("willmore_flow: mean curvature is not finite");
  SpinTransformResult r = st.solve(rho);
  if (!r.V.allFinite()) throw numerical_error("willmore_flow: the spin transformation is not finite");
  return r;
}

WillmoreFlowResult willmore_flow(const Mesh& mesh, const WillmoreFlowOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  if (!std::isfinite(options.tau))
    throw Error("willmore_flow: step tau = " + std::to_string(options.tau) + " is not finite");
  if (options.steps < 1)
    throw Error("willmore_flow: steps = " + std::to_string(options.steps) + " must be >= 1");
  const auto start = Clock::now();
  WillmoreFlowResult res;
  res.willmore.resize(options.steps + 1);
  res.step_ms.resize(options.steps);
  Mesh cur = mesh;
  res.willmore[0] = willmore_energy(cur.V, cur.F);
  if (options.keep_positions) res.positions.push_back(cur.V);
  for (int s = 1; s <= options.steps; ++s) {
    const auto t0 = Clock::now();
    const std::string where =
        "willmore_flow: step " + std::to_string(s) + " of " + std::to_string(options.steps);
    try {
      cur.V = willmore_flow_step(cur, options.tau, options.spin).V;
    } catch (const Error& e) {
      // The first step's bad input (a bad mesh) stays bad input; later failures are numerical.
      if (s == 1 && e.kind() == Error::Kind::BadInput) throw;
      throw numerical_error(where + ": " + e.what());
    }
    const double W = willmore_energy(cur.V, cur.F);
    if (!std::isfinite(W)) throw numerical_error(where + ": the Willmore energy is not finite");
    res.willmore[s] = W;
    if (options.keep_positions) res.positions.push_back(cur.V);
    const auto t1 = Clock::now();
    res.step_ms[s - 1] = ms(t0, t1);
    if (options.progress) options.progress({s, options.steps, W, ms(t0, t1), ms(start, t1)});
  }
  res.V = std::move(cur.V);
  return res;
}

}  // namespace spinmotor
