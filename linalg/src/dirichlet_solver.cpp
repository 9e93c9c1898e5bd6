#include "spinmotor/linalg/dirichlet_solver.hpp"

#include <algorithm>
#include <optional>
#include <sstream>
#include <vector>

#include "solver_detail.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/huge_pages.hpp"

namespace spinmotor {

struct DirichletSolver::Impl {
  Options options;
  Kind kind = Kind::SPD;
  Eigen::Index n = -1;
  Eigen::VectorXi constrained, free;
  Eigen::SparseMatrix<double> A_FC;  // free rows, constrained columns
  std::optional<CholeskySolver> cholesky;
  std::optional<LUSolver> lu;
};

DirichletSolver::DirichletSolver() : DirichletSolver(Options{}) {}
DirichletSolver::DirichletSolver(const Options& options) : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
}
DirichletSolver::~DirichletSolver() = default;
DirichletSolver::DirichletSolver(DirichletSolver&&) noexcept = default;
DirichletSolver& DirichletSolver::operator=(DirichletSolver&&) noexcept = default;

namespace {
// Sorts the row indices (with their values) of every column: extraction in a caller-given order
// leaves them unsorted, and CHOLMOD and SuperLU read sorted columns. Columns are short (a vertex's
// one-ring): insertion sort.
void sort_columns(Eigen::SparseMatrix<double>& S) {
  int* inner = S.innerIndexPtr();
  double* value = S.valuePtr();
  for (Eigen::Index j = 0; j < S.outerSize(); ++j) {
    const int b = S.outerIndexPtr()[j], e = S.outerIndexPtr()[j + 1];
    for (int k = b + 1; k < e; ++k) {
      const int r = inner[k];
      const double v = value[k];
      int t = k;
      for (; t > b && inner[t - 1] > r; --t) inner[t] = inner[t - 1], value[t] = value[t - 1];
      inner[t] = r, value[t] = v;
    }
  }
}
}  // namespace

void DirichletSolver::bind(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& constrained,
                           Kind kind) {
  bind_impl(A, constrained, nullptr, kind);
}

void DirichletSolver::bind(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& constrained,
                           Kind kind, const std::vector<char>& anchors) {
  if (static_cast<Eigen::Index>(anchors.size()) != A.rows())
    throw Error("DirichletSolver: " + std::to_string(anchors.size()) + " anchor flags for " +
                std::to_string(A.rows()) + " unknowns");
  bind_impl(A, constrained, nullptr, kind, &anchors);
}

void DirichletSolver::bind(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& constrained,
                           const Eigen::VectorXi& free_order, Kind kind) {
  bind_impl(A, constrained, &free_order, kind);
}

namespace {

/// slot[i] = position among the free (≥ 0, assigned later) or −1 − position among the constrained
/// unknowns; range and repeat checks of `constrained`.
std::vector<int> constrained_slots(int n, const Eigen::VectorXi& constrained) {
  std::vector<int> slot(n, 0);
  for (Eigen::Index r = 0; r < constrained.size(); ++r) {
    const int i = constrained[r];
    if (i < 0 || i >= n) {
      std::ostringstream s;
      s << "DirichletSolver: constrained index " << r << " is " << i << ", out of range [0, " << n << ")";
      throw Error(s.str());
    }
    if (slot[i] != 0) {
      std::ostringstream s;
      s << "DirichletSolver: vertex " << i << " is constrained twice (constrained indices " << (-1 - slot[i])
        << " and " << r << ")";
      throw Error(s.str());
    }
    slot[i] = -1 - static_cast<int>(r);
  }
  return slot;
}

/// Every connected component of the matrix graph needs a constrained vertex (or an anchor), else A_FF
/// is singular: FloatingComponentError naming the first that has none.
void check_anchored(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& constrained,
                    const std::vector<char>* anchors) {
  const detail::GraphComponents g = detail::matrix_components(A);
  std::vector<char> anchored(g.count(), 0);
  for (Eigen::Index r = 0; r < constrained.size(); ++r) anchored[g.label[constrained[r]]] = 1;
  if (anchors)
    for (Eigen::Index i = 0; i < A.rows(); ++i)
      if ((*anchors)[i]) anchored[g.label[i]] = 1;
  std::vector<FloatingComponentError::Component> floating;
  for (int c = 0; c < g.count(); ++c)
    if (!anchored[c]) floating.push_back({c, g.size[c], g.first[c]});
  if (floating.empty()) return;
  // The message first: the vector is moved into the exception.
  const std::string what =
      "DirichletSolver: " + detail::describe_component(g, floating[0].id, "vertex", "vertices") + " of " +
      std::to_string(g.count()) + " has no constrained vertex: its values are undetermined";
  throw FloatingComponentError(what, std::move(floating), g.count());
}

/// The free unknowns in the caller's order (checked) or increasing; fills their slots. Returns whether
/// the order is increasing.
bool number_free(const Eigen::VectorXi* free_order, std::vector<int>& slot, Eigen::VectorXi& free) {
  const int n = static_cast<int>(slot.size());
  int nf = 0;
  bool sorted = true;
  if (!free_order) {
    for (int i = 0; i < n; ++i)
      if (slot[i] == 0) free[nf] = i, slot[i] = nf++;
    return true;
  }
  if (free_order->size() != free.size()) {
    std::ostringstream s;
    s << "DirichletSolver: the free order has " << free_order->size()
      << " indices, expected n - c = " << free.size();
    throw Error(s.str());
  }
  for (Eigen::Index r = 0; r < free_order->size(); ++r) {
    const int i = (*free_order)[r];
    if (i < 0 || i >= n || slot[i] != 0) {
      std::ostringstream s;
      s << "DirichletSolver: free order index " << r << " is " << i
        << (i < 0 || i >= n ? ", out of range" : ", constrained or listed twice");
      throw Error(s.str());
    }
    free[nf] = i, slot[i] = nf++;
    sorted = sorted && (r == 0 || i > (*free_order)[r - 1]);
  }
  return sorted;
}

/// A_FF and A_FC in compressed column storage, one pass over A (rows stay sorted when the free order is
/// increasing: the maps are monotone on the free unknowns; A_FC columns follow the order of
/// `constrained`).
void extract_blocks(const Eigen::SparseMatrix<double>& A, const std::vector<int>& slot, int nf, int nc,
                    bool sorted, Eigen::SparseMatrix<double>& A_FF, Eigen::SparseMatrix<double>& A_FC) {
  const int n = static_cast<int>(A.rows());
  A_FF.resize(nf, nf);
  A_FC.resize(nf, nc);
  std::vector<int> ff_outer(nf + 1, 0), fc_outer(nc + 1, 0);
  for (int j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      if (slot[it.row()] < 0) continue;
      if (slot[j] >= 0)
        ++ff_outer[slot[j] + 1];
      else
        ++fc_outer[-slot[j]];  // −1 − pos + 1
    }
  for (int j = 0; j < nf; ++j) ff_outer[j + 1] += ff_outer[j];
  for (int j = 0; j < nc; ++j) fc_outer[j + 1] += fc_outer[j];
  A_FF.resizeNonZeros(ff_outer[nf]);
  A_FC.resizeNonZeros(fc_outer[nc]);
  // Fresh memory, written whole below: faulted in by one system call each (core/huge_pages.hpp).
  prepare_fresh(A_FF.innerIndexPtr(), sizeof(int) * static_cast<std::size_t>(ff_outer[nf]));
  prepare_fresh(A_FF.valuePtr(), sizeof(double) * static_cast<std::size_t>(ff_outer[nf]));
  std::copy(ff_outer.begin(), ff_outer.end(), A_FF.outerIndexPtr());
  std::copy(fc_outer.begin(), fc_outer.end(), A_FC.outerIndexPtr());
  for (int j = 0; j < n; ++j) {  // ff_outer / fc_outer now serve as per-column write cursors
    const bool jf = slot[j] >= 0;
    Eigen::SparseMatrix<double>& T = jf ? A_FF : A_FC;
    std::vector<int>& cursor = jf ? ff_outer : fc_outer;
    int& pos = cursor[jf ? slot[j] : -1 - slot[j]];
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      if (slot[it.row()] < 0) continue;
      T.innerIndexPtr()[pos] = slot[it.row()];
      T.valuePtr()[pos] = it.value();
      ++pos;
    }
  }
  if (!sorted) {  // rows follow the caller's order: sort each column
    sort_columns(A_FF);
    sort_columns(A_FC);
  }
}

}  // namespace

void DirichletSolver::bind_impl(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& constrained,
                                const Eigen::VectorXi* free_order, Kind kind,
                                const std::vector<char>* anchors) {
  Impl& m = *impl_;
  m.n = -1;
  m.cholesky.reset();
  m.lu.reset();
  detail::check_square_finite(A, "DirichletSolver");
  const int n = static_cast<int>(A.rows());
  std::vector<int> slot = constrained_slots(n, constrained);
  check_anchored(A, constrained, anchors);
  m.free.resize(n - constrained.size());
  const bool sorted = number_free(free_order, slot, m.free);
  Eigen::SparseMatrix<double> A_FF;
  extract_blocks(A, slot, static_cast<int>(m.free.size()), static_cast<int>(constrained.size()), sorted, A_FF,
                 m.A_FC);
  m.kind = kind;
  m.constrained = constrained;
  try {
    if (kind == Kind::SPD) {
      m.cholesky.emplace(m.options.cholesky);
      m.cholesky->compute(A_FF);
    } else {
      m.lu.emplace(m.options.lu);
      m.lu->compute(A_FF);
    }
  } catch (const Error& e) {
    m.cholesky.reset();
    m.lu.reset();
    // The solver names rows of A_FF: translate to the caller's indexing in the message.
    throw Error(std::string("DirichletSolver: factorizing the free block A_FF failed (free row r is vertex "
                            "free()[r]): ") +
                    e.what(),
                e.kind());
  }
  m.n = n;
}

Eigen::MatrixXd DirichletSolver::solve(const Eigen::Ref<const Eigen::MatrixXd>& B,
                                       const Eigen::Ref<const Eigen::MatrixXd>& values) const {
  const Impl& m = *impl_;
  if (m.n < 0) throw Error("DirichletSolver: solve() before a successful bind()");
  const Eigen::Index nc = m.constrained.size(), k = values.cols();
  if (values.rows() != nc) {
    std::ostringstream s;
    s << "DirichletSolver: values have " << values.rows() << " rows, expected one per constrained vertex ("
      << nc << ")";
    throw Error(s.str());
  }
  const bool zero_rhs = B.size() == 0;
  if (!zero_rhs && (B.rows() != m.n || B.cols() != k)) {
    std::ostringstream s;
    s << "DirichletSolver: right-hand side is " << B.rows() << "x" << B.cols() << ", expected " << m.n << "x"
      << k << " (or empty for B = 0)";
    throw Error(s.str());
  }
  if (!values.allFinite()) throw Error("DirichletSolver: constrained values are not finite");
  Eigen::MatrixXd X(m.n, k);
  for (Eigen::Index r = 0; r < nc; ++r) X.row(m.constrained[r]) = values.row(r);
  const Eigen::Index nf = m.free.size();
  if (nf == 0 || k == 0) return X;
  Eigen::MatrixXd rhs = -(m.A_FC * values);
  if (!zero_rhs)
    for (Eigen::Index r = 0; r < nf; ++r) rhs.row(r) += B.row(m.free[r]);
  const Eigen::MatrixXd xf = m.kind == Kind::SPD ? m.cholesky->solve(rhs) : m.lu->solve(rhs);
  for (Eigen::Index r = 0; r < nf; ++r) X.row(m.free[r]) = xf.row(r);
  return X;
}

Eigen::MatrixXd DirichletSolver::solve(const Eigen::Ref<const Eigen::MatrixXd>& values) const {
  return solve(Eigen::MatrixXd(), values);
}

Eigen::MatrixXd DirichletSolver::solve_free(const Eigen::Ref<const Eigen::MatrixXd>& rhs_F) const {
  const Impl& m = *impl_;
  if (m.n < 0) throw Error("DirichletSolver: solve_free() before a successful bind()");
  if (rhs_F.rows() != m.free.size()) {
    std::ostringstream s;
    s << "DirichletSolver: free right-hand side has " << rhs_F.rows()
      << " rows, expected one per free unknown (" << m.free.size() << ")";
    throw Error(s.str());
  }
  if (m.free.size() == 0) return Eigen::MatrixXd(0, rhs_F.cols());
  return m.kind == Kind::SPD ? m.cholesky->solve(rhs_F) : m.lu->solve(rhs_F);
}

const Eigen::SparseMatrix<double>& DirichletSolver::free_constrained_block() const { return impl_->A_FC; }

const CholeskySolver& DirichletSolver::cholesky() const {
  if (impl_->n < 0 || !impl_->cholesky)
    throw Error("DirichletSolver: cholesky() needs a bind() with Kind::SPD");
  return *impl_->cholesky;
}

Eigen::Index DirichletSolver::rows() const { return impl_->n < 0 ? 0 : impl_->n; }
bool DirichletSolver::bound() const { return impl_->n >= 0; }
const Eigen::VectorXi& DirichletSolver::constrained() const { return impl_->constrained; }
const Eigen::VectorXi& DirichletSolver::free() const { return impl_->free; }

}  // namespace spinmotor
