#include "spinmotor/linalg/smallest_eigenpair.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "spinmotor/core/error.hpp"

namespace spinmotor {

namespace {

// y = K x for K stored as its lower triangle (Hermitian for complex K).
template <class Scalar>
Eigen::Matrix<Scalar, Eigen::Dynamic, 1> sym_mul(const Eigen::SparseMatrix<Scalar>& K,
                                                 const Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& x) {
  return K.template selfadjointView<Eigen::Lower>() * x;
}

// ‖K‖∞ of the symmetric (Hermitian) matrix stored as its lower triangle: max absolute row sum.
template <class Scalar>
double sym_norm_inf(const Eigen::SparseMatrix<Scalar>& K) {
  Eigen::VectorXd rows = Eigen::VectorXd::Zero(K.rows());
  for (Eigen::Index j = 0; j < K.outerSize(); ++j)
    for (typename Eigen::SparseMatrix<Scalar>::InnerIterator it(K, j); it; ++it) {
      const double v = std::abs(it.value());
      rows[it.row()] += v;
      if (it.row() != j) rows[j] += v;
    }
  return rows.size() ? rows.maxCoeff() : 0.0;
}

struct IterationResult {
  double theta = 0;
  double residual = 0;
  int iterations = 0;
};

// Stops at the tolerance, or at the roundoff floor of the residual: ‖K_s x − θGx‖/‖K_s x‖ cannot go
// below ~ε‖K_s‖‖x‖/‖K_s x‖ (= ε‖K_s‖/θ_s for eq. 7: ~1e-8 when the smallest eigenvalue sits at the
// shift, ρ = 0; ~4e-9 on the 28k-face capsule, where the residual stalls at 1.6e-10). As a safety
// net, also when it has stalled below 1e-6 (less than 10% progress in 4 iterations).
class Convergence {
 public:
  Convergence(double tol, double norm_k) : tol_(tol), norm_k_(norm_k) {}
  /// residual and ‖K_s x‖/‖x‖ of the current iterate.
  bool done(double residual, double kx) {
    const double floor = std::numeric_limits<double>::epsilon() * norm_k_ / kx;
    if (residual < std::max(tol_, floor)) return true;
    if (residual < 0.9 * best_)
      best_ = residual, since_ = 0;
    else
      ++since_;
    return best_ < 1e-6 && since_ >= 4;
  }

 private:
  double tol_, norm_k_, best_ = std::numeric_limits<double>::infinity();
  int since_ = 0;
};

// Inverse iteration x ← K⁻¹x (or K⁻¹Gx for eq. 6) on one factorization; K includes the shift sigma.
template <class Scalar, class Solve>
IterationResult inverse_iteration(const Eigen::SparseMatrix<Scalar>& K, const Eigen::SparseMatrix<Scalar>* G,
                                  const Solve& solve, double sigma, const SmallestEigenpairOptions& o,
                                  Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& x) {
  using Vec = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  IterationResult r;
  Convergence conv(o.tolerance, sym_norm_inf(K));
  for (int it = 0; it < o.iterations; ++it) {
    Vec y = G ? solve(sym_mul(*G, x)) : solve(x);
    const double ny = y.norm();
    if (!(ny > 0) || !std::isfinite(ny))
      throw numerical_error(std::string(o.who) + ": inverse iteration broke down");
    y /= ny;
    const Vec Ky = sym_mul(K, y);
    const double nKy = Ky.norm();
    if (G) {
      const Vec Gy = sym_mul(*G, y);
      r.theta = (std::real(y.dot(Ky)) - sigma) / std::real(y.dot(Gy));  // Rayleigh quotient, unshifted pencil
      r.residual = (Ky - (r.theta * Gy + sigma * y)).norm() / nKy;
    } else {
      const double th = std::real(y.dot(Ky));
      r.residual = (Ky - th * y).norm() / nKy;
      r.theta = th - sigma;
    }
    x = std::move(y);
    r.iterations = it + 1;
    if (!o.fixed_iterations && conv.done(r.residual, nKy)) break;
  }
  return r;
}

// The Rayleigh–Ritz problems below are k × k (k ≤ max_basis) and solved in real arithmetic for both
// scalar types: a Hermitian H = A + iB has the real symmetric embedding [[A, −B], [B, A]], whose
// eigenvalues are H's, each twice, with eigenvectors (x; y) and (−y; x) for H's x + iy. Eigen's dense
// Hermitian solvers for complex matrices (and a pivoted QR for each type) made this file the longest
// compile of the library: 42 s of CPU at -O3 and 112 s under ASan + UBSan, 77 s of it the complex
// instantiations (docs/performance.md, "Session 22").
using RealMat = Eigen::MatrixXd;

template <class Scalar>
RealMat real_embedding(const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& H) {
  if constexpr (std::is_same_v<Scalar, double>) {
    return H;
  } else {
    const Eigen::Index k = H.rows();
    RealMat M(2 * k, 2 * k);
    M.topLeftCorner(k, k) = H.real();
    M.bottomRightCorner(k, k) = H.real();
    M.bottomLeftCorner(k, k) = H.imag();
    M.topRightCorner(k, k) = -H.imag();
    return M;
  }
}

// The inverse map on eigenvector columns: (x; y) ↦ x + iy (the identity for real matrices).
template <class Scalar>
Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> from_real_embedding(const RealMat& U) {
  if constexpr (std::is_same_v<Scalar, double>) {
    return U;
  } else {
    const Eigen::Index k = U.rows() / 2;
    return U.topRows(k).template cast<Scalar>() + Scalar(0, 1) * U.bottomRows(k).template cast<Scalar>();
  }
}

// v minus its components along the first q (orthonormal) columns of Q: classical Gram–Schmidt, twice.
template <class Mat, class Vec>
void orthogonalize(const Mat& Q, Eigen::Index q, Vec& v) {
  for (int pass = 0; pass < 2; ++pass)
    if (q > 0) v -= Q.leftCols(q) * (Q.leftCols(q).adjoint() * v);
}

// An orthonormal basis of the span of U's columns; a column that adds less than 1e-8 of its norm is
// left out (in the complex case (x; y) and (−y; x) map to x + iy and i(x + iy), one direction).
template <class Mat>
Mat orthonormal_span(const Mat& U) {
  Mat Q(U.rows(), U.cols());
  Eigen::Index q = 0;
  for (Eigen::Index j = 0; j < U.cols(); ++j) {
    auto v = U.col(j).eval();
    const double n0 = v.norm();
    orthogonalize(Q, q, v);
    const double nv = v.norm();
    if (nv > 1e-8 * n0) Q.col(q++) = v / nv;
  }
  return Q.leftCols(q);
}

// Inverse iteration accelerated by Rayleigh–Ritz on all its iterates (i.e. on the Krylov space of
// K⁻¹, or K⁻¹G, built from the start vector): the same solves as inverse iteration, but the Ritz
// vector converges at the Lanczos rate instead of the power rate θ1/θ2. The basis is kept orthonormal
// (classical Gram–Schmidt, twice) and restarted from the current Ritz vector when it reaches
// `max_basis` vectors.
template <class Scalar, class Solve>
IterationResult krylov_inverse_iteration(const Eigen::SparseMatrix<Scalar>& K,
                                         const Eigen::SparseMatrix<Scalar>* G, const Solve& solve,
                                         double sigma, const SmallestEigenpairOptions& o,
                                         Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& x) {
  const int max_basis = std::max(o.max_basis, 2);
  using Vec = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  using Mat = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  const Eigen::Index N = x.size();
  Mat Vb(N, max_basis), W(N, max_basis), Z;  // basis, K·basis, G·basis
  Mat Hk(max_basis, max_basis), Hgk;         // projections Vbᴴ W and Vbᴴ Z, grown one row/column per step
  if (G) Z.resize(N, max_basis), Hgk.resize(max_basis, max_basis);
  int k = 0;
  // Matrix–vector products only (Eigen would run N×k by N×k products through its OpenMP GEMM).
  auto project = [&](int j) {
    const Vec hv = Vb.leftCols(j + 1).adjoint() * W.col(j);
    Hk.col(j).head(j + 1) = hv;
    Hk.row(j).head(j + 1) = hv.adjoint();
    if (G) {
      const Vec hg = Vb.leftCols(j + 1).adjoint() * Z.col(j);
      Hgk.col(j).head(j + 1) = hg;
      Hgk.row(j).head(j + 1) = hg.adjoint();
    }
  };
  auto push = [&](Vec v) -> bool {
    const double n0 = v.norm();
    orthogonalize(Vb, k, v);
    const double nv = v.norm();
    // Nothing new: the Krylov space is invariant and its Ritz pairs are exact.
    if (!(nv > 1e-12 * n0) || !std::isfinite(nv)) return false;
    Vb.col(k) = v / nv;
    W.col(k) = sym_mul(K, Vec(Vb.col(k)));
    if (G) Z.col(k) = sym_mul(*G, Vec(Vb.col(k)));
    project(k);
    ++k;
    return true;
  };
  IterationResult r;
  Convergence conv(o.tolerance, sym_norm_inf(K));
  x.normalize();
  const Vec x0 = x;
  push(x);
  Vec last = x;
  for (int it = 0; it < o.iterations; ++it) {
    Vec y = G ? solve(sym_mul(*G, last)) : solve(last);
    if (!y.allFinite()) throw numerical_error(std::string(o.who) + ": inverse iteration broke down");
    if (k == max_basis) {  // restart from the current Ritz vector
      Vb.col(0) = x;
      W.col(0) = sym_mul(K, x);
      if (G) Z.col(0) = sym_mul(*G, x);
      project(0);
      k = 1;
    }
    const bool grew = push(y);
    r.iterations = it + 1;
    // Rayleigh–Ritz. When the wanted Ritz value is (nearly) multiple — a quaternionic eigenvalue in
    // the complex form, or a degenerate kernel such as the extra exact solutions of a flat disk with
    // ρ = 0 — any vector of its eigenspace is a solution, and rounding noise would pick one at random;
    // take the projection of the start vector instead, which is what plain inverse iteration
    // converges to.
    const RealMat H = real_embedding<Scalar>(Mat(Hk.topLeftCorner(k, k)));
    RealMat Ur;  // Ritz vectors (embedded basis coordinates) of the wanted cluster
    if (!G) {
      Eigen::SelfAdjointEigenSolver<RealMat> es(H);
      const Eigen::VectorXd& ev = es.eigenvalues();
      Eigen::Index c = 1;
      while (c < ev.size() && ev[c] - ev[0] <= 1e-6 * std::abs(ev[0])) ++c;
      Ur = es.eigenvectors().leftCols(c);
      r.theta = ev[0];
    } else {
      const RealMat Hg = real_embedding<Scalar>(Mat(Hgk.topLeftCorner(k, k)));
      // Hg u = μ H u with H positive definite; the largest |μ| is the smallest |γ| = |1/μ|.
      Eigen::GeneralizedSelfAdjointEigenSolver<RealMat> es(Hg, H);
      const Eigen::VectorXd& mu = es.eigenvalues();
      Eigen::Index best = 0;
      mu.cwiseAbs().maxCoeff(&best);
      std::vector<Eigen::Index> cl;
      for (Eigen::Index i = 0; i < mu.size(); ++i)
        if (std::abs(mu[i] - mu[best]) <= 1e-6 * std::abs(mu[best])) cl.push_back(i);
      Ur.resize(H.rows(), static_cast<Eigen::Index>(cl.size()));
      for (std::size_t i = 0; i < cl.size(); ++i)
        Ur.col(static_cast<Eigen::Index>(i)) = es.eigenvectors().col(cl[i]);
      r.theta = 1.0 / mu[best];
    }
    const Mat Uc = from_real_embedding<Scalar>(Ur);
    Vec u;
    if (Uc.cols() == 1) {  // a simple eigenvalue (of a real matrix: a complex one's embedding has two)
      u = Uc.col(0);
    } else {
      // The projection of the start vector on the cluster's span.
      const Mat Q = orthonormal_span(Uc);
      const Vec c0 = Vb.leftCols(k).adjoint() * x0;
      u = Q * (Q.adjoint() * c0);
      if (!(u.norm() > 1e-8 * c0.norm())) u = Q.col(0);  // the start has no component there
    }
    x = Vb.leftCols(k) * u;
    const double nx = x.norm();
    x /= nx;
    const Vec Kx = W.leftCols(k) * u / nx;
    const double nKx = Kx.norm();
    if (G) {
      const Vec Gx = Z.leftCols(k) * u / nx;
      // Unshifted pencil: A*A = K − σ; its Rayleigh quotient on the Ritz vector.
      r.theta = (std::real(x.dot(Kx)) - sigma) / std::real(x.dot(Gx));
      r.residual = (Kx - (r.theta * Gx + sigma * x)).norm() / nKx;
    } else {
      r.residual = (Kx - r.theta * x).norm() / nKx;
      r.theta -= sigma;
    }
    last = Vb.col(k - 1);
    if (conv.done(r.residual, nKx) || !grew) break;
  }
  return r;
}

}  // namespace

template <class Scalar>
SmallestEigenpair smallest_eigenpair(const Eigen::SparseMatrix<Scalar>& K,
                                     const Eigen::SparseMatrix<Scalar>* G, const SolveFunction<Scalar>& solve,
                                     double sigma, const SmallestEigenpairOptions& options,
                                     Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& x) {
  if (K.rows() != K.cols() || x.size() != K.rows() || (G && (G->rows() != K.rows() || G->cols() != K.cols())))
    throw Error(std::string(options.who) + ": K, G and the start vector must have the same size");
  const IterationResult r = options.fixed_iterations || !options.krylov
                                ? inverse_iteration(K, G, solve, sigma, options, x)
                                : krylov_inverse_iteration(K, G, solve, sigma, options, x);
  return {r.theta, r.residual, r.iterations};
}

template SmallestEigenpair smallest_eigenpair(const Eigen::SparseMatrix<double>&,
                                              const Eigen::SparseMatrix<double>*,
                                              const SolveFunction<double>&, double,
                                              const SmallestEigenpairOptions&, Eigen::VectorXd&);
template SmallestEigenpair smallest_eigenpair(const Eigen::SparseMatrix<std::complex<double>>&,
                                              const Eigen::SparseMatrix<std::complex<double>>*,
                                              const SolveFunction<std::complex<double>>&, double,
                                              const SmallestEigenpairOptions&, Eigen::VectorXcd&);

}  // namespace spinmotor
