#include "spinmotor/deform/harmonic_field.hpp"

#include <string>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/linalg/dirichlet_solver.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/mean_value_laplacian.hpp"

namespace spinmotor {

const char* to_string(HarmonicWeights w) { return w == HarmonicWeights::MeanValue ? "mean-value" : "cotan"; }

namespace {

/// Solves L X = 0 with X(constrained(r), :) = values(r, :): one factorization for all columns. With
/// `unity_last`, every row of `values` sums to 1 and the last column is not solved for: it is
/// 1 − Σ of the others (header: L·1 = 0 and the solution is unique, so the columns sum to 1).
Eigen::MatrixXd solve_dirichlet(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                const Eigen::VectorXi& constrained, const Eigen::MatrixXd& values,
                                HarmonicWeights weights, const char* who, bool unity_last = false) {
  // Row i of either Laplacian is the equation of vertex i (eq. 14 times Σ_j w_ij).
  const bool mv = weights == HarmonicWeights::MeanValue;
  const Eigen::SparseMatrix<double> L = mv ? mean_value_laplacian(V, F) : cotangent_laplacian(V, F);
  // Column ordering of the LU: the mean-value Laplacian has a symmetric pattern, and minimum degree on
  // Aᵀ + A gave half the factorization time of COLAMD on tubes of 10k–100k vertices (bench_deform);
  // CHOLMOD keeps its default (supernodal, AMD).
  DirichletSolver::Options options;
  options.lu.ordering = LUSolver::Ordering::MMD_AtPlusA;
  DirichletSolver solver(options);
  try {
    solver.bind(L, constrained, mv ? DirichletSolver::Kind::LU : DirichletSolver::Kind::SPD);
  } catch (const Error& e) {
    // DirichletSolver names the component in the matrix graph, which is the mesh's vertex graph.
    throw Error(std::string(who) + " (" + to_string(weights) + " weights): " + e.what(), e.kind());
  }
  if (!unity_last) return solver.solve(values);
  const Eigen::Index k = values.cols();
  Eigen::MatrixXd X(V.rows(), k);
  X.leftCols(k - 1) = solver.solve(values.leftCols(k - 1));
  X.col(k - 1).setOnes();
  X.col(k - 1) -= X.leftCols(k - 1).rowwise().sum();
  // Constrained values stay exact (the header's promise): 1 − Σ of exact 0s and one 1 is exact.
  return X;
}

}  // namespace

Eigen::MatrixXd harmonic_coordinates(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                     std::span<const Handle> handles, HarmonicWeights weights) {
  const char* who = "harmonic_coordinates";
  if (handles.empty()) throw Error(std::string(who) + ": needs at least one handle");
  check_handles(handles, V.rows(), who);
  Eigen::Index c = 0;
  for (const Handle& h : handles) c += h.vertices.size();
  Eigen::VectorXi constrained(c);
  Eigen::MatrixXd values = Eigen::MatrixXd::Zero(c, static_cast<Eigen::Index>(handles.size()));
  Eigen::Index r = 0;
  for (std::size_t j = 0; j < handles.size(); ++j)
    for (Eigen::Index k = 0; k < handles[j].vertices.size(); ++k, ++r) {
      constrained[r] = handles[j].vertices[k];
      values(r, static_cast<Eigen::Index>(j)) = 1.0;  // §IV: 1 on H_j, 0 on every other handle
    }
  // Each constrained row holds one 1: the fields sum to 1 and the last one costs no solve (a third
  // less solve time for 3 handles, half for 2; bench_deform BM_bind, docs/performance.md).
  return solve_dirichlet(V, F, constrained, values, weights, who, /*unity_last=*/true);
}

Eigen::VectorXd harmonic_field(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Handle& zero,
                               const Handle& one, HarmonicWeights weights) {
  const char* who = "harmonic_field";
  const Handle sets[2] = {zero, one};
  check_handles(sets, V.rows(), who);
  const Eigen::Index nz = zero.vertices.size(), no = one.vertices.size();
  Eigen::VectorXi constrained(nz + no);
  constrained << zero.vertices, one.vertices;
  Eigen::MatrixXd values(nz + no, 1);
  values.topRows(nz).setZero();  // §VIII: fixed sets → 0, handle sets → 1
  values.bottomRows(no).setOnes();
  return solve_dirichlet(V, F, constrained, values, weights, who).col(0);
}

}  // namespace spinmotor
