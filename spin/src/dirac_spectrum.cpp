#include "spinmotor/spin/dirac_spectrum.hpp"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsSolver.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/memory_budget.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/mesh/mass_matrix.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/spin/dirac_assembly.hpp"
#include "spinmotor/spin/quaternion_matrix.hpp"

namespace spinmotor {

namespace {

using LLT = CholeskySolver;

// Spectra's B operation in Cholesky mode, B = A*A = Pᵀ L Lᵀ P: the two triangular solves, so that the
// Lanczos iteration runs on the standard symmetric operator L⁻¹ P (B*A) Pᵀ L⁻ᵀ (no B-inner products).
class NormalMatrixCholesky {
 public:
  using Scalar = double;
  explicit NormalMatrixCholesky(const LLT& llt) : llt_(llt) {}
  Eigen::Index rows() const { return llt_.rows(); }
  Eigen::Index cols() const { return llt_.rows(); }
  void lower_triangular_solve(const double* x, double* y) const {  // y = L⁻¹ P x
    const Eigen::VectorXd px = llt_.solve(Eigen::Map<const Eigen::VectorXd>(x, rows()), LLT::System::P);
    Eigen::Map<Eigen::VectorXd>(y, rows()) = llt_.solve(px, LLT::System::L);
  }
  void upper_triangular_solve(const double* x, double* y) const {  // y = Pᵀ L⁻ᵀ x
    const Eigen::VectorXd z = llt_.solve(Eigen::Map<const Eigen::VectorXd>(x, rows()), LLT::System::Lt);
    Eigen::Map<Eigen::VectorXd>(y, rows()) = llt_.solve(z, LLT::System::Pt);
  }

 private:
  const LLT& llt_;
};

// Shared by the vertex (Crane) and face (Ye) spectra: the eigenvalues γ = 1/μ of G x = μ K x of largest
// |μ| (K = lower triangle of an SPD matrix, G = lower triangle of a symmetric one, both Nr×Nr in
// quaternion 4-blocks), Lanczos in Cholesky mode followed by the quaternionic completion. Returns the
// `count` values by increasing |γ| and, in the same order, the unit eigenvectors (Nr×count).
struct PencilSolution {
  Eigen::VectorXd gamma;
  Eigen::MatrixXd vectors;
  long iterations = 0, operations = 0;
};

PencilSolution solve_pencil(const Eigen::SparseMatrix<double>& K, const Eigen::SparseMatrix<double>& G,
                            int count, const DiracSpectrumOptions& options, LLT::Ordering ordering,
                            const char* who) {
  const Eigen::Index Nr = K.rows();
  // Every eigenvalue is (at least) 4-fold — quaternionic — and single-vector Lanczos finds the copies
  // of an exactly multiple eigenvalue only through rounding and restarts: ask for two multiplets more
  // than wanted so that a late copy is not crowded out by the next eigenvalue.
  const int nev = static_cast<int>(std::min<Eigen::Index>(count + 8, Nr - 1));
  const int ncv = options.ncv > 0
                      ? std::min<int>(options.ncv, static_cast<int>(Nr))
                      : static_cast<int>(std::min<Eigen::Index>(Nr, std::max(2 * nev + 1, nev + 40)));
  if (ncv <= nev) throw Error(std::string(who) + ": ncv must exceed count + 8");
  // The dense blocks, before any work: the Lanczos basis (Nr × ncv) and the quaternionic completion's
  // S, KS, GS (Nr × 4 nev each). The factor is checked by the solver after its symbolic analysis.
  require_memory(mul_sat(static_cast<std::uint64_t>(Nr), static_cast<std::uint64_t>(ncv + 12 * nev) * 8),
                 std::string(who) + ": the eigenvector blocks (" + std::to_string(Nr) + " rows, " +
                     std::to_string(ncv + 12 * nev) + " columns)");
  LLT chol({.ordering = ordering, .supernodal = true});
  chol.analyze(K);
  chol.factorize(K);

  using Op = Spectra::SparseSymMatProd<double, Eigen::Lower>;
  Op op(G);
  NormalMatrixCholesky bop(chol);
  Spectra::SymGEigsSolver<Op, NormalMatrixCholesky, Spectra::GEigsMode::Cholesky> eigs(op, bop, nev, ncv);
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, options.max_iterations, options.tolerance,
               Spectra::SortRule::LargestMagn);
  if (eigs.info() != Spectra::CompInfo::Successful) {
    std::ostringstream s;
    s << who << ": Spectra did not converge (" << eigs.num_iterations() << " restarts, " << nev
      << " eigenvalues, ncv " << ncv << ")";
    throw numerical_error(s.str());
  }
  // Quaternionic completion. Right multiplication by i, j, k commutes with both (left-quaternionic)
  // matrices, so the eigenspaces are closed under it; Lanczos may still have missed some real copies
  // of a multiple eigenvalue (it did on the icosphere). Rayleigh–Ritz of the pencil on
  // span{X, Xi, Xj, Xk} recovers every copy of each quaternionic line Lanczos touched.
  const Eigen::MatrixXd X = eigs.eigenvectors();
  Eigen::MatrixXd S(Nr, 4 * nev);
  for (int t = 0; t < nev; ++t)
    for (Eigen::Index v = 0; v < Nr / 4; ++v) {
      const double a = X(4 * v, t), b = X(4 * v + 1, t), c = X(4 * v + 2, t), d = X(4 * v + 3, t);
      S.block<4, 1>(4 * v, t) << a, b, c, d;              // q
      S.block<4, 1>(4 * v, nev + t) << -b, a, d, -c;      // q i
      S.block<4, 1>(4 * v, 2 * nev + t) << -c, -d, a, b;  // q j
      S.block<4, 1>(4 * v, 3 * nev + t) << -d, c, -b, a;  // q k
    }
  Eigen::MatrixXd KS(Nr, 4 * nev), GS(Nr, 4 * nev);
  for (int t = 0; t < 4 * nev; ++t) {
    KS.col(t) = K.selfadjointView<Eigen::Lower>() * S.col(t);
    GS.col(t) = G.selfadjointView<Eigen::Lower>() * S.col(t);
  }
  Eigen::MatrixXd Ks = S.transpose() * KS, Gs = S.transpose() * GS;
  Ks = (0.5 * (Ks + Ks.transpose())).eval();
  Gs = (0.5 * (Gs + Gs.transpose())).eval();
  // K-orthonormal basis of span S (drops the dependent columns: copies already in the same line).
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ek(Ks);
  const double kmax = ek.eigenvalues().maxCoeff();
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < ek.eigenvalues().size(); ++i)
    if (ek.eigenvalues()[i] > 1e-10 * kmax) keep.push_back(i);
  Eigen::MatrixXd T(4 * nev, static_cast<Eigen::Index>(keep.size()));
  for (std::size_t i = 0; i < keep.size(); ++i)
    T.col(static_cast<Eigen::Index>(i)) =
        ek.eigenvectors().col(keep[i]) / std::sqrt(ek.eigenvalues()[keep[i]]);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eg(T.transpose() * Gs * T);
  const Eigen::VectorXd mu = eg.eigenvalues();
  const Eigen::Index nr = mu.size();
  if (nr < count)
    throw numerical_error(std::string(who) + ": the Lanczos subspace is too small for the requested count");
  PencilSolution out;
  out.iterations = eigs.num_iterations();
  out.operations = eigs.num_operations();
  std::vector<int> idx(static_cast<std::size_t>(nr));
  std::iota(idx.begin(), idx.end(), 0);
  Eigen::VectorXd gamma = mu.cwiseInverse();
  std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) {
    const double ga = std::abs(gamma[a]), gb = std::abs(gamma[b]);
    if (std::abs(ga - gb) > 1e-9 * std::max(ga, gb)) return ga < gb;
    return gamma[a] < gamma[b];
  });
  out.gamma.resize(count);
  for (int t = 0; t < count; ++t) out.gamma[t] = gamma[idx[t]];
  if (options.eigenvectors) {
    const Eigen::MatrixXd Y = S * T * eg.eigenvectors();
    out.vectors.resize(Nr, count);
    for (int t = 0; t < count; ++t) out.vectors.col(t) = Y.col(idx[t]).normalized();
  }
  return out;
}

/// The tail both spectra share: without the constants (closed meshes) the last quaternion's 4
/// unknowns are dropped, the count is checked against the remaining size, the pencil is solved and the
/// eigenvalue fields of `out` are filled.
PencilSolution solve_trimmed_pencil(Eigen::SparseMatrix<double> K, Eigen::SparseMatrix<double> G,
                                    bool constants, const DiracSpectrumOptions& options,
                                    LLT::Ordering ordering, const char* who, DiracSpectrum& out) {
  const Eigen::Index Nr = constants ? K.rows() - 4 : K.rows();
  if (constants) {
    K = Eigen::SparseMatrix<double>(K.topLeftCorner(Nr, Nr));
    G = Eigen::SparseMatrix<double>(G.topLeftCorner(Nr, Nr));
  }
  if (options.count < 1 || options.count >= Nr) {
    std::ostringstream s;
    s << who << ": count must be in [1, " << Nr - 1 << "], got " << options.count;
    throw Error(s.str());
  }
  PencilSolution p = solve_pencil(K, G, options.count, options, ordering, who);
  out.constant_kernel = constants ? 4 : 0;
  out.iterations = p.iterations;
  out.operations = p.operations;
  out.eigenvalues = p.gamma;
  return p;
}

}  // namespace

DiracSpectrum dirac_spectrum(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                             const Eigen::VectorXd& rho_in, const DiracSpectrumOptions& options) {
  require(Mesh{V, F, {}, {}}, kClosedSurface, "dirac_spectrum");
  const Eigen::Index m = F.rows();
  if (rho_in.size() != 0 && rho_in.size() != m) {
    std::ostringstream s;
    s << "dirac_spectrum: rho has " << rho_in.size() << " values for " << m << " faces";
    throw Error(s.str());
  }
  const Eigen::VectorXd rho = rho_in.size() ? rho_in : Eigen::VectorXd::Zero(m);
  for (Eigen::Index f = 0; f < m; ++f)
    if (!std::isfinite(rho[f])) {
      std::ostringstream s;
      s << "dirac_spectrum: rho of face " << f << " is not finite";
      throw Error(s.str());
    }
  const bool constants = (rho.array() == 0.0).all();

  const DiracAssembly as(V, F, Ordering::AMD);
  Eigen::SparseMatrix<double> K = as.pattern(), G = as.pattern();
  as.normal_matrix(rho, {}, K);
  as.mixed_matrix(rho, {}, G);
  // Without the constants, the last vertex in the assembly's order is dropped.
  DiracSpectrum out;
  const PencilSolution p = solve_trimmed_pencil(std::move(K), std::move(G), constants, options,
                                                LLT::Ordering::Natural, "dirac_spectrum", out);
  const int count = options.count;
  const Eigen::Index N = as.num_unknowns();
  if (options.eigenvectors) {
    const Eigen::VectorXd& Mv = as.vertex_areas();
    out.eigenvectors.resize(4 * V.rows(), count);
    for (int t = 0; t < count; ++t) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(N);
      x.head(p.vectors.rows()) = p.vectors.col(t);
      Eigen::MatrixXd lambda = as.expand(x, {});
      if (constants) {
        const Eigen::RowVector4d mean = (Mv.asDiagonal() * lambda).colwise().sum() / Mv.sum();
        lambda.rowwise() -= mean;
      }
      out.eigenvectors.col(t) = flatten_quaternions(lambda);
    }
  }
  return out;
}

}  // namespace spinmotor

namespace spinmotor {

DiracSpectrum face_dirac_spectrum(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, FaceDiracKind kind,
                                  const Eigen::VectorXd& rho_in, const DiracSpectrumOptions& options) {
  require(Mesh{V, F, {}, {}},
          {.manifold = true,
           .oriented = true,
           .no_degenerate = true,
           .single_component = true,
           .no_unreferenced = true},
          "face_dirac_spectrum");
  const Eigen::Index m = F.rows(), n = V.rows();
  if (rho_in.size() != 0 && rho_in.size() != m) {
    std::ostringstream s;
    s << "face_dirac_spectrum: rho has " << rho_in.size() << " values for " << m << " faces";
    throw Error(s.str());
  }
  const Eigen::VectorXd rho = rho_in.size() ? rho_in : Eigen::VectorXd::Zero(m);
  for (Eigen::Index f = 0; f < m; ++f)
    if (!std::isfinite(rho[f])) {
      std::ostringstream s;
      s << "face_dirac_spectrum: rho of face " << f << " is not finite";
      throw Error(s.str());
    }
  // Constant spinors are in the kernel of the extrinsic operator (eq. 13) only.
  const bool constants = kind == FaceDiracKind::Extrinsic && (rho.array() == 0.0).all();
  const EdgeConstraintNet net = edge_constraint_net(V, F);
  // Ye eq. 26: Aᵀ D̂ M⁻¹ D̂ A φ = λ Aᵀ D̂ A φ with D̂ = D − P (P = diag ρ, eq. 23), solved as in
  // dirac_spectrum for μ = 1/λ of (Aᵀ D̂ A) x = μ (Aᵀ D̂ M⁻¹ D̂ A) x.
  const Eigen::SparseMatrix<double> Dh = face_dirac_operator(V, F, net, kind) - quaternion_diagonal(rho);
  const Eigen::SparseMatrix<double> Av = face_vertex_averaging(F, n);
  const Eigen::SparseMatrix<double> DA = Dh * Av;
  const Eigen::SparseMatrix<double> Minv = quaternion_diagonal(net.area.cwiseInverse());
  DiracSpectrum out;
  const PencilSolution p = solve_trimmed_pencil(Eigen::SparseMatrix<double>(DA.transpose() * Minv * DA),
                                                Eigen::SparseMatrix<double>(Av.transpose() * DA), constants,
                                                options, LLT::Ordering::AMD, "face_dirac_spectrum", out);
  const int count = options.count;
  const Eigen::Index N = 4 * n;
  if (options.eigenvectors) {
    const Eigen::VectorXd w = barycentric_vertex_areas(F, net.area, n);
    out.eigenvectors.resize(N, count);
    for (int t = 0; t < count; ++t) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(N);
      x.head(p.vectors.rows()) = p.vectors.col(t);
      Eigen::MatrixXd phi = unflatten_quaternions(x);
      if (constants) phi.rowwise() -= (w.asDiagonal() * phi).colwise().sum() / w.sum();
      out.eigenvectors.col(t) = flatten_quaternions(phi);
    }
  }
  return out;
}

}  // namespace spinmotor
