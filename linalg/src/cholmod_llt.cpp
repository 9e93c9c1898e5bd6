#include "spinmotor/linalg/cholmod_llt.hpp"

#include <cholmod.h>

#include <limits>
#include <sstream>
#include <type_traits>

#include "spinmotor/core/error.hpp"
#include "spinmotor/linalg/blas_threads.hpp"

namespace spinmotor::detail {

template <class Scalar>
struct CholmodLLT<Scalar>::Impl {
  static constexpr bool kComplex = !std::is_same_v<Scalar, double>;
  static constexpr int kXtype = kComplex ? CHOLMOD_COMPLEX : CHOLMOD_REAL;  // complex: interleaved (re, im)
  cholmod_common c{};
  cholmod_factor* L = nullptr;
  Eigen::Index n = -1;
  Eigen::Index nnz = -1;
  bool factorized = false;

  Impl(Ordering o, bool supernodal) {
    use_single_threaded_blas();
    cholmod_start(&c);
    c.print = 0;
    c.error_handler = nullptr;
    c.nmethods = 1;
    c.method[0].ordering = o == Ordering::Natural ? CHOLMOD_NATURAL
                           : o == Ordering::AMD   ? CHOLMOD_AMD
                                                  : CHOLMOD_METIS;
    c.postorder = 1;
    c.supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    c.final_ll = 1;  // simplicial: LLᴴ too, so that a non-positive pivot is reported
  }
  ~Impl() {
    if (L) cholmod_free_factor(&L, &c);
    cholmod_finish(&c);
  }
  static cholmod_sparse view(const Eigen::SparseMatrix<Scalar>& A) {
    if (!A.isCompressed()) throw Error("CholmodLLT: the matrix must be compressed");
    cholmod_sparse s{};
    s.nrow = s.ncol = static_cast<size_t>(A.rows());
    s.nzmax = static_cast<size_t>(A.nonZeros());
    s.p = const_cast<int*>(A.outerIndexPtr());
    s.i = const_cast<int*>(A.innerIndexPtr());
    s.x = const_cast<Scalar*>(A.valuePtr());
    s.stype = -1;  // lower triangle
    s.itype = CHOLMOD_INT;
    s.xtype = kXtype;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
  }
  void status(const char* what) const {
    if (c.status < 0) {
      std::ostringstream s;
      s << "CholmodLLT: CHOLMOD " << what << " failed (status " << c.status << ")";
      throw numerical_error(s.str());
    }
  }
};

template <class Scalar>
CholmodLLT<Scalar>::CholmodLLT(Ordering ordering, bool supernodal)
    : impl_(std::make_unique<Impl>(ordering, supernodal)) {}
template <class Scalar>
CholmodLLT<Scalar>::~CholmodLLT() = default;
template <class Scalar>
CholmodLLT<Scalar>::CholmodLLT(CholmodLLT&&) noexcept = default;
template <class Scalar>
CholmodLLT<Scalar>& CholmodLLT<Scalar>::operator=(CholmodLLT&&) noexcept = default;

template <class Scalar>
void CholmodLLT<Scalar>::analyze(const Eigen::SparseMatrix<Scalar>& A) {
  Impl& m = *impl_;
  if (A.rows() != A.cols()) throw Error("CholmodLLT: the matrix must be square");
  if (m.L) cholmod_free_factor(&m.L, &m.c);
  m.factorized = false;
  cholmod_sparse s = Impl::view(A);
  m.L = cholmod_analyze(&s, &m.c);
  if (!m.L) m.status("analyze"), throw numerical_error("CholmodLLT: CHOLMOD analyze failed");
  m.n = A.rows();
  m.nnz = A.nonZeros();
}

template <class Scalar>
void CholmodLLT<Scalar>::factorize(const Eigen::SparseMatrix<Scalar>& A) {
  Impl& m = *impl_;
  if (!m.L) throw Error("CholmodLLT: factorize() before analyze()");
  if (A.rows() != m.n || A.nonZeros() != m.nnz)
    throw Error("CholmodLLT: the pattern differs from the analyzed one");
  m.factorized = false;
  cholmod_sparse s = Impl::view(A);
  cholmod_factorize(&s, m.L, &m.c);
  m.status("factorize");
  if (m.c.status == CHOLMOD_NOT_POSDEF || m.L->minor < m.L->n) {
    std::ostringstream msg;
    msg << "CholmodLLT: matrix is not positive definite (CHOLMOD: leading minor " << m.L->minor << " of "
        << m.L->n << ")";
    throw numerical_error(msg.str());
  }
  const double rc = cholmod_rcond(m.L, &m.c);
  if (!(rc >= std::numeric_limits<double>::epsilon())) {
    std::ostringstream msg;
    msg << "CholmodLLT: matrix is numerically singular (rcond " << rc << ")";
    throw numerical_error(msg.str());
  }
  m.factorized = true;
}

template <class Scalar>
typename CholmodLLT<Scalar>::Vector CholmodLLT<Scalar>::solve(const Vector& b, System system) const {
  Impl& m = *impl_;
  if (!m.factorized) throw Error("CholmodLLT: solve() before a successful factorize()");
  if (b.size() != m.n) throw Error("CholmodLLT: right-hand side of the wrong size");
  cholmod_dense d{};
  d.nrow = static_cast<size_t>(m.n);
  d.ncol = 1;
  d.nzmax = d.d = static_cast<size_t>(m.n);
  d.x = const_cast<Scalar*>(b.data());
  d.xtype = Impl::kXtype;
  d.dtype = CHOLMOD_DOUBLE;
  const int sys = system == System::A    ? CHOLMOD_A
                  : system == System::L  ? CHOLMOD_L
                  : system == System::Lt ? CHOLMOD_Lt
                  : system == System::P  ? CHOLMOD_P
                                         : CHOLMOD_Pt;
  cholmod_dense* x = cholmod_solve(sys, m.L, &d, &m.c);
  if (!x) m.status("solve"), throw numerical_error("CholmodLLT: CHOLMOD solve failed");
  Vector out = Eigen::Map<const Vector>(static_cast<const Scalar*>(x->x), m.n);
  cholmod_free_dense(&x, &m.c);
  if (!out.allFinite()) throw numerical_error("CholmodLLT: the solution is not finite");
  return out;
}

template <class Scalar>
Eigen::Index CholmodLLT<Scalar>::rows() const {
  return impl_->n < 0 ? 0 : impl_->n;
}
template <class Scalar>
double CholmodLLT<Scalar>::factor_nonzeros() const {
  return impl_->L ? impl_->c.lnz : 0.0;
}
template <class Scalar>
double CholmodLLT<Scalar>::factor_flops() const {
  return impl_->L ? impl_->c.fl : 0.0;
}

template class CholmodLLT<double>;
template class CholmodLLT<std::complex<double>>;

}  // namespace spinmotor::detail
