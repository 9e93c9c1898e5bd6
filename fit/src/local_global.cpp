// The local/global solver (local_global.hpp).
#include "spinmotor/fit/local_global.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/core/stopwatch.hpp"

namespace spinmotor::fit {

namespace {

using Clock = std::chrono::steady_clock;
using Vec3 = Eigen::Vector3d;

double face_volume(const Vec3& a, const Vec3& b, const Vec3& c) { return a.dot(b.cross(c)) / 6.0; }
double face_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * (b - a).cross(c - a).norm(); }

}  // namespace

/// The equality row: the faces with a free vertex, the incidences of each free vertex (in the rows'
/// order) and the fixed faces (every corner constrained), whose measure is constant during a solve.
struct MeasureRow {
  MeasureKind kind = MeasureKind::None;
  Eigen::MatrixXi F;
  std::vector<int> active, fixed;        // face indices
  std::vector<int> inc_offset;           // free row r -> [inc_offset[r], inc_offset[r+1])
  std::vector<std::pair<int, int>> inc;  // (face, corner)

  double face(const RowMatrix3& X, int f) const {
    const Vec3 a = X.row(F(f, 0)), b = X.row(F(f, 1)), c = X.row(F(f, 2));
    return kind == MeasureKind::Volume ? face_volume(a, b, c) : face_area(a, b, c);
  }
  double over(const RowMatrix3& X, const std::vector<int>& faces) const {
    double s = 0;
    const long m = static_cast<long>(faces.size());
#pragma omp parallel for schedule(static) reduction(+ : s) if (parallel::worth(m, parallel::kMotorBlend))
    for (long k = 0; k < m; ++k) s += face(X, faces[k]);
    return s;
  }
  /// g_r = ∂measure/∂x_i for the free vertex i of row r: volume Σ_{f∋i} v_j × v_k / 6, area
  /// Σ_{f∋i} ½ n_f × (v_k − v_j) ((i, j, k) the face's corners counter-clockwise).
  void gradient(const RowMatrix3& X, RowMatrix3& g) const {
    const long nf = static_cast<long>(inc_offset.size()) - 1;
#pragma omp parallel for schedule(static) if (parallel::worth(nf, parallel::kMotorBlend))
    for (long r = 0; r < nf; ++r) {
      Vec3 s = Vec3::Zero();
      for (int q = inc_offset[r]; q < inc_offset[r + 1]; ++q) {
        const auto [f, corner] = inc[q];
        const Vec3 vj = X.row(F(f, (corner + 1) % 3)), vk = X.row(F(f, (corner + 2) % 3));
        if (kind == MeasureKind::Volume) {
          s += vj.cross(vk) / 6.0;
        } else {
          const Vec3 vi = X.row(F(f, corner));
          const Vec3 nv = (vj - vi).cross(vk - vi);
          const double len = nv.norm();
          if (len > 0) s += 0.5 * (nv / len).cross(vk - vj);
        }
      }
      g.row(r) = s.transpose();
    }
  }
};

struct LocalGlobal::Impl {
  Eigen::Index n = 0;
  DirichletSolver solver;
  Eigen::VectorXd attraction;  // empty: none
  MeasureRow measure;
  // per-solve scratch
  RowMatrix3 FCX, B, G;
  Eigen::MatrixXd rhs;  // nf × 3 or 6
};

LocalGlobal::LocalGlobal() : impl_(std::make_unique<Impl>()) {}
LocalGlobal::~LocalGlobal() = default;
LocalGlobal::LocalGlobal(LocalGlobal&&) noexcept = default;
LocalGlobal& LocalGlobal::operator=(LocalGlobal&&) noexcept = default;

void LocalGlobal::bind(const Bind& b) {
  Impl& m = *impl_;
  m.n = b.L.rows();
  if (b.L.cols() != m.n) throw Error("LocalGlobal: the global matrix is not square");
  if (b.attraction.size() != 0 && b.attraction.size() != m.n)
    throw Error("LocalGlobal: " + std::to_string(b.attraction.size()) + " attraction values for " +
                std::to_string(m.n) + " vertices");
  Eigen::SparseMatrix<double> A = b.L;
  std::vector<char> anchors(static_cast<size_t>(m.n), 0);
  m.attraction = b.attraction;
  for (Eigen::Index i = 0; i < b.attraction.size(); ++i)
    if (b.attraction[i] > 0) A.coeffRef(i, i) += b.attraction[i], anchors[i] = 1;
  A.makeCompressed();
  m.solver = DirichletSolver(b.solver);
  if (b.free_order.size() > 0) {
    m.solver.bind(A, b.constrained, b.free_order, DirichletSolver::Kind::SPD);
  } else if (b.attraction.size() > 0) {
    m.solver.bind(A, b.constrained, DirichletSolver::Kind::SPD, anchors);
  } else {
    m.solver.bind(A, b.constrained, DirichletSolver::Kind::SPD);
  }
  // The equality row's faces and incidences.
  m.measure = MeasureRow{};
  m.measure.kind = b.measure;
  m.measure.F = b.F;
  std::vector<int> row(static_cast<size_t>(m.n), -1);
  const Eigen::VectorXi& fr = m.solver.free();
  for (Eigen::Index r = 0; r < fr.size(); ++r) row[fr[r]] = static_cast<int>(r);
  m.measure.inc_offset.assign(static_cast<size_t>(fr.size()) + 1, 0);
  if (b.measure == MeasureKind::None) return;
  for (Eigen::Index f = 0; f < b.F.rows(); ++f) {
    const bool active = row[b.F(f, 0)] >= 0 || row[b.F(f, 1)] >= 0 || row[b.F(f, 2)] >= 0;
    (active ? m.measure.active : m.measure.fixed).push_back(static_cast<int>(f));
    for (int c = 0; c < 3 && active; ++c)
      if (row[b.F(f, c)] >= 0) ++m.measure.inc_offset[row[b.F(f, c)] + 1];
  }
  for (size_t r = 0; r + 1 < m.measure.inc_offset.size(); ++r)
    m.measure.inc_offset[r + 1] += m.measure.inc_offset[r];
  m.measure.inc.resize(m.measure.inc_offset.back());
  std::vector<int> fill(m.measure.inc_offset.begin(), m.measure.inc_offset.end() - 1);
  for (const int f : m.measure.active)
    for (int c = 0; c < 3; ++c)
      if (const int r = row[b.F(f, c)]; r >= 0) m.measure.inc[fill[r]++] = {f, c};
}

double total_measure(MeasureKind kind, const Eigen::MatrixXi& F, const RowMatrix3& X) {
  const bool vol = kind == MeasureKind::Volume;
  double s = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 a = X.row(F(f, 0)), b = X.row(F(f, 1)), c = X.row(F(f, 2));
    s += vol ? face_volume(a, b, c) : face_area(a, b, c);
  }
  return s;
}

double LocalGlobal::measure(const RowMatrix3& X) const {
  return total_measure(impl_->measure.kind, impl_->measure.F, X);
}

Eigen::Index LocalGlobal::rows() const { return impl_->n; }
const Eigen::VectorXi& LocalGlobal::free() const { return impl_->solver.free(); }
const Eigen::VectorXi& LocalGlobal::constrained() const { return impl_->solver.constrained(); }
const DirichletSolver& LocalGlobal::dirichlet() const { return impl_->solver; }

namespace {

/// Anderson acceleration's state over the free coordinates (local_global.hpp).
struct Anderson {
  int depth = 0, hist = 0, slot = 0;
  bool have_prev = false, accelerated = false;
  Eigen::VectorXd x, Gk, f, f_prev, G_prev, G_last;
  Eigen::MatrixXd dF, dG;

  Anderson(int m, Eigen::Index N) : depth(std::max(0, m)), dF(N, std::max(0, m)), dG(N, std::max(0, m)) {}
  void restart() { hist = 0, slot = 0, have_prev = false; }
  /// After a global step from x to G_k: record the step (when plain) and, with a history, the accelerated
  /// point into `out` (returns whether it did).
  bool step(bool plain, Eigen::VectorXd& out) {
    f = Gk - x;
    if (have_prev && plain) {
      dF.col(slot) = f - f_prev;
      dG.col(slot) = Gk - G_prev;
      slot = (slot + 1) % depth;
      hist = std::min(hist + 1, depth);
    }
    f_prev = f;
    G_prev = Gk;
    have_prev = true;
    if (hist == 0) return false;
    const Eigen::MatrixXd A = dF.leftCols(hist);
    const Eigen::VectorXd gamma = A.colPivHouseholderQr().solve(f);
    if (!gamma.allFinite()) return false;
    G_last = Gk;
    out = Gk - dG.leftCols(hist) * gamma;
    return true;
  }
};

void gather(const RowMatrix3& X, const Eigen::VectorXi& free, Eigen::VectorXd& x) {
  x.resize(3 * free.size());
  for (Eigen::Index r = 0; r < free.size(); ++r) x.segment<3>(3 * r) = X.row(free[r]).transpose();
}
void scatter(const Eigen::VectorXd& x, const Eigen::VectorXi& free, RowMatrix3& X) {
  for (Eigen::Index r = 0; r < free.size(); ++r) X.row(free[r]) = x.segment<3>(3 * r).transpose();
}

}  // namespace

SolveReport LocalGlobal::solve(Problem& problem, RowMatrix3& X, const RowMatrix3& values,
                               const RowMatrix3* targets, double measure_target, const SolveOptions& o) {
  Impl& m = *impl_;
  const Eigen::VectorXi& free = m.solver.free();
  const Eigen::VectorXi& cons = m.solver.constrained();
  const Eigen::Index nf = free.size();
  if (X.rows() != m.n || values.rows() != cons.size())
    throw Error("LocalGlobal: " + std::to_string(X.rows()) + " positions and " +
                std::to_string(values.rows()) + " constrained values for " + std::to_string(m.n) +
                " vertices and " + std::to_string(cons.size()) + " constraints");
  const bool attracted = m.attraction.size() > 0;
  if (attracted && (!targets || targets->rows() != m.n))
    throw Error("LocalGlobal: the attraction needs n targets");
  SolveReport r;
  for (Eigen::Index k = 0; k < cons.size(); ++k) X.row(cons[k]) = values.row(k);
  m.FCX.noalias() = m.solver.free_constrained_block() * values;  // the constrained vertices' share, once
  const bool constrained = m.measure.kind != MeasureKind::None;
  const double fixed = constrained ? m.measure.over(X, m.measure.fixed) : 0.0;
  if (m.B.rows() != nf) m.B.setZero(nf, 3);
  if (constrained && m.G.rows() != nf) m.G.setZero(nf, 3);
  m.rhs.resize(nf, constrained ? 6 : 3);
  Anderson acc(o.anderson, 3 * nf);
  double e_prev = -1;
  bool finishing = false;
  for (int it = 0;; ++it) {
    auto t0 = Clock::now();
    double e = problem.fit(X, it, r);
    if (acc.accelerated && e > e_prev) {  // the accelerated step raised the energy: back to the plain one
      scatter(acc.G_last, free, X);
      acc.restart();
      ++r.rejected_accelerations;
      e = problem.fit(X, it, r);
      acc.accelerated = false;
    }
    r.local_ms += ms_since(t0);
    if (!std::isfinite(e)) {
      std::ostringstream s;
      s << "LocalGlobal: the energy is not finite at iteration " << it;
      throw numerical_error(s.str());
    }
    r.energy.push_back(e);
    bool stop = e <= 1e-24 * problem.energy_scale();
    if (it > 0 && std::abs(e - e_prev) <= o.tolerance * std::max(e, e_prev)) stop = true;
    e_prev = e;
    if (finishing) {  // the plain step after a stop at an accelerated point
      r.converged = true;
      break;
    }
    if (stop || it >= o.max_iterations || nf == 0) {
      // Stopped at an accelerated point: one plain step from it, so that the positions returned are a
      // plain iterate (they meet the linearised row) and the last energy reported is theirs.
      if (stop && acc.accelerated && nf > 0) {
        finishing = true;
      } else {
        r.converged = stop || nf == 0;
        break;
      }
    }
    acc.accelerated = false;
    const auto t_global = Clock::now();
    t0 = t_global;
    problem.rhs(it, *this, m.B);
    m.B -= m.FCX;
    if (attracted)
      for (Eigen::Index k = 0; k < nf; ++k) m.B.row(k) += m.attraction[free[k]] * targets->row(free[k]);
    m.rhs.leftCols<3>() = m.B;
    double row_rhs = 0;
    if (constrained) {
      m.measure.gradient(X, m.G);
      double gX = 0;
      for (Eigen::Index k = 0; k < nf; ++k) gX += m.G.row(k).dot(X.row(free[k]));
      row_rhs = measure_target - (fixed + m.measure.over(X, m.measure.active)) + gX;
      m.rhs.rightCols<3>() = m.G;
    }
    r.rhs_ms += ms_since(t0);
    t0 = Clock::now();
    const Eigen::MatrixXd XF = m.solver.solve_free(m.rhs);
    r.solve_ms += ms_since(t0);
    double mu = 0;
    if (constrained) {
      double ga = 0, gg = 0;
      for (Eigen::Index k = 0; k < nf; ++k) {
        ga += m.G.row(k).dot(XF.row(k).head<3>());
        gg += m.G.row(k).dot(XF.row(k).tail<3>());
      }
      if (gg > 0) mu = (ga - row_rhs) / gg;
    }
    if (acc.depth > 0 && !finishing) gather(X, free, acc.x);
    for (Eigen::Index k = 0; k < nf; ++k) {
      X.row(free[k]) = XF.row(k).head<3>();
      if (constrained) X.row(free[k]) -= mu * XF.row(k).tail<3>();
    }
    // The last step allowed (and a finishing one) stays plain, so the iteration never ends accelerated.
    if (acc.depth > 0 && !finishing && it + 1 < o.max_iterations) {
      gather(X, free, acc.Gk);
      Eigen::VectorXd next;
      if (acc.step(problem.plain_step(it), next)) {
        scatter(next, free, X);
        acc.accelerated = true;
      }
    }
    r.global_ms += ms_since(t_global);
    ++r.iterations;
    problem.after_step(X, it);
  }
  return r;
}

}  // namespace spinmotor::fit
