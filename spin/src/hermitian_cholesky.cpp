#include "hermitian_cholesky.hpp"

#include <cholmod.h>

#include <limits>
#include <sstream>

#include "spinmotor/error.hpp"

namespace spinmotor::detail {

struct HermitianCholesky::Impl {
  cholmod_common c{};
  cholmod_factor* L = nullptr;
  Eigen::Index n = -1;
  Eigen::Index nnz = -1;
  bool factorized = false;

  Impl(Ordering o, bool supernodal) {
    cholmod_start(&c);
    c.print = 0;
    c.error_handler = nullptr;
    c.nmethods = 1;
    c.method[0].ordering = o == Ordering::Natural ? CHOLMOD_NATURAL : o == Ordering::AMD ? CHOLMOD_AMD : CHOLMOD_METIS;
    c.postorder = 1;
    c.supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    c.final_ll = 1;  // simplicial: LLᴴ as well, so that a non-positive pivot is reported
  }
  ~Impl() {
    if (L) cholmod_free_factor(&L, &c);
    cholmod_finish(&c);
  }
  static cholmod_sparse view(const Eigen::SparseMatrix<std::complex<double>>& A) {
    if (!A.isCompressed()) throw Error("HermitianCholesky: the matrix must be compressed");
    cholmod_sparse s{};
    s.nrow = s.ncol = static_cast<size_t>(A.rows());
    s.nzmax = static_cast<size_t>(A.nonZeros());
    s.p = const_cast<int*>(A.outerIndexPtr());
    s.i = const_cast<int*>(A.innerIndexPtr());
    s.x = const_cast<std::complex<double>*>(A.valuePtr());  // interleaved (re, im): CHOLMOD_COMPLEX
    s.stype = -1;
    s.itype = CHOLMOD_INT;
    s.xtype = CHOLMOD_COMPLEX;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
  }
  void status(const char* what) const {
    if (c.status < 0) {
      std::ostringstream s;
      s << "HermitianCholesky: CHOLMOD " << what << " failed (status " << c.status << ")";
      throw numerical_error(s.str());
    }
  }
};

HermitianCholesky::HermitianCholesky(Ordering ordering, bool supernodal)
    : impl_(std::make_unique<Impl>(ordering, supernodal)) {}
HermitianCholesky::~HermitianCholesky() = default;
HermitianCholesky::HermitianCholesky(HermitianCholesky&&) noexcept = default;
HermitianCholesky& HermitianCholesky::operator=(HermitianCholesky&&) noexcept = default;

void HermitianCholesky::analyze(const Eigen::SparseMatrix<std::complex<double>>& A) {
  Impl& m = *impl_;
  if (A.rows() != A.cols()) throw Error("HermitianCholesky: the matrix must be square");
  if (m.L) cholmod_free_factor(&m.L, &m.c);
  m.factorized = false;
  cholmod_sparse s = Impl::view(A);
  m.L = cholmod_analyze(&s, &m.c);
  if (!m.L) m.status("analyze"), throw numerical_error("HermitianCholesky: CHOLMOD analyze failed");
  m.n = A.rows();
  m.nnz = A.nonZeros();
}

void HermitianCholesky::factorize(const Eigen::SparseMatrix<std::complex<double>>& A) {
  Impl& m = *impl_;
  if (!m.L) throw Error("HermitianCholesky: factorize() before analyze()");
  if (A.rows() != m.n || A.nonZeros() != m.nnz) throw Error("HermitianCholesky: the pattern differs from the analyzed one");
  m.factorized = false;
  cholmod_sparse s = Impl::view(A);
  cholmod_factorize(&s, m.L, &m.c);
  m.status("factorize");
  if (m.c.status == CHOLMOD_NOT_POSDEF || m.L->minor < m.L->n) {
    std::ostringstream msg;
    msg << "HermitianCholesky: matrix is not positive definite (CHOLMOD: leading minor " << m.L->minor << " of "
        << m.L->n << ")";
    throw numerical_error(msg.str());
  }
  const double rc = cholmod_rcond(m.L, &m.c);
  if (!(rc >= std::numeric_limits<double>::epsilon())) {
    std::ostringstream msg;
    msg << "HermitianCholesky: matrix is numerically singular (rcond " << rc << ")";
    throw numerical_error(msg.str());
  }
  m.factorized = true;
}

Eigen::VectorXcd HermitianCholesky::solve(const Eigen::VectorXcd& b) const {
  Impl& m = *impl_;
  if (!m.factorized) throw Error("HermitianCholesky: solve() before a successful factorize()");
  if (b.size() != m.n) throw Error("HermitianCholesky: right-hand side of the wrong size");
  cholmod_dense d{};
  d.nrow = static_cast<size_t>(m.n);
  d.ncol = 1;
  d.nzmax = d.d = static_cast<size_t>(m.n);
  d.x = const_cast<std::complex<double>*>(b.data());
  d.xtype = CHOLMOD_COMPLEX;
  d.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* x = cholmod_solve(CHOLMOD_A, m.L, &d, &m.c);
  if (!x) m.status("solve"), throw numerical_error("HermitianCholesky: CHOLMOD solve failed");
  Eigen::VectorXcd out = Eigen::Map<const Eigen::VectorXcd>(static_cast<const std::complex<double>*>(x->x), m.n);
  cholmod_free_dense(&x, &m.c);
  if (!out.allFinite()) throw numerical_error("HermitianCholesky: the solution is not finite");
  return out;
}

double HermitianCholesky::factor_nonzeros() const { return impl_->L ? impl_->c.lnz : 0.0; }
double HermitianCholesky::factor_flops() const { return impl_->L ? impl_->c.fl : 0.0; }

}  // namespace spinmotor::detail
