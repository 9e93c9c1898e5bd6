#include "spinmotor/spin/dirac_spectrum.hpp"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsSolver.h>

#include <algorithm>
#include <numeric>
#include <sstream>

#include "spinmotor/error.hpp"
#include "spinmotor/mesh/cholesky_solver.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/spin/dirac_assembly.hpp"
#include "spinmotor/spin/quaternion_matrix.hpp"

namespace spinmotor {

namespace {

// Spectra's B operation for regular-inverse mode: B x and B⁻¹ x with B = A*A (lower triangle stored).
class NormalMatrixOp {
public:
  using Scalar = double;
  NormalMatrixOp(const Eigen::SparseMatrix<double>& K, const CholeskySolver& chol) : K_(K), chol_(chol) {}
  Eigen::Index rows() const { return K_.rows(); }
  Eigen::Index cols() const { return K_.cols(); }
  void solve(const double* x, double* y) const {
    Eigen::Map<Eigen::VectorXd>(y, K_.rows()) = chol_.solve(Eigen::Map<const Eigen::VectorXd>(x, K_.rows()));
  }
  void perform_op(const double* x, double* y) const {
    Eigen::Map<Eigen::VectorXd>(y, K_.rows()).noalias() =
        K_.selfadjointView<Eigen::Lower>() * Eigen::Map<const Eigen::VectorXd>(x, K_.rows());
  }

private:
  const Eigen::SparseMatrix<double>& K_;
  const CholeskySolver& chol_;
};

}  // namespace

DiracSpectrum dirac_spectrum(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::VectorXd& rho_in,
                             const DiracSpectrumOptions& options) {
  require(Mesh{V, F, {}, {}},
          {.manifold = true, .oriented = true, .no_degenerate = true, .closed = true, .single_component = true,
           .no_unreferenced = true},
          "dirac_spectrum");
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

  const DiracAssembly as(V, F, VertexOrdering::AMD);
  Eigen::SparseMatrix<double> K = as.pattern(), G = as.pattern();
  as.normal_matrix(rho, {}, K);
  as.mixed_matrix(rho, {}, G);
  const Eigen::Index N = as.num_unknowns();
  // Drop the last vertex (in the assembly's order) when the constants must be removed.
  const Eigen::Index Nr = constants ? N - 4 : N;
  if (constants) {
    K = Eigen::SparseMatrix<double>(K.topLeftCorner(Nr, Nr));
    G = Eigen::SparseMatrix<double>(G.topLeftCorner(Nr, Nr));
  }
  const int count = options.count;
  if (count < 1 || count >= Nr) {
    std::ostringstream s;
    s << "dirac_spectrum: count must be in [1, " << Nr - 1 << "], got " << count;
    throw Error(s.str());
  }
  CholeskySolver chol({.ordering = CholeskySolver::Ordering::Natural, .supernodal = true});
  chol.compute(K);

  using Op = Spectra::SparseSymMatProd<double, Eigen::Lower>;
  Op op(G);
  NormalMatrixOp bop(K, chol);
  const int ncv = options.ncv > 0 ? std::min<int>(options.ncv, static_cast<int>(Nr))
                                  : static_cast<int>(std::min<Eigen::Index>(Nr, std::max(2 * count + 1, count + 40)));
  if (ncv <= count) throw Error("dirac_spectrum: ncv must exceed count");
  Spectra::SymGEigsSolver<Op, NormalMatrixOp, Spectra::GEigsMode::RegularInverse> eigs(op, bop, count, ncv);
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, options.max_iterations, options.tolerance, Spectra::SortRule::LargestMagn);
  if (eigs.info() != Spectra::CompInfo::Successful) {
    std::ostringstream s;
    s << "dirac_spectrum: Spectra did not converge (" << eigs.num_iterations() << " restarts, " << count
      << " eigenvalues, ncv " << ncv << ")";
    throw numerical_error(s.str());
  }
  const Eigen::VectorXd mu = eigs.eigenvalues();
  DiracSpectrum out;
  out.constant_kernel = constants ? 4 : 0;
  out.iterations = eigs.num_iterations();
  out.operations = eigs.num_operations();
  std::vector<int> idx(count);
  std::iota(idx.begin(), idx.end(), 0);
  Eigen::VectorXd gamma = mu.cwiseInverse();
  std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) {
    const double ga = std::abs(gamma[a]), gb = std::abs(gamma[b]);
    if (std::abs(ga - gb) > 1e-9 * std::max(ga, gb)) return ga < gb;
    return gamma[a] < gamma[b];
  });
  out.eigenvalues.resize(count);
  for (int t = 0; t < count; ++t) out.eigenvalues[t] = gamma[idx[t]];
  if (options.eigenvectors) {
    const Eigen::MatrixXd X = eigs.eigenvectors();
    const Eigen::VectorXd& Mv = as.vertex_areas();
    out.eigenvectors.resize(4 * V.rows(), count);
    for (int t = 0; t < count; ++t) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(N);
      x.head(Nr) = X.col(idx[t]);
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
