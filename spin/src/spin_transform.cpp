#include "spinmotor/spin/spin_transform.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <sstream>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/interrupt.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/ga/quaternion.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/linalg/smallest_eigenpair.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/spin/quaternion_matrix.hpp"

namespace spinmotor {

namespace {

using Clock = std::chrono::steady_clock;

// Adds sigma to the diagonal (the first stored entry of each column of a lower triangle); returns the
// mean diagonal before the shift.
template <class Scalar>
double mean_diagonal(const Eigen::SparseMatrix<Scalar>& K) {
  double sum = 0;
  for (Eigen::Index j = 0; j < K.cols(); ++j) sum += std::real(K.valuePtr()[K.outerIndexPtr()[j]]);
  return sum / static_cast<double>(K.cols());
}
// Whether every stored value is finite (an extreme ρ overflows the ρ² terms of the eigen matrix).
template <class Scalar>
bool values_finite(const Eigen::SparseMatrix<Scalar>& K) {
  for (Eigen::Index k = 0; k < K.nonZeros(); ++k)
    if (!std::isfinite(std::abs(K.valuePtr()[k]))) return false;
  return true;
}
template <class Scalar>
void shift_diagonal(Eigen::SparseMatrix<Scalar>& K, double sigma) {
  for (Eigen::Index j = 0; j < K.cols(); ++j) K.valuePtr()[K.outerIndexPtr()[j]] += sigma;
}

}  // namespace

Eigen::MatrixXd transformed_edges(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E,
                                  const Eigen::MatrixXd& lambda) {
  if (lambda.rows() != V.rows() || lambda.cols() != 4) throw Error("transformed_edges: lambda must be n x 4");
  Eigen::MatrixXd out(E.rows(), 3);
#pragma omp parallel for schedule(static) if (parallel::worth(E.rows(), parallel::kAssembly))
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const int a = E(e, 0), b = E(e, 1);
    const ga::Quat li(lambda(a, 0), lambda(a, 1), lambda(a, 2), lambda(a, 3));
    const ga::Quat lj(lambda(b, 0), lambda(b, 1), lambda(b, 2), lambda(b, 3));
    const ga::Quat ed = ga::imaginary((V.row(b) - V.row(a)).transpose());
    const ga::Quat ci = ga::conj(li), cj = ga::conj(lj);
    // eq. 8: ẽ = ⅓ λ̄_i e λ_i + ⅙ λ̄_i e λ_j + ⅙ λ̄_j e λ_i + ⅓ λ̄_j e λ_j
    const ga::Quat ei = ci * ed, ej = cj * ed;
    const ga::Quat t =
        (1.0 / 3.0) * (ei * li) + (1.0 / 6.0) * (ei * lj) + (1.0 / 6.0) * (ej * li) + (1.0 / 3.0) * (ej * lj);
    out.row(e) = t.vec().transpose();
  }
  return out;
}

struct SpinTransform::Impl {
  SpinTransformOptions opt;
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  double area0 = 0;
  Eigen::RowVector3d mean0;
  std::unique_ptr<DiracAssembly> as;
  Eigen::VectorXd scale;  // s_i (Standard) or empty
  double scale_c = 1.0;   // s_i = scale_c / sqrt(M_i)
  bool complex = false;   // complex Hermitian form (no reductions)
  Eigen::SparseMatrix<double> K, G;
  Eigen::SparseMatrix<std::complex<double>> Kc, Gc;
  CholeskySolver chol;
  ComplexCholeskySolver cchol;
  Eigen::VectorXd start;  // normalised all-ones start vector (unknowns)
  Eigen::VectorXcd cstart;
  // Poisson (§5.6), prepared on a second thread during bind (it does not depend on ρ) and awaited by
  // the first solve: on two cores it overlaps the eigen matrix's factorization.
  Eigen::MatrixXi E;
  Eigen::VectorXd w;       // cotangent weight per edge (−L_ij)
  CholeskySolver poisson;  // L in the assembly's vertex order, last vertex (in that order) removed
  double poisson_factor_ms = 0;
  double bind_ms = 0;
  std::future<void> poisson_ready;  // last member: destroyed (joined) before the data it writes

  void prepare_poisson() {
    const auto t0 = Clock::now();
    const Eigen::Index n = V.rows();
    const Eigen::SparseMatrix<double> L = cotangent_laplacian(V, F);
    const EdgeTopology topo = edge_topology(F);
    E = topo.E;
    w.resize(E.rows());
    for (Eigen::Index e = 0; e < E.rows(); ++e) w[e] = -L.coeff(E(e, 0), E(e, 1));
    if (n > 1) {
      // Pin the last vertex of the fill-reducing order (the pinned vertex only moves the solution by a
      // constant, which the normalisation removes) and factor in that order.
      const Eigen::VectorXi& order = as->order();
      Eigen::VectorXi rank(n);
      for (Eigen::Index k = 0; k < n; ++k) rank[order[k]] = static_cast<int>(k);
      std::vector<Eigen::Triplet<double>> t;
      t.reserve(static_cast<std::size_t>(L.nonZeros()));
      for (Eigen::Index j = 0; j < L.outerSize(); ++j)
        for (Eigen::SparseMatrix<double>::InnerIterator it(L, j); it; ++it)
          if (rank[it.row()] < n - 1 && rank[j] < n - 1) t.emplace_back(rank[it.row()], rank[j], it.value());
      Eigen::SparseMatrix<double> Lr(n - 1, n - 1);
      Lr.setFromTriplets(t.begin(), t.end());
      poisson.compute(Lr);
    }
    poisson_factor_ms = ms_since(t0);
  }

  // Eq. 8 edges of lambda, Poisson solve with the stored factor (poisson_ready already awaited),
  // normalisation by opt.scale.
  Eigen::MatrixXd reconstruct(const Eigen::MatrixXd& lambda) const {
    const SpinTransformOptions& o = opt;
    const Eigen::Index n = V.rows();
    const Eigen::MatrixXd et = transformed_edges(V, E, lambda);
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n, 3);  // in the assembly's vertex order
    const Eigen::VectorXi& order = as->order();
    Eigen::VectorXi rank(n);
    for (Eigen::Index k = 0; k < n; ++k) rank[order[k]] = static_cast<int>(k);
    for (Eigen::Index e = 0; e < E.rows(); ++e) {
      const Eigen::RowVector3d we = w[e] * et.row(e);
      b.row(rank[E(e, 0)]) -= we;
      b.row(rank[E(e, 1)]) += we;
    }
    Eigen::MatrixXd Vn = Eigen::MatrixXd::Zero(n, 3);
    if (n > 1) {
      const Eigen::MatrixXd x = poisson.solve(b.topRows(n - 1));
      for (Eigen::Index k = 0; k < n - 1; ++k) Vn.row(order[k]) = x.row(k);
    }
    // Normalisation.
    const Eigen::RowVector3d mean = Vn.colwise().mean();
    Vn.rowwise() -= mean;
    switch (o.scale) {
      case SpinScale::UnitMaxNorm: {
        const double r = Vn.rowwise().norm().maxCoeff();
        if (!(r > 0)) throw numerical_error("spin_transform: the reconstructed mesh collapsed to a point");
        Vn /= r;
        break;
      }
      case SpinScale::KeepArea: {
        const double a = face_areas(Vn, F).sum();
        if (!(a > 0)) throw numerical_error("spin_transform: the reconstructed mesh has zero area");
        Vn *= std::sqrt(area0 / a);
        Vn.rowwise() += mean0;
        break;
      }
      case SpinScale::None:
        Vn.rowwise() += mean0;
        break;
    }
    if (!Vn.allFinite()) throw numerical_error("spin_transform: the reconstructed positions are not finite");
    return Vn;
  }

  // Throws unless rho holds one finite value per face.
  void check_rho(const Eigen::VectorXd& rho) const {
    const Eigen::Index m = F.rows();
    if (rho.size() != m) {
      std::ostringstream msg;
      msg << "spin_transform: rho has " << rho.size() << " values for " << m << " faces";
      throw Error(msg.str());
    }
    for (Eigen::Index f = 0; f < m; ++f)
      if (!std::isfinite(rho[f])) {
        std::ostringstream msg;
        msg << "spin_transform: rho of face " << f << " is not finite (" << rho[f] << ")";
        throw Error(msg.str());
      }
  }

  // Assembles the eigen matrix K (and G for eq. 6, `gen`) of rho into K/G or Kc/Gc; returns the
  // diagonal shift σ to factor with: 1e-8 times the mean diagonal, 0 for eq. 6. Throws (Numerical) when
  // an entry is not finite.
  //
  // The relative shift of the diagonal keeps the constants (the kernel when ρ = 0) from making K
  // singular; it does not change the eigenvectors of eqs. 7 and (unweighted), only the convergence
  // ratio (θ1 + σ)/(θ2 + σ). Not for eq. 6, whose eigenvectors it would change; there A*A is
  // nonsingular for ρ ≢ 0, and for ρ ≡ 0 the constants are returned without factoring.
  double assemble(const Eigen::VectorXd& rho, bool gen) {
    if (complex) {
      as->normal_matrix(rho, scale, Kc);
      if (gen) as->mixed_matrix(rho, scale, Gc);
    } else {
      as->normal_matrix(rho, scale, K);
      if (gen) as->mixed_matrix(rho, scale, G);
    }
    // A numerical failure on valid input, not a bad matrix handed to the solver (BadInput).
    if (!(complex ? values_finite(Kc) && (!gen || values_finite(Gc))
                  : values_finite(K) && (!gen || values_finite(G))))
      throw numerical_error(
          "spin_transform: the eigen matrix is not finite (rho too large: its squares overflow)");
    const double dmean = complex ? mean_diagonal(Kc) : mean_diagonal(K);
    return gen ? 0.0 : 1e-8 * dmean;
  }

  // Shifts the diagonal of K (Kc) by sigma and factors it; if roundoff still makes a pivot
  // non-positive the shift is raised 100-fold (at most twice; never for eq. 6, `gen`). Returns the
  // shift on the diagonal; rethrows the last failure.
  double factorize(double sigma, bool gen) {
    double applied = 0;  // shift already on the diagonal
    for (int attempt = 0;; ++attempt) {
      try {
        if (complex) {
          shift_diagonal(Kc, sigma - applied);
          applied = sigma;
          cchol.factorize(Kc);
        } else {
          shift_diagonal(K, sigma - applied);
          applied = sigma;
          chol.factorize(K);
        }
        return sigma;
      } catch (const Error& e) {
        if (gen || attempt == 2 || e.kind() != Error::Kind::Numerical) throw;
        sigma *= 100.0;
      }
    }
  }

  // Inverse iteration on the factored K (shift sigma; eq. 6 with G when `gen`) from the all-ones start:
  // sets res.lambda (n×4, not yet normalised), res.residual and res.iterations; returns the eigenvalue.
  double inverse_iteration(bool gen, double sigma, SpinTransformResult& res) {
    const SmallestEigenpairOptions eo{.tolerance = opt.tolerance,
                                      .iterations = opt.iterations,
                                      .fixed_iterations = opt.fixed_iterations,
                                      .krylov = opt.krylov,
                                      .who = "spin_transform"};
    SmallestEigenpair r;
    if (complex) {
      Eigen::VectorXcd x = cstart;
      const SolveFunction<std::complex<double>> solve = [&](const Eigen::VectorXcd& b) -> Eigen::VectorXcd {
        return cchol.solve(b);
      };
      r = smallest_eigenpair<std::complex<double>>(Kc, gen ? &Gc : nullptr, solve, sigma, eo, x);
      res.lambda = as->expand(x, scale);
    } else {
      Eigen::VectorXd x = start;
      const SolveFunction<double> solve = [&](const Eigen::VectorXd& b) -> Eigen::VectorXd {
        return chol.solve(b);
      };
      r = smallest_eigenpair<double>(K, gen ? &G : nullptr, solve, sigma, eo, x);
      res.lambda = as->expand(x, scale);
    }
    res.residual = r.residual, res.iterations = r.iterations;
    return r.eigenvalue;
  }

  // Turns the n×4 field lambda by the unit quaternion that makes Σ_i x_i real positive.
  //
  // Eigenspaces are quaternionic lines (λq solves whatever λ solves), and λ ↦ λq turns the result by a
  // rotation. Pick the q that makes Σ_i x_i real positive (x = S⁻¹λ the unknowns): this is what inverse
  // iteration from the all-ones real start converges to, and it leaves the mean rotation of the unknowns
  // at zero.
  void fix_gauge(Eigen::MatrixXd& lambda) const {
    const Eigen::Index n = V.rows();
    ga::Quat sum(0.0, 0.0, 0.0, 0.0);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double wi = scale.size() ? 1.0 / scale[i] : 1.0;
      sum += wi * ga::Quat(lambda(i, 0), lambda(i, 1), lambda(i, 2), lambda(i, 3));
    }
    const double ns = std::sqrt(ga::norm2(sum));
    if (ns > 0) {
      const ga::Quat q = ga::conj(sum) / ns;
      for (Eigen::Index i = 0; i < n; ++i) {
        const ga::Quat l = ga::Quat(lambda(i, 0), lambda(i, 1), lambda(i, 2), lambda(i, 3)) * q;
        lambda.row(i) = l.coeffs().transpose();
      }
    }
  }

  explicit Impl(const SpinTransformOptions& o)
      : opt(o),
        chol({.ordering = CholeskySolver::Ordering::Natural, .supernodal = o.supernodal}),
        cchol({.ordering = CholeskySolver::Ordering::Natural, .supernodal = o.supernodal}),
        poisson({.ordering = CholeskySolver::Ordering::Natural, .supernodal = true}) {}
};

SpinTransform::SpinTransform(const Mesh& mesh, const SpinTransformOptions& options)
    : impl_(std::make_unique<Impl>(options)) {
  require_ordering(options.ordering, kVertexOrderings, "SpinTransform");
  const auto t0 = Clock::now();
  Impl& s = *impl_;
  const SpinTransformOptions& o = s.opt;
  const MeshReport rep = require(mesh,
                                 {.finite = true,
                                  .manifold = true,
                                  .oriented = true,
                                  .no_degenerate = true,
                                  .closed = o.problem == SpinEigenProblem::Generalized,
                                  .single_component = true,
                                  .no_unreferenced = true},
                                 "spin_transform");
  (void)rep;
  if (!o.fixed_iterations && !(o.tolerance > 0)) throw Error("spin_transform: tolerance must be positive");
  if (o.iterations < 1) throw Error("spin_transform: iterations must be at least 1");
  s.V = mesh.V;
  s.F = mesh.F;
  const Eigen::Index n = s.V.rows();
  s.area0 = face_areas(s.V, s.F).sum();
  s.mean0 = s.V.colwise().mean();

  // Boundary tangents (§5.7): U_i = W_i C_i.
  Eigen::VectorXi reduced;
  std::vector<Eigen::Matrix<double, 4, 2>> U;
  const SpinBoundaryTangents& bt = o.boundary;
  if (bt.vertices.size() != bt.targets.rows() || (bt.vertices.size() > 0 && bt.targets.cols() != 3))
    throw Error("spin_transform: boundary tangents need one target row (3 columns) per listed vertex");
  if (bt.vertices.size() > 0) {
    if (o.problem == SpinEigenProblem::Generalized)
      throw Error(
          "spin_transform: boundary tangents need the Standard or Unweighted problem (B*A is not "
          "Hermitian on a mesh with boundary)");
    // Source tangent: the unit outgoing boundary edge, loops oriented with the surface on the left.
    std::vector<int> next(n, -1);
    for (const auto& loop : boundary_loops(s.F))
      for (std::size_t k = 0; k < loop.size(); ++k) next[loop[k]] = loop[(k + 1) % loop.size()];
    reduced = bt.vertices;
    U.resize(bt.vertices.size());
    for (Eigen::Index r = 0; r < bt.vertices.size(); ++r) {
      const int i = bt.vertices[r];
      if (i < 0 || i >= n) {
        std::ostringstream m;
        m << "spin_transform: boundary tangent vertex " << i << " is outside [0, " << n << ")";
        throw Error(m.str());
      }
      if (next[i] < 0) {
        std::ostringstream m;
        m << "spin_transform: vertex " << i << " has a prescribed tangent but is not on the boundary";
        throw Error(m.str());
      }
      const Eigen::Vector3d Tt = bt.targets.row(r).transpose();
      if (!Tt.allFinite() || !(Tt.norm() > 0)) {
        std::ostringstream m;
        m << "spin_transform: target tangent of boundary vertex " << i << " is zero or not finite";
        throw Error(m.str());
      }
      const Eigen::Vector3d T = (s.V.row(next[i]) - s.V.row(i)).normalized().transpose();
      const Eigen::Vector3d Tn = Tt.normalized();
      // Rotation r with r T r̄ = T̃ (Eigen's convention); in Crane's action v ↦ W̄ v W, W = r̄.
      const Eigen::Quaterniond rot = Eigen::Quaterniond::FromTwoVectors(T, Tn);
      const ga::Quat W = ga::conj(ga::from_quaterniond(rot));
      Eigen::Matrix<double, 4, 2> C = Eigen::Matrix<double, 4, 2>::Zero();
      C(0, 0) = 1.0;
      C.block<3, 1>(1, 1) = Tn;
      U[r] = quaternion_block(W) * C;  // λ_i = W_i (a + b T̃_i)
    }
  }

  // Eigen matrix: vertex ordering, pattern, symbolic analysis.
  const Ordering vord = o.order_full_matrix ? Ordering::Natural : o.ordering;
  s.as = std::make_unique<DiracAssembly>(s.V, s.F, vord, reduced, U);
  // Poisson: the cotangent Laplacian and its factor, on a second thread.
  s.poisson_ready = std::async(std::launch::async, [&s] {
    block_stop_signals_on_this_thread();  // stop signals are the application's (core/interrupt.hpp)
    s.prepare_poisson();
  });
  s.complex = o.complex_form && !s.as->has_reductions();
  if (o.order_full_matrix) {
    s.chol = CholeskySolver({.ordering = o.ordering, .supernodal = o.supernodal});
    s.cchol = ComplexCholeskySolver({.ordering = o.ordering, .supernodal = o.supernodal});
  }
  if (o.problem == SpinEigenProblem::Standard) {
    // V = M_V^{-1/2}, rescaled to mean 1 (§5.5).
    const Eigen::VectorXd& Mv = s.as->vertex_areas();
    s.scale = Mv.cwiseSqrt().cwiseInverse();
    const double mean = s.scale.mean();
    s.scale /= mean;
    s.scale_c = 1.0 / mean;
  }
  if (s.complex) {
    s.Kc = s.as->complex_pattern();
    if (o.problem == SpinEigenProblem::Generalized) s.Gc = s.Kc;
    s.cchol.analyze(s.Kc);
    // All-ones real quaternions: (w1, w2) = (1, 0) at every vertex.
    s.cstart = Eigen::VectorXcd::Zero(2 * n);
    for (Eigen::Index k = 0; k < n; ++k) s.cstart[2 * k] = 1.0;
    s.cstart.normalize();
  } else {
    s.K = s.as->pattern();
    if (o.problem == SpinEigenProblem::Generalized) s.G = s.as->pattern();
    s.chol.analyze(s.K);
    s.start =
        s.as->restrict_field(Eigen::MatrixXd::Constant(n, 4, 0.0).rowwise() + Eigen::RowVector4d(1, 0, 0, 0));
    s.start.normalize();
  }

  s.bind_ms = ms_since(t0);
}

SpinTransform::~SpinTransform() = default;
SpinTransform::SpinTransform(SpinTransform&&) noexcept = default;
SpinTransform& SpinTransform::operator=(SpinTransform&&) noexcept = default;

const SpinTransformOptions& SpinTransform::options() const { return impl_->opt; }
double SpinTransform::bind_ms() const { return impl_->bind_ms; }
Eigen::Index SpinTransform::num_unknowns() const { return impl_->as->num_unknowns(); }
double SpinTransform::factor_nonzeros() const {
  return impl_->complex ? impl_->cchol.factor_nonzeros() : impl_->chol.factor_nonzeros();
}

SpinTransformResult SpinTransform::solve(const Eigen::VectorXd& rho) { return solve_impl(rho, true); }

SpinTransformResult SpinTransform::solve_similarity(const Eigen::VectorXd& rho) {
  return solve_impl(rho, false);
}

SpinTransformResult SpinTransform::solve_impl(const Eigen::VectorXd& rho, bool reconstruct_positions) {
  Impl& s = *impl_;
  const SpinTransformOptions& o = s.opt;
  const Eigen::Index n = s.V.rows();
  s.check_rho(rho);
  SpinTransformResult res;
  res.timings.bind = s.bind_ms;
  const bool rho_zero = (rho.array() == 0.0).all();
  const bool gen = o.problem == SpinEigenProblem::Generalized;
  const bool skip = gen && rho_zero;

  // Assembly, with a relative shift of the diagonal (Impl::assemble).
  auto t = Clock::now();
  double sigma = s.assemble(rho, gen);
  res.timings.assembly = ms_since(t);

  // Factorization.
  t = Clock::now();
  if (!skip) sigma = s.factorize(sigma, gen);
  res.timings.factor = ms_since(t);

  // Inverse iteration.
  t = Clock::now();
  double theta = 0;
  if (gen && rho_zero) {
    // The constants solve (D − 0)λ = 0 exactly; (6) is singular on them (γ = 0).
    res.lambda = Eigen::MatrixXd::Zero(n, 4);
    res.lambda.col(0).setOnes();
  } else {
    theta = s.inverse_iteration(gen, sigma, res);
  }
  if (o.problem == SpinEigenProblem::Standard) theta /= s.scale_c * s.scale_c;  // γ of A*Aλ = γ M_V λ
  res.eigenvalue = theta;
  if (!s.as->has_reductions()) s.fix_gauge(res.lambda);
  res.lambda /= res.lambda.norm();
  if (!res.lambda.allFinite()) throw numerical_error("spin_transform: the eigenvector is not finite");
  res.timings.eigen = ms_since(t);

  if (!reconstruct_positions) return res;
  // Reconstruction (§5.6): L f̃ = ∇·ẽ with one vertex pinned.
  t = Clock::now();
  if (s.poisson_ready.valid()) s.poisson_ready.get();  // the bind's second thread (rethrows its error)
  res.timings.poisson_setup = s.poisson_factor_ms;
  res.V = s.reconstruct(res.lambda);
  res.timings.poisson = ms_since(t);
  return res;
}

Eigen::MatrixXd SpinTransform::reconstruct(const Eigen::MatrixXd& lambda, double* ms) {
  Impl& s = *impl_;
  const Eigen::Index n = s.V.rows();
  if (lambda.rows() != n || lambda.cols() != 4) {
    std::ostringstream msg;
    msg << "spin_transform: reconstruct needs an n x 4 similarity field (n = " << n << "), got "
        << lambda.rows() << " x " << lambda.cols();
    throw Error(msg.str());
  }
  for (Eigen::Index i = 0; i < n; ++i)
    if (!lambda.row(i).allFinite()) {
      std::ostringstream msg;
      msg << "spin_transform: similarity of vertex " << i << " is not finite";
      throw Error(msg.str());
    }
  const auto t = Clock::now();
  if (s.poisson_ready.valid()) s.poisson_ready.get();
  Eigen::MatrixXd V = s.reconstruct(lambda);
  if (ms) *ms = ms_since(t);
  return V;
}

SpinTransformResult spin_transform(const Mesh& mesh, const Eigen::VectorXd& rho,
                                   const SpinTransformOptions& options) {
  SpinTransform st(mesh, options);
  return st.solve(rho);
}

}  // namespace spinmotor
