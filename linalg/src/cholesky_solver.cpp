#include "spinmotor/linalg/cholesky_solver.hpp"

#include <cholmod.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <sstream>
#include <string>
#include <system_error>
#include <thread>
#include <type_traits>
#include <vector>

#include "ordering_scope.hpp"
#include "solver_detail.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/huge_pages.hpp"
#include "spinmotor/core/interrupt.hpp"
#include "spinmotor/core/memory_budget.hpp"
#include "spinmotor/linalg/blas_threads.hpp"
#include "spinmotor/linalg/serial_openmp.hpp"

namespace spinmotor {
namespace {
// solve(): right-hand sides per thread, and the work (factor nonzeros × right-hand sides) from which
// the columns are split among the cores (below, one thread; a 100k-face spin factor's 8M nonzeros
// times its 1–4 columns stays below).
constexpr Eigen::Index kColumnsPerThread = 8;
// The cores the threaded paths use (the BLAS of a large factorization, the blocks of a large solve).
int cores() { return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }
constexpr double kThreadedSolveWork = 1e8;
// Relative pivot size below which a factor is declared numerically singular (cond ≳ 4.5e12).
constexpr double kSingularPivot = 1e3 * std::numeric_limits<double>::epsilon();
// Whether A stores both triangles: as many entries above the diagonal as below (the input convention
// makes such a matrix symmetric / Hermitian, so either triangle can be read). One pass over the row
// indices.
template <class SparseMatrix>
bool stored_in_full(const SparseMatrix& A) {
  std::int64_t above = 0, below = 0;
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  for (Eigen::Index j = 0; j < A.cols(); ++j)
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      above += inner[p] < j;
      below += inner[p] > j;
    }
  return below > 0 && above == below;
}

// Ordering::Auto switches from AMD to METIS at this many rows (bench_laplacian: AMD is faster
// overall at 100k, METIS at 1M).
constexpr Eigen::Index kAutoMetisRows = 500000;
constexpr const char* kWho = "CholeskySolver";

// CHOLMOD allocates through SuiteSparse_config's function pointers (process-wide). Pointing them at
// the huge-page variants of malloc/calloc/realloc (core/huge_pages.hpp) puts a factor's values on
// 2 MiB pages where the kernel allows it: its zeroing in cholmod_super_numeric was most of the page
// faults of a bind (docs/performance.md, "Page faults, CHOLMOD's OpenMP regions and OpenBLAS's idle
// workers"). The memory is std::malloc's, so free_func stays std::free and blocks allocated before
// the switch (or by another CHOLMOD user in the process) are freed correctly. Set once, before the
// first CHOLMOD call of this library.
void use_huge_pages_in_cholmod() {
  static std::once_flag once;
  std::call_once(once, [] {
    SuiteSparse_config.malloc_func = malloc_huge;
    SuiteSparse_config.calloc_func = calloc_huge;
    SuiteSparse_config.realloc_func = realloc_huge;
  });
}
}  // namespace

template <class Scalar>
struct BasicCholeskySolver<Scalar>::Impl {
  static constexpr bool kComplex = !std::is_same_v<Scalar, double>;
  // Complex values are interleaved (re, im) pairs, as std::complex<double> stores them.
  static constexpr int kXtype = kComplex ? CHOLMOD_COMPLEX : CHOLMOD_REAL;
  static constexpr int kStride = kComplex ? 2 : 1;  // doubles per value in the factor's x array

  Options options;
  cholmod_common common{};
  cholmod_factor* L = nullptr;
  Eigen::Index n = -1;
  std::size_t pattern = 0;
  bool factorized = false;
  Ordering used = Ordering::Natural;
  // The triangle CHOLMOD reads (stype): −1, the lower one, unless A is stored in full and the ordering
  // permutes it, then +1, the upper one. cholmod_factorize forms the permuted lower triangle that its
  // supernodal and simplicial kernels read with one permuted transpose from the upper triangle and with
  // two from the lower one; with the natural ordering it reads the lower triangle in place.
  int stype = -1;

  explicit Impl(const Options& o) : options(o) {
    use_single_threaded_blas();
    use_huge_pages_in_cholmod();
    cholmod_start(&common);
    common.print = 0;  // failures are reported by our exceptions, not on stderr
    common.error_handler = nullptr;
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_AMD;  // set per matrix in analyze()
    common.postorder = 1;
    common.supernodal = o.supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  }
  ~Impl() {
    if (L) cholmod_free_factor(&L, &common);
    cholmod_finish(&common);
  }

  // A view of A: CHOLMOD reads it in place, the lower triangle for stype −1 (the upper one ignored),
  // the upper triangle for +1.
  static cholmod_sparse view(const SparseMatrix& A, int stype) {
    cholmod_sparse s{};
    s.nrow = static_cast<size_t>(A.rows());
    s.ncol = static_cast<size_t>(A.cols());
    s.nzmax = static_cast<size_t>(A.nonZeros());
    s.p = const_cast<int*>(A.outerIndexPtr());
    s.i = const_cast<int*>(A.innerIndexPtr());
    s.x = const_cast<Scalar*>(A.valuePtr());
    s.stype = stype;
    s.itype = CHOLMOD_INT;
    s.xtype = kXtype;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
  }

  void check_status(const char* what) const {
    if (common.status == CHOLMOD_OUT_OF_MEMORY)
      throw numerical_error(std::string(kWho) + ": out of memory in CHOLMOD " + what);
    if (common.status == CHOLMOD_TOO_LARGE)
      throw numerical_error(std::string(kWho) + ": problem too large for CHOLMOD " + what);
    if (common.status < 0) {
      std::ostringstream s;
      s << kWho << ": CHOLMOD " << what << " failed (status " << common.status << ")";
      throw numerical_error(s.str());
    }
  }

  [[noreturn]] void throw_not_pd(const SparseMatrix& A, long k, const std::string& why) const {
    // Name the original row of the failing pivot and its component: usually a component that floats.
    const int* perm = static_cast<const int*>(L->Perm);
    const int row = (perm && k >= 0 && k < static_cast<long>(L->n)) ? perm[k] : static_cast<int>(k);
    const detail::GraphComponents g = detail::matrix_components(A);
    std::ostringstream s;
    s << kWho << ": matrix is not positive definite (CHOLMOD: " << why << "; pivot at row " << row;
    if (row >= 0 && row < static_cast<int>(A.rows()))
      s << ", in " << detail::describe_component(g, g.label[row], "row", "rows") << " of " << g.count()
        << " of the matrix graph";
    s << ")";
    throw numerical_error(s.str());
  }

  // Real part of the diagonal entry of column j of a simplicial factor (L(j,j) for LLᴴ, D(j,j) for LDLᴴ;
  // real for a Hermitian matrix).
  double simplicial_diagonal(Eigen::Index j) const {
    const int* p = static_cast<const int*>(L->p);
    return static_cast<const double*>(L->x)[kStride * static_cast<std::ptrdiff_t>(p[j])];
  }

  // The pivot checks after a successful CHOLMOD factorization (see the header): D > 0 for LDLᴴ, then
  // the smallest pivot against the largest diagonal entry of A.
  void check_pivots(const SparseMatrix& A) const {
    if (!L->is_ll)  // simplicial LDLᴴ succeeds on indefinite matrices: require D > 0
      for (Eigen::Index j = 0; j < n; ++j)
        if (const double d = simplicial_diagonal(j); !(d > 0)) {
          std::ostringstream why;
          why << "pivot D(" << j << "," << j << ") = " << d;
          throw_not_pd(A, static_cast<long>(j), why.str());
        }
    // A positive semi-definite singular matrix (e.g. a Laplacian with a floating component) ends with
    // a roundoff pivot of either sign; a positive one passes the factorization. Every pivot of an SPD
    // matrix is ≥ λ_min(A), so a pivot ≤ kSingularPivot·max_j A(j,j) means cond(A) ≳ 1/kSingularPivot:
    // numerically singular.
    double amax = 0;
    for (Eigen::Index j = 0; j < n; ++j)
      for (int k = A.outerIndexPtr()[j]; k < A.outerIndexPtr()[j + 1]; ++k)
        if (A.innerIndexPtr()[k] == j) amax = std::max(amax, std::real(A.valuePtr()[k]));
    long kmin = 0;
    double dmin = std::numeric_limits<double>::infinity();  // smallest pivot d_k (= L(k,k)² for LLᴴ)
    if (!L->is_super) {
      for (Eigen::Index j = 0; j < n; ++j) {
        const double x = simplicial_diagonal(j), d = L->is_ll ? x * x : x;
        if (d < dmin) dmin = d, kmin = static_cast<long>(j);
      }
    } else {
      const int* super = static_cast<const int*>(L->super);
      const int* pi = static_cast<const int*>(L->pi);
      const int* px = static_cast<const int*>(L->px);
      const double* x = static_cast<const double*>(L->x);
      for (size_t sn = 0; sn < L->nsuper; ++sn) {
        const int k1 = super[sn], k2 = super[sn + 1], nrows = pi[sn + 1] - pi[sn];
        for (int k = k1; k < k2; ++k) {
          const double l = x[kStride * (px[sn] + (k - k1) + static_cast<long>(k - k1) * nrows)];
          if (l * l < dmin) dmin = l * l, kmin = k;
        }
      }
    }
    if (!(dmin > kSingularPivot * amax)) {
      std::ostringstream why;
      why << "numerically singular, smallest pivot " << dmin << " vs largest diagonal entry " << amax;
      throw_not_pd(A, kmin, why.str());
    }
  }
};

template <class Scalar>
BasicCholeskySolver<Scalar>::BasicCholeskySolver() : BasicCholeskySolver(Options{}) {}
template <class Scalar>
BasicCholeskySolver<Scalar>::BasicCholeskySolver(const Options& options)
    : impl_(std::make_unique<Impl>(options)) {
  require_ordering(options.ordering, kOrderings, kWho);
}
template <class Scalar>
BasicCholeskySolver<Scalar>::~BasicCholeskySolver() = default;
template <class Scalar>
BasicCholeskySolver<Scalar>::BasicCholeskySolver(BasicCholeskySolver&&) noexcept = default;
template <class Scalar>
BasicCholeskySolver<Scalar>& BasicCholeskySolver<Scalar>::operator=(BasicCholeskySolver&&) noexcept = default;

template <class Scalar>
void BasicCholeskySolver<Scalar>::analyze(const SparseMatrix& A) {
  Impl& m = *impl_;
  detail::check_square_finite(A, kWho);
  if (m.L) cholmod_free_factor(&m.L, &m.common);
  m.factorized = false;
  m.n = A.rows();
  m.pattern = detail::pattern_hash(A);
  if (m.n == 0) return;  // nothing to factor; solve() returns 0×k
  m.used = m.options.ordering == Ordering::Auto ? (m.n < kAutoMetisRows ? Ordering::AMD : Ordering::METIS)
                                                : m.options.ordering;
  m.common.method[0].ordering = [&] {
    switch (m.options.ordering) {
      case Ordering::Auto:
        return m.n < kAutoMetisRows ? CHOLMOD_AMD : CHOLMOD_METIS;
      case Ordering::Natural:
        return CHOLMOD_NATURAL;
      case Ordering::AMD:
        return CHOLMOD_AMD;
      case Ordering::METIS:
        return CHOLMOD_METIS;
      case Ordering::NESDIS:
        return CHOLMOD_NESDIS;
      default:  // rejected by the constructor
        return CHOLMOD_AMD;
    }
  }();
  m.stype = m.used != Ordering::Natural && stored_in_full(A) ? 1 : -1;
  cholmod_sparse s = Impl::view(A, m.stype);
  {
    const detail::OrderingScope ordering;  // METIS traps SIGTERM (ordering_scope.hpp)
    m.L = cholmod_analyze(&s, &m.common);
  }
  if (!m.L) m.check_status("analyze"), throw numerical_error(std::string(kWho) + ": CHOLMOD analyze failed");
  if (m.options.try_natural && m.used != Ordering::Natural) {
    const double fl = m.common.fl, lnz = m.common.lnz;
    m.common.method[0].ordering = CHOLMOD_NATURAL;
    cholmod_factor* natural = nullptr;
    {
      const detail::OrderingScope ordering;
      natural = cholmod_analyze(&s, &m.common);
    }
    if (!natural)
      m.check_status("analyze"), throw numerical_error(std::string(kWho) + ": CHOLMOD analyze failed");
    if (m.common.fl < fl) {
      cholmod_free_factor(&m.L, &m.common);
      m.L = natural;
      m.used = Ordering::Natural;
      m.stype = -1;  // read in place (the pattern analysed is the same: A is symmetric)
    } else {
      cholmod_free_factor(&natural, &m.common);
      m.common.fl = fl, m.common.lnz = lnz;  // factor_flops() and factor_nonzeros() of the kept one
    }
  }
  // The symbolic analysis knows the factor's size: refuse before the numeric factorization what cannot
  // fit (a value and a row index per nonzero, plus per-column bookkeeping).
  const auto lnz = static_cast<std::uint64_t>(m.common.lnz);
  const std::uint64_t estimate = add_sat(mul_sat(lnz, sizeof(Scalar) + sizeof(SuiteSparse_long)),
                                         mul_sat(static_cast<std::uint64_t>(m.n), 64));
  if (estimate > memory_limit()) {
    std::ostringstream s;
    s << kWho << ": the Cholesky factor of a " << m.n << "x" << m.n << " matrix (" << m.common.lnz
      << " nonzeros after ordering)";
    cholmod_free_factor(&m.L, &m.common);
    require_memory(estimate, s.str());
  }
}

template <class Scalar>
void BasicCholeskySolver<Scalar>::factorize(const SparseMatrix& A) {
  Impl& m = *impl_;
  if (!m.L && m.n != 0) throw Error(std::string(kWho) + ": factorize() before analyze()");
  detail::check_square_finite(A, kWho);
  if (A.rows() != m.n || detail::pattern_hash(A) != m.pattern) {
    std::ostringstream s;
    s << kWho << ": factorize() got a " << A.rows() << "x" << A.cols() << " matrix with " << A.nonZeros()
      << " nonzeros whose pattern differs from the analyzed one (" << m.n << " rows): call compute()";
    throw Error(s.str());
  }
  m.factorized = false;
  if (m.n == 0) {
    m.factorized = true;
    return;
  }
  cholmod_sparse s = Impl::view(A, m.stype);
  {
    // All cores for the BLAS of a large supernodal factor (blas_threads.hpp); fl: from analyze().
    const bool large = m.options.supernodal && m.common.fl >= kThreadedBlasFactorFlops;
    const ScopedBlasThreads blas(large ? cores() : 1);
    const BlasCallScope call;
    const SerialOpenMPScope serial;  // CHOLMOD's OpenMP regions: plain calls (serial_openmp.hpp)
    cholmod_factorize(&s, m.L, &m.common);
  }
  m.check_status("factorize");
  if (m.common.status == CHOLMOD_NOT_POSDEF || m.L->minor < m.L->n) {
    std::ostringstream why;
    why << "leading minor " << m.L->minor;
    m.throw_not_pd(A, static_cast<long>(m.L->minor), why.str());
  }
  m.check_pivots(A);
  m.factorized = true;
}

template <class Scalar>
void BasicCholeskySolver<Scalar>::compute(const SparseMatrix& A) {
  analyze(A);
  factorize(A);
}

template <class Scalar>
typename BasicCholeskySolver<Scalar>::Matrix BasicCholeskySolver<Scalar>::solve(
    const Eigen::Ref<const Matrix>& B, System system) const {
  Impl& m = *impl_;
  if (!m.factorized) throw Error(std::string(kWho) + ": solve() before a successful factorize()");
  if (B.rows() != m.n) {
    std::ostringstream s;
    s << kWho << ": right-hand side has " << B.rows() << " rows, the matrix " << m.n;
    throw Error(s.str());
  }
  Matrix X(B.rows(), B.cols());
  advise_huge_pages(X.data(), static_cast<std::size_t>(X.size()) * sizeof(Scalar));  // not yet touched
  if (B.size() == 0) return X;
  // L of A = Pᵀ L Lᴴ P from a simplicial LDLᴴ factor L₁ D L₁ᴴ is L₁ D^½: L⁻¹B = D^−½ (L₁⁻¹ B) and
  // L⁻ᴴB = L₁⁻ᴴ (D^−½ B).
  const bool ldl = !m.L->is_ll && (system == System::L || system == System::Lt);
  Matrix scaled;
  const Scalar* bdata = B.data();
  Eigen::Index bstride = B.outerStride();
  if (ldl && system == System::Lt) {
    scaled = B;
    for (Eigen::Index j = 0; j < m.n; ++j) scaled.row(j) /= std::sqrt(m.simplicial_diagonal(j));
    bdata = scaled.data();
    bstride = scaled.rows();
  }
  const int sys = system == System::A    ? CHOLMOD_A
                  : system == System::L  ? CHOLMOD_L
                  : system == System::Lt ? CHOLMOD_Lt
                  : system == System::P  ? CHOLMOD_P
                                         : CHOLMOD_Pt;
  // Columns [j0, j1) of B into X, with `common`'s workspace: CHOLMOD's status, or CHOLMOD_INVALID
  // when it returned no solution without a negative status.
  const auto solve_columns = [&](Eigen::Index j0, Eigen::Index j1, cholmod_common& common) {
    cholmod_dense b{};
    b.nrow = static_cast<size_t>(B.rows());
    b.ncol = static_cast<size_t>(j1 - j0);
    b.d = static_cast<size_t>(bstride);
    b.nzmax = b.d * b.ncol;
    b.x = const_cast<Scalar*>(bdata + j0 * bstride);
    b.xtype = Impl::kXtype;
    b.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* x = nullptr;
    {
      const BlasCallScope call;
      x = cholmod_solve(sys, m.L, &b, &common);
    }
    if (!x) return common.status < 0 ? common.status : CHOLMOD_INVALID;
    const Scalar* xs = static_cast<const Scalar*>(x->x);
    for (Eigen::Index j = j0; j < j1; ++j)
      X.col(j) = Eigen::Map<const Eigen::Matrix<Scalar, Eigen::Dynamic, 1>>(
          xs + (j - j0) * static_cast<Eigen::Index>(x->d), X.rows());
    cholmod_free_dense(&x, &common);
    return common.status;
  };
  // Many right-hand sides against a large factor: the columns in one block per core, each solved on
  // its own thread with its own CHOLMOD workspace (the factor is only read; OpenBLAS stays on one
  // thread per caller). The cage bind's 98 columns against 29M factor nonzeros: 0.77–0.79 s on one
  // core, 0.41–0.45 s on two (docs/performance.md, "Cage bind").
  const Eigen::Index blocks = m.common.lnz * static_cast<double>(B.cols()) < kThreadedSolveWork
                                  ? 1
                                  : std::min<Eigen::Index>(cores(), B.cols() / kColumnsPerThread);
  int status = CHOLMOD_OK;
  if (blocks <= 1) {
    status = solve_columns(0, B.cols(), m.common);
  } else {
    std::vector<int> block_status(static_cast<std::size_t>(blocks), CHOLMOD_OK);
    const auto block = [&](Eigen::Index t) {
      cholmod_common common;
      cholmod_start(&common);
      common.print = 0;
      common.error_handler = nullptr;
      block_status[static_cast<std::size_t>(t)] =
          solve_columns(B.cols() * t / blocks, B.cols() * (t + 1) / blocks, common);
      cholmod_finish(&common);
    };
    std::vector<std::thread> threads;
    Eigen::Index t = 1;
    try {
      for (; t < blocks; ++t)
        threads.emplace_back([&block, t] {
          block_stop_signals_on_this_thread();  // stop signals are the application's (core/interrupt.hpp)
          block(t);
        });
    } catch (const std::system_error&) {  // no thread to be had: the rest of the blocks here
    }
    for (Eigen::Index u = t; u < blocks; ++u) block(u);
    block(0);
    for (auto& thread : threads) thread.join();
    for (int st : block_status) status = std::min(status, st);
  }
  if (status < 0) {
    m.common.status = status;
    m.check_status("solve");
  }
  if (ldl && system == System::L)
    for (Eigen::Index j = 0; j < m.n; ++j) X.row(j) /= std::sqrt(m.simplicial_diagonal(j));
  if (!X.allFinite()) throw numerical_error(std::string(kWho) + ": the solution is not finite");
  return X;
}

template <class Scalar>
Eigen::Index BasicCholeskySolver<Scalar>::rows() const {
  return impl_->n < 0 ? 0 : impl_->n;
}
template <class Scalar>
bool BasicCholeskySolver<Scalar>::analyzed() const {
  return impl_->L != nullptr || impl_->n == 0;
}
template <class Scalar>
bool BasicCholeskySolver<Scalar>::factorized() const {
  return impl_->factorized;
}
template <class Scalar>
double BasicCholeskySolver<Scalar>::factor_nonzeros() const {
  return impl_->L ? impl_->common.lnz : 0.0;
}
template <class Scalar>
double BasicCholeskySolver<Scalar>::factor_flops() const {
  return impl_->L ? impl_->common.fl : 0.0;
}
template <class Scalar>
const typename BasicCholeskySolver<Scalar>::Options& BasicCholeskySolver<Scalar>::options() const {
  return impl_->options;
}

template <class Scalar>
Ordering BasicCholeskySolver<Scalar>::ordering_used() const {
  return impl_->used;
}

template class BasicCholeskySolver<double>;
template class BasicCholeskySolver<std::complex<double>>;

}  // namespace spinmotor
