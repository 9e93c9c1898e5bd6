#include "spinmotor/linalg/lu_solver.hpp"

#include <slu_ddefs.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "solver_detail.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/linalg/blas_threads.hpp"

namespace spinmotor {
namespace {
// Reciprocal condition number below which a factorization is declared numerically singular.
constexpr double kSingularRcond = 1e2 * std::numeric_limits<double>::epsilon();
}  // namespace

struct LUSolver::Impl {
  Options options;
  superlu_options_t slu{};
  Eigen::Index n = -1;
  std::size_t pattern = 0;
  bool analyzed = false, factorized = false;
  std::vector<int> perm_c_analyzed;  // COLAMD (or other) ordering from analyze()
  std::vector<int> perm_c, perm_r, etree;
  SuperMatrix L{}, U{};
  GlobalLU_t glu{};
  double lu_nnz = 0, rcond = 0;

  explicit Impl(const Options& o) : options(o) {
    set_default_options(&slu);
    slu.ColPerm = [&] {
      switch (o.ordering) {
        case Ordering::Natural:
          return NATURAL;
        case Ordering::COLAMD:
          return COLAMD;
        case Ordering::MMD_AtA:
          return MMD_ATA;
        case Ordering::MMD_AtPlusA:
          return MMD_AT_PLUS_A;
        default:  // rejected by the constructor
          return COLAMD;
      }
    }();
    slu.DiagPivotThresh = o.pivot_threshold;
    slu.PrintStat = NO;
    slu.Equil = NO;
  }
  ~Impl() { free_factors(); }

  void free_factors() {
    if (L.Store) Destroy_SuperNode_Matrix(&L);
    if (U.Store) Destroy_CompCol_Matrix(&U);
    L.Store = nullptr;
    U.Store = nullptr;
    factorized = false;
  }

  // SuperLU view of A (no copy): only the Store struct is allocated, freed with Destroy_SuperMatrix_Store.
  static SuperMatrix view(const Eigen::SparseMatrix<double>& A) {
    SuperMatrix s{};
    dCreate_CompCol_Matrix(&s, static_cast<int>(A.rows()), static_cast<int>(A.cols()),
                           static_cast<int>(A.nonZeros()), const_cast<double*>(A.valuePtr()),
                           const_cast<int*>(A.innerIndexPtr()), const_cast<int*>(A.outerIndexPtr()), SLU_NC,
                           SLU_D, SLU_GE);
    return s;
  }

  int superlu_ispec() const {
    switch (options.ordering) {
      case Ordering::Natural:
        return 0;
      case Ordering::MMD_AtA:
        return 1;
      case Ordering::MMD_AtPlusA:
        return 2;
      case Ordering::COLAMD:
      default:
        return 3;
    }
  }

  [[noreturn]] void throw_singular(const Eigen::SparseMatrix<double>& A, int col,
                                   const std::string& why) const {
    const detail::GraphComponents g = detail::matrix_components(A);
    std::ostringstream s;
    s << "LUSolver: matrix is singular (" << why;
    if (col >= 0 && col < static_cast<int>(A.rows()))
      s << "; column " << col << ", in " << detail::describe_component(g, g.label[col], "row", "rows")
        << " of " << g.count() << " of the matrix graph";
    s << ")";
    throw numerical_error(s.str());
  }
};

LUSolver::LUSolver() : LUSolver(Options{}) {}
LUSolver::LUSolver(const Options& options) : impl_(std::make_unique<Impl>(options)) {
  require_ordering(options.ordering, kOrderings, "LUSolver");
  if (!(options.pivot_threshold >= 0.0 && options.pivot_threshold <= 1.0)) {
    std::ostringstream s;
    s << "LUSolver: pivot_threshold must be in [0, 1], got " << options.pivot_threshold;
    throw Error(s.str());
  }
}
LUSolver::~LUSolver() = default;
LUSolver::LUSolver(LUSolver&&) noexcept = default;
LUSolver& LUSolver::operator=(LUSolver&&) noexcept = default;

void LUSolver::analyze(const Eigen::SparseMatrix<double>& A) {
  Impl& m = *impl_;
  m.analyzed = false;
  detail::check_square_finite(A, "LUSolver");
  m.free_factors();
  m.n = A.rows();
  m.pattern = detail::pattern_hash(A);
  m.perm_c_analyzed.assign(static_cast<size_t>(m.n), 0);
  // SuperLU's pivot search reads past the column for a structurally singular matrix (no candidate
  // row left): reject those here, naming a column that no pivot sequence can cover.
  if (const int col = detail::structurally_singular_column(A); col >= 0) {
    std::ostringstream why;
    why << "structurally singular, column " << col
        << (A.outerIndexPtr()[col] == A.outerIndexPtr()[col + 1] ? " is empty"
                                                                 : " cannot be given a pivot row");
    m.throw_singular(A, col, why.str());
  }
  if (m.n > 0) {
    SuperMatrix s = Impl::view(A);
    get_perm_c(m.superlu_ispec(), &s, m.perm_c_analyzed.data());
    Destroy_SuperMatrix_Store(&s);
  }
  m.analyzed = true;
}

void LUSolver::factorize(const Eigen::SparseMatrix<double>& A) {
  Impl& m = *impl_;
  if (!m.analyzed) throw Error("LUSolver: factorize() before analyze()");
  detail::check_square_finite(A, "LUSolver");
  if (A.rows() != m.n || detail::pattern_hash(A) != m.pattern) {
    std::ostringstream s;
    s << "LUSolver: factorize() got a " << A.rows() << "x" << A.cols() << " matrix with " << A.nonZeros()
      << " nonzeros whose pattern differs from the analyzed one (" << m.n << " rows): call compute()";
    throw Error(s.str());
  }
  m.free_factors();
  if (m.n == 0) {
    m.factorized = true;
    return;
  }
  const int n = static_cast<int>(m.n);
  m.perm_c = m.perm_c_analyzed;  // sp_preorder postorders perm_c in place
  m.perm_r.assign(n, 0);
  m.etree.assign(n, 0);
  SuperMatrix s = Impl::view(A), AC{};
  m.slu.Fact = DOFACT;
  sp_preorder(&m.slu, &s, m.perm_c.data(), m.etree.data(), &AC);
  SuperLUStat_t stat;
  StatInit(&stat);
  int info = 0;
  const BlasCallScope call;  // SuperLU's BLAS (blas_threads.hpp)
  dgstrf(&m.slu, &AC, sp_ienv(2), sp_ienv(1), m.etree.data(), nullptr, 0, m.perm_c.data(), m.perm_r.data(),
         &m.L, &m.U, &m.glu, &stat, &info);
  Destroy_CompCol_Permuted(&AC);
  if (info > 0 && info <= n) {  // U(info−1, info−1) is exactly zero
    StatFree(&stat);
    Destroy_SuperMatrix_Store(&s);
    int col = -1;
    for (int i = 0; i < n; ++i)
      if (m.perm_c[i] == info - 1) col = i;
    m.free_factors();
    std::ostringstream why;
    why << "SuperLU: U(" << info - 1 << "," << info - 1 << ") is exactly zero";
    m.throw_singular(A, col, why.str());
  }
  if (info != 0) {
    StatFree(&stat);
    Destroy_SuperMatrix_Store(&s);
    m.free_factors();
    std::ostringstream e;
    e << "LUSolver: SuperLU dgstrf failed (info " << info << (info > n ? ": out of memory" : "") << ")";
    throw numerical_error(e.str());
  }
  m.lu_nnz = static_cast<double>(static_cast<SCformat*>(m.L.Store)->nnz) +
             static_cast<double>(static_cast<NCformat*>(m.U.Store)->nnz);
  // Reciprocal condition number in the 1-norm (a few triangular solves): catches matrices that are
  // singular up to roundoff, whose pivots are tiny but not exactly zero.
  double anorm = 0;
  for (int j = 0; j < n; ++j) {
    double c = 0;
    for (int k = A.outerIndexPtr()[j]; k < A.outerIndexPtr()[j + 1]; ++k) c += std::abs(A.valuePtr()[k]);
    anorm = std::max(anorm, c);
  }
  char norm[] = "1";
  dgscon(norm, &m.L, &m.U, anorm, &m.rcond, &stat, &info);
  StatFree(&stat);
  Destroy_SuperMatrix_Store(&s);
  if (!(m.rcond >= kSingularRcond)) {
    // Name the column of the smallest pivot |U(k,k)| (stored in the supernodes of L).
    const SCformat* Ls = static_cast<const SCformat*>(m.L.Store);
    const double* x = static_cast<const double*>(Ls->nzval);
    int kmin = 0;
    double dmin = std::numeric_limits<double>::infinity();
    for (int sn = 0; sn <= Ls->nsuper; ++sn) {
      const int fsupc = Ls->sup_to_col[sn];
      for (int k = fsupc; k < Ls->sup_to_col[sn + 1]; ++k) {
        const double d = std::abs(x[Ls->nzval_colptr[k] + (k - fsupc)]);
        if (d < dmin) dmin = d, kmin = k;
      }
    }
    int col = -1;
    for (int i = 0; i < n; ++i)
      if (m.perm_c[i] == kmin) col = i;
    m.free_factors();
    std::ostringstream why;
    why << "SuperLU: numerically singular, rcond " << m.rcond << ", smallest pivot " << dmin;
    m.throw_singular(A, col, why.str());
  }
  m.factorized = true;
}

void LUSolver::compute(const Eigen::SparseMatrix<double>& A) {
  analyze(A);
  factorize(A);
}

Eigen::MatrixXd LUSolver::solve(const Eigen::Ref<const Eigen::MatrixXd>& B) const {
  Impl& m = *impl_;
  if (!m.factorized) throw Error("LUSolver: solve() before a successful factorize()");
  if (B.rows() != m.n) {
    std::ostringstream s;
    s << "LUSolver: right-hand side has " << B.rows() << " rows, the matrix " << m.n;
    throw Error(s.str());
  }
  Eigen::MatrixXd X = B;  // dgstrs overwrites the right-hand side with the solution
  if (X.size() == 0) return X;
  SuperMatrix b{};
  dCreate_Dense_Matrix(&b, static_cast<int>(X.rows()), static_cast<int>(X.cols()), X.data(),
                       static_cast<int>(X.rows()), SLU_DN, SLU_D, SLU_GE);
  SuperLUStat_t stat;
  StatInit(&stat);
  int info = 0;
  const BlasCallScope call;  // SuperLU's BLAS (blas_threads.hpp)
  dgstrs(NOTRANS, &m.L, &m.U, m.perm_c.data(), m.perm_r.data(), &b, &stat, &info);
  StatFree(&stat);
  Destroy_SuperMatrix_Store(&b);
  if (info != 0) {
    std::ostringstream s;
    s << "LUSolver: SuperLU dgstrs failed (info " << info << ")";
    throw numerical_error(s.str());
  }
  if (!X.allFinite()) throw numerical_error("LUSolver: the solution is not finite");
  return X;
}

Eigen::Index LUSolver::rows() const { return impl_->n < 0 ? 0 : impl_->n; }
bool LUSolver::analyzed() const { return impl_->analyzed; }
bool LUSolver::factorized() const { return impl_->factorized; }
double LUSolver::factor_nonzeros() const { return impl_->factorized ? impl_->lu_nnz : 0.0; }
double LUSolver::rcond() const { return impl_->factorized ? impl_->rcond : 0.0; }
const LUSolver::Options& LUSolver::options() const { return impl_->options; }

}  // namespace spinmotor
