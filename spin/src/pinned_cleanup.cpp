// Pose-keeping conformal cleanup: local/global ASAP with pins and a volume (or area) multiplier.
// See pinned_cleanup.hpp for the equations.
#include "spinmotor/spin/pinned_cleanup.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/linalg/dirichlet_solver.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/face_geometry.hpp"  // kDegenerateFace
#include "spinmotor/mesh/mass_matrix.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/mesh/topology.hpp"

namespace spinmotor {

namespace detail {

/// Rest data of a face with at least one free corner. (In a named namespace: PinnedCleanup::Impl,
/// which has external linkage, holds a vector of them.)
struct PinnedActiveFace {
  std::array<int, 3> v;        // corner vertices
  double area;                 // rest area A_f
  std::array<double, 6> grad;  // rest gradients ∇φ_i in the rest frame (b1, b2): (x0, y0, x1, y1, x2, y2)
  Eigen::Vector3d b1, b2;      // orthonormal frame of the rest plane (the collapsed-face fallback at k = 0)
};

}  // namespace detail

namespace {

using Vec3 = Eigen::Vector3d;
using Clock = std::chrono::steady_clock;
using ActiveFace = detail::PinnedActiveFace;

inline bool collapsed(const Vec3& e1, const Vec3& e2, const Vec3& e3, const Vec3& nv) {
  const double l2 = std::max({e1.squaredNorm(), e2.squaredNorm(), e3.squaredNorm()});
  return !(nv.norm() > kDegenerateFace * l2);
}

/// The proper rotation R maximising tr(R S) (S = Σ w e e'ᵀ): with S = U Σ Wᵀ, R = W diag(1, 1, ±1) Uᵀ.
/// Fast path from the eigenvectors of S Sᵀ = U Σ² Uᵀ (closed-form 3×3 solver): u1, u2 the top two,
/// w_k = Sᵀ u_k / σ_k, and the proper completion R = w1 u1ᵀ + w2 u2ᵀ + (w1 × w2)(u1 × u2)ᵀ, which maps
/// the two leading singular directions as the SVD does and is a rotation by construction (it needs
/// only σ2 > 0: flat one-rings, rank 2, are the common case). Falls back to a Jacobi SVD when σ2 is
/// tiny or the fast result is not orthonormal to 1e-10.
Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& S) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(S * S.transpose());
  const Eigen::Vector3d lam = es.eigenvalues();  // increasing
  const double scale = lam[2];
  if (scale > 0 && lam[1] > 1e-16 * scale) {
    const Vec3 u1 = es.eigenvectors().col(2), u2 = es.eigenvectors().col(1);
    const Vec3 w1 = (S.transpose() * u1).normalized(), w2r = S.transpose() * u2;
    const Vec3 w2 = (w2r - w2r.dot(w1) * w1).normalized();
    const Eigen::Matrix3d R =
        w1 * u1.transpose() + w2 * u2.transpose() + w1.cross(w2) * u1.cross(u2).transpose();
    if ((R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-10) return R;
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d W = svd.matrixV();
  if ((W * svd.matrixU().transpose()).determinant() < 0) W.col(2) *= -1;
  return W * svd.matrixU().transpose();
}

}  // namespace

struct PinnedCleanup::Impl {
  PinnedCleanupOptions options;
  CleanupKeep keep = CleanupKeep::None;
  bool closed = false;
  Eigen::Index n = 0;
  Eigen::MatrixXd V0;
  Eigen::MatrixXi F;
  Eigen::VectorXi pins, free;
  std::vector<ActiveFace> active;  // faces with a free corner
  std::vector<int> fixed_faces;    // faces whose corners are all pinned
  double active_area = 0;          // Σ A_f over active faces
  double rest_measure = 0;
  // free vertex k (= free[k]) -> incidences [inc_offset[k], inc_offset[k+1]) of (active face, corner)
  std::vector<int> inc_offset;
  std::vector<std::pair<int, int>> inc;
  DirichletSolver solver;  // L + C with the pins as Dirichlet values
  // Pose attraction (header comment): c_i = γ a_i m_i / A_rest per vertex (0 on pins and when γ = 0).
  Eigen::VectorXd attract;
  bool attracted = false;
  double bind_ms = 0;
  // Vertex cells: the free vertices and their neighbours; cell k is vertex cell_vertex[k], its spokes
  // [cell_offset[k], cell_offset[k+1]) go to cell_nbr with cotangent weights cell_w (= −L_ij);
  // cell_d[k] = Σ_j w_ij |e_ij|² at rest; cell_of[i] = the cell of vertex i or −1.
  std::vector<int> cell_vertex, cell_offset, cell_nbr, cell_of;
  std::vector<double> cell_w, cell_d;
  double cell_dsum = 0;
  // per-frame scratch
  std::vector<Eigen::Matrix3d> cell_T;  // vertex cells: T_i = s_i R_i
  std::vector<std::array<Vec3, 2>> T;   // per active face: t1, t2 (the columns of T_f in the rest frame)
  Eigen::MatrixXd B, values, V;
  // warm start: the previous frame's edit and result (have_prev after a successful cleanup)
  Eigen::MatrixXd prev_edit, prev_out;
  bool have_prev = false;

  double measure_all(const Eigen::MatrixXd& X) const;  // the kept measure (area for None) over all faces
  double measure_fixed(const Eigen::MatrixXd& X) const;
  double measure_active(const Eigen::MatrixXd& X) const;
};

static double face_volume(const Vec3& a, const Vec3& b, const Vec3& c) { return a.dot(b.cross(c)) / 6.0; }
static double face_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

double PinnedCleanup::Impl::measure_all(const Eigen::MatrixXd& X) const {
  const bool vol = keep == CleanupKeep::Volume;
  double s = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 a = X.row(F(f, 0)), b = X.row(F(f, 1)), c = X.row(F(f, 2));
    s += vol ? face_volume(a, b, c) : face_area(a, b, c);
  }
  return s;
}

double PinnedCleanup::Impl::measure_fixed(const Eigen::MatrixXd& X) const {
  const bool vol = keep == CleanupKeep::Volume;
  double s = 0;
  for (const int f : fixed_faces) {
    const Vec3 a = X.row(F(f, 0)), b = X.row(F(f, 1)), c = X.row(F(f, 2));
    s += vol ? face_volume(a, b, c) : face_area(a, b, c);
  }
  return s;
}

double PinnedCleanup::Impl::measure_active(const Eigen::MatrixXd& X) const {
  const bool vol = keep == CleanupKeep::Volume;
  double s = 0;
  const long m = static_cast<long>(active.size());
#pragma omp parallel for schedule(static) reduction(+ : s) if (parallel::worth(m, parallel::kMotorBlend))
  for (long k = 0; k < m; ++k) {
    const ActiveFace& af = active[k];
    const Vec3 a = X.row(af.v[0]), b = X.row(af.v[1]), c = X.row(af.v[2]);
    s += vol ? face_volume(a, b, c) : face_area(a, b, c);
  }
  return s;
}

PinnedCleanup::PinnedCleanup() : impl_(std::make_unique<Impl>()) {}
PinnedCleanup::~PinnedCleanup() = default;
PinnedCleanup::PinnedCleanup(PinnedCleanup&&) noexcept = default;
PinnedCleanup& PinnedCleanup::operator=(PinnedCleanup&&) noexcept = default;

PinnedCleanup PinnedCleanup::bind(const Mesh& rest, const Eigen::VectorXi& pins,
                                  const PinnedCleanupOptions& options, const Eigen::VectorXd& attraction) {
  return bind(rest, std::span<const int>(pins.data(), static_cast<size_t>(pins.size())), options,
              std::span<const double>(attraction.data(), static_cast<size_t>(attraction.size())));
}

PinnedCleanup PinnedCleanup::bind(const Mesh& rest, std::span<const int> pins,
                                  const PinnedCleanupOptions& options, std::span<const double> attraction) {
  const auto t0 = Clock::now();
  PinnedCleanup out;
  Impl& m = *out.impl_;
  m.options = options;
  if (options.max_iterations < 1) throw Error("PinnedCleanup: max_iterations must be at least 1");
  if (!(options.vertex_cell_weight >= 0 && options.vertex_cell_weight <= 1))
    throw Error("PinnedCleanup: vertex_cell_weight must be in [0, 1]");
  if (!(options.tolerance > 0) || !std::isfinite(options.tolerance))
    throw Error("PinnedCleanup: tolerance must be a finite positive number");
  if (!(options.pose_weight >= 0) || !std::isfinite(options.pose_weight))
    throw Error("PinnedCleanup: pose_weight must be a finite number ≥ 0");
  if (rest.V.cols() != 3 || rest.F.cols() != 3)
    throw Error("PinnedCleanup: the rest mesh needs n×3 V and m×3 F");
  const Eigen::Index n = rest.V.rows();
  m.n = n;
  m.V0 = rest.V;
  m.F = rest.F;
  // The cotangent Laplacian validates indices, finiteness and degenerate faces (naming them).
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(rest.V, rest.F);

  // Pins: range, then sort and drop repeats.
  const bool attracting = options.pose_weight > 0;
  if (pins.empty() && !attracting)
    throw Error("PinnedCleanup: no pinned vertex (give at least one per connected component)");
  std::vector<int> p(pins.begin(), pins.end());
  for (size_t r = 0; r < p.size(); ++r)
    if (p[r] < 0 || p[r] >= n) {
      std::ostringstream s;
      s << "PinnedCleanup: pin " << r << " is vertex " << p[r] << ", out of range [0, " << n << ")";
      throw Error(s.str());
    }
  std::sort(p.begin(), p.end());
  p.erase(std::unique(p.begin(), p.end()), p.end());
  m.pins = Eigen::Map<const Eigen::VectorXi>(p.data(), static_cast<Eigen::Index>(p.size()));
  std::vector<char> pinned(n, 0);
  for (const int i : p) pinned[i] = 1;
  std::vector<int> slot(n, -1);  // free index
  std::vector<int> fr;
  fr.reserve(n - p.size());
  for (Eigen::Index i = 0; i < n; ++i)
    if (!pinned[i]) {
      slot[i] = static_cast<int>(fr.size());
      fr.push_back(static_cast<int>(i));
    }
  m.free = Eigen::Map<const Eigen::VectorXi>(fr.data(), static_cast<Eigen::Index>(fr.size()));

  // Attraction weights (checked before the anchors, which they can provide).
  if (!attraction.empty() && static_cast<Eigen::Index>(attraction.size()) != n) {
    std::ostringstream s;
    s << "PinnedCleanup: " << attraction.size() << " attraction weights for " << n << " vertices";
    throw Error(s.str());
  }
  for (size_t i = 0; i < attraction.size(); ++i)
    if (!(attraction[i] >= 0 && attraction[i] <= 1)) {
      std::ostringstream s;
      s << "PinnedCleanup: attraction weight of vertex " << i << " is " << attraction[i] << ", not in [0, 1]";
      throw Error(s.str());
    }
  // Every connected component needs an anchor: a pin, or (with the pose attraction) a free vertex with a
  // positive attraction weight. A free region without one floats.
  int ncomp = 0;
  const Eigen::VectorXi comp = vertex_components(rest.F, n, &ncomp);
  std::vector<char> anchors(n, 0);
  for (const int i : p) anchors[i] = 1;
  if (attracting)
    for (Eigen::Index i = 0; i < n; ++i)
      if (attraction.empty() || attraction[i] > 0) anchors[i] = 1;
  {
    std::vector<char> anchored(ncomp, 0);
    for (Eigen::Index i = 0; i < n; ++i)
      if (anchors[i]) anchored[comp[i]] = 1;
    for (int c = 0; c < ncomp; ++c)
      if (!anchored[c]) {
        Eigen::Index count = 0, first = -1;
        for (Eigen::Index i = 0; i < n; ++i)
          if (comp[i] == c) {
            if (first < 0) first = i;
            ++count;
          }
        std::ostringstream s;
        s << "PinnedCleanup: connected component " << c << " of the mesh (" << count
          << (count == 1 ? " vertex" : " vertices") << ", e.g. vertex " << first << ") has no pinned vertex"
          << (attracting ? " and no attracted one" : "") << ": its free vertices have no anchor";
        throw Error(s.str());
      }
  }

  m.closed = boundary_vertices(rest.F, n).size() == 0;
  m.keep =
      options.keep == CleanupKeep::Auto ? (m.closed ? CleanupKeep::Volume : CleanupKeep::Area) : options.keep;
  if (m.keep == CleanupKeep::Volume && !m.closed)
    throw Error("PinnedCleanup: keep = volume needs a closed mesh (this one has boundary edges); use area");

  // Rest data of the active faces.
  const Eigen::Index nf = rest.F.rows();
  for (Eigen::Index f = 0; f < nf; ++f) {
    const int a = rest.F(f, 0), b = rest.F(f, 1), c = rest.F(f, 2);
    if (pinned[a] && pinned[b] && pinned[c]) {
      m.fixed_faces.push_back(static_cast<int>(f));
      continue;
    }
    ActiveFace af;
    af.v = {a, b, c};
    const Vec3 p0 = rest.V.row(a), p1 = rest.V.row(b), p2 = rest.V.row(c);
    const Vec3 e1 = p1 - p0, e2 = p2 - p0, nv = e1.cross(e2);
    if (collapsed(e1, e2, p2 - p1, nv)) {
      std::ostringstream s;
      s << "PinnedCleanup: rest face " << f << " is degenerate";
      throw Error(s.str());
    }
    af.area = 0.5 * nv.norm();
    af.b1 = e1.normalized();
    af.b2 = nv.normalized().cross(af.b1);
    // 2D corners q0 = 0, q1 = (|e1|, 0), q2 = (e2·b1, e2·b2); ∇φ_i = perp(q_{i+2} − q_{i+1}) / (2A),
    // perp(x, y) = (−y, x) (counter-clockwise quarter turn).
    const std::array<Eigen::Vector2d, 3> q = {Eigen::Vector2d(0, 0), Eigen::Vector2d(e1.norm(), 0),
                                              Eigen::Vector2d(e2.dot(af.b1), e2.dot(af.b2))};
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector2d e = q[(i + 2) % 3] - q[(i + 1) % 3];
      af.grad[2 * i] = -e.y() / (2 * af.area);
      af.grad[2 * i + 1] = e.x() / (2 * af.area);
    }
    m.active_area += af.area;
    m.active.push_back(af);
  }
  // Incidences of the free vertices in the active faces (CSR).
  m.inc_offset.assign(fr.size() + 1, 0);
  for (const ActiveFace& af : m.active)
    for (int c = 0; c < 3; ++c)
      if (slot[af.v[c]] >= 0) ++m.inc_offset[slot[af.v[c]] + 1];
  for (size_t k = 0; k < fr.size(); ++k) m.inc_offset[k + 1] += m.inc_offset[k];
  m.inc.resize(m.inc_offset.back());
  {
    std::vector<int> fill(m.inc_offset.begin(), m.inc_offset.end() - 1);
    for (size_t f = 0; f < m.active.size(); ++f)
      for (int c = 0; c < 3; ++c) {
        const int s = slot[m.active[f].v[c]];
        if (s >= 0) m.inc[fill[s]++] = {static_cast<int>(f), c};
      }
  }
  m.rest_measure = m.measure_all(rest.V);

  // Pose attraction: C = diag(c), c_i = γ a_i m_i / A_rest on the free vertices (m_i the barycentric
  // vertex area of the rest mesh, A_rest its area; a_i the caller's weights, 1 when none are given).
  m.attract.setZero(n);
  m.attracted = options.pose_weight > 0;
  Eigen::SparseMatrix<double> A = L;
  if (m.attracted) {
    const Eigen::VectorXd mass = vertex_areas(rest.V, rest.F, MassType::Barycentric);
    const double area = mass.sum();
    for (const int i : fr) {
      m.attract[i] = options.pose_weight * (attraction.empty() ? 1.0 : attraction[i]) * mass[i] / area;
      A.coeffRef(i, i) += m.attract[i];
    }
  }

  // One factorisation of (L + C)_FF (skipped when everything is pinned).
  if (!fr.empty()) m.solver.bind(A, m.pins, DirichletSolver::Kind::SPD, anchors);
  // Vertex cells from the Laplacian's off-diagonal entries.
  m.cell_of.assign(n, -1);
  for (const int i : fr) {
    if (m.cell_of[i] < 0) {
      m.cell_of[i] = static_cast<int>(m.cell_vertex.size());
      m.cell_vertex.push_back(i);
    }
    for (Eigen::SparseMatrix<double>::InnerIterator itL(L, i); itL; ++itL) {
      const int j = static_cast<int>(itL.row());
      if (j != i && m.cell_of[j] < 0) {
        m.cell_of[j] = static_cast<int>(m.cell_vertex.size());
        m.cell_vertex.push_back(j);
      }
    }
  }
  m.cell_offset.assign(1, 0);
  bool cells_ok = m.options.vertex_cell_weight > 0 || m.options.harmonic_start;
  for (const int i : m.cell_vertex) {
    if (!cells_ok) break;
    double d = 0;
    for (Eigen::SparseMatrix<double>::InnerIterator itL(L, i); itL; ++itL) {
      const int j = static_cast<int>(itL.row());
      if (j == i || itL.value() == 0) continue;
      m.cell_nbr.push_back(j);
      m.cell_w.push_back(-itL.value());
      d += -itL.value() * (rest.V.row(j) - rest.V.row(i)).squaredNorm();
    }
    m.cell_offset.push_back(static_cast<int>(m.cell_nbr.size()));
    if (!(d > 0)) {
      // The cotangent weights around vertex i sum to d ≤ 0 (a one-ring of obtuse triangles, common on
      // coarse game meshes): no similarity can be fitted to that cell. The cleanup then uses face cells
      // only (vertex_cell_weight = 0, no harmonic start), which every non-degenerate mesh allows;
      // options() reports the options in effect.
      cells_ok = false;
      break;
    }
    m.cell_d.push_back(d);
    m.cell_dsum += d;
  }
  if (!cells_ok) {
    m.options.vertex_cell_weight = 0;
    m.options.harmonic_start = false;
    m.cell_offset.assign(1, 0);
    m.cell_nbr.clear();
    m.cell_w.clear();
    m.cell_d.clear();
    m.cell_dsum = 0;
    m.cell_vertex.clear();
    m.cell_of.assign(n, -1);
  }
  m.cell_T.resize(m.cell_vertex.size());
  m.T.resize(m.active.size());
  m.bind_ms = ms_since(t0);
  return out;
}

PinnedCleanupResult PinnedCleanup::cleanup(const Eigen::MatrixXd& V_edit, Eigen::MatrixXd& V_out) {
  const auto t_start = Clock::now();
  Impl& m = *impl_;
  if (!m.V0.size()) throw Error("PinnedCleanup: cleanup() before bind()");
  if (V_edit.rows() != m.n || V_edit.cols() != 3) {
    std::ostringstream s;
    s << "PinnedCleanup: the edit has " << V_edit.rows() << "×" << V_edit.cols()
      << " positions, the rest mesh " << m.n << "×3";
    throw Error(s.str());
  }
  for (Eigen::Index i = 0; i < m.n; ++i)
    if (!V_edit.row(i).allFinite()) {
      std::ostringstream s;
      s << "PinnedCleanup: vertex " << i << " of the edit has a non-finite coordinate";
      throw Error(s.str());
    }
  PinnedCleanupResult r;
  r.kept = m.keep;
  r.rest_measure = m.rest_measure;
  r.edit_measure = m.measure_all(V_edit);
  if (V_out.rows() != m.n || V_out.cols() != 3) V_out.resize(m.n, 3);
  if (m.free.size() == 0) {
    V_out = V_edit;
    r.all_pinned = true;
    r.converged = true;
    r.measure = r.edit_measure;
    r.total_ms = ms_since(t_start);
    return r;
  }

  const bool constrained = m.keep != CleanupKeep::None;
  const bool vol = m.keep == CleanupKeep::Volume;
  const Eigen::Index c = m.pins.size(), nfree = m.free.size();
  const int cols = constrained ? 6 : 3;
  Eigen::MatrixXd& V = m.V;
  V = V_edit;
  // Warm start (header comment): carry the previous frame's correction along with the edit.
  const bool warm = m.options.warm_start && m.have_prev;
  m.have_prev = false;  // until this frame succeeds
  if (warm)
    for (Eigen::Index k = 0; k < m.free.size(); ++k) {
      const int i = m.free[k];
      V.row(i) += m.prev_out.row(i) - m.prev_edit.row(i);
    }
  const bool harmonic_start = m.options.harmonic_start && !warm;
  if (m.B.rows() != m.n || m.B.cols() != cols) m.B.setZero(m.n, cols);
  m.values.setZero(c, cols);
  for (Eigen::Index k = 0; k < c; ++k) m.values.row(k).head<3>() = V_edit.row(m.pins[k]);
  for (size_t f = 0; f < m.active.size(); ++f) m.T[f] = {m.active[f].b1, m.active[f].b2};
  const double fixed = constrained ? m.measure_fixed(V_edit) : 0.0;
  const long na = static_cast<long>(m.active.size());
  const long nfl = static_cast<long>(nfree);

  const long nc = static_cast<long>(m.cell_vertex.size());
  const double beta = m.options.vertex_cell_weight;  // (1 − β) face cells + β vertex cells
  const bool faces = beta < 1;
  const bool vertices = beta > 0;
  for (auto& T : m.cell_T) T = Eigen::Matrix3d::Identity();
  const double e_scale = (1 - beta) * 2 * m.active_area + 0.5 * beta * m.cell_dsum;

  // fit_vertices: fit the vertex cells (also when β = 0, for the harmonic start's pinned values).
  auto local_step = [&](bool fit_vertices) -> double {
    double energy = 0, energy_v = 0;
    long fallback = 0;
    if (faces) {
      // Local step, face cells: T_f = the conformal part of J_f in the frames of the rest and current planes.
#pragma omp parallel for schedule(static) reduction(+ : energy, fallback) if (parallel::worth(na, parallel::kMotorBlend))
      for (long k = 0; k < na; ++k) {
        const ActiveFace& af = m.active[k];
        const Vec3 v0 = V.row(af.v[0]), v1 = V.row(af.v[1]), v2 = V.row(af.v[2]);
        const Vec3 c1 = af.grad[0] * v0 + af.grad[2] * v1 + af.grad[4] * v2;
        const Vec3 c2 = af.grad[1] * v0 + af.grad[3] * v1 + af.grad[5] * v2;
        const Vec3 e1 = v1 - v0, e2 = v2 - v0, nv = e1.cross(e2);
        std::array<Vec3, 2>& T = m.T[k];
        if (collapsed(e1, e2, v2 - v1, nv)) {
          ++fallback;  // keep the previous T_f
        } else {
          const Vec3 d1 = e1.normalized(), d2 = nv.normalized().cross(d1);
          const double a = d1.dot(c1), b = d1.dot(c2), cc = d2.dot(c1), d = d2.dot(c2);
          const double alpha = 0.5 * (a + d), beta = 0.5 * (cc - b);
          T[0] = alpha * d1 + beta * d2;
          T[1] = -beta * d1 + alpha * d2;
        }
        energy += af.area * ((c1 - T[0]).squaredNorm() + (c2 - T[1]).squaredNorm());
      }
    }
    if (fit_vertices) {
      // Local step, vertex cells: T_i = s_i R_i, the best similarity of the cotangent-weighted spokes
      // (3D Procrustes with scale): S_i = Σ_j w_ij e_ij e'_ijᵀ = U Σ Wᵀ, R_i = W diag(1, 1, ±1) Uᵀ,
      // s_i = tr(R_i S_i) / Σ_j w_ij |e_ij|²; cell energy Σ w|e'|² − s_i tr(R_i S_i).
#pragma omp parallel for schedule(static) reduction(+ : energy_v, fallback) if (parallel::worth(nc, parallel::kMotorBlend))
      for (long k = 0; k < nc; ++k) {
        const int i = m.cell_vertex[k];
        const Vec3 vi = V.row(i), pi = m.V0.row(i);
        Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
        double e2sum = 0;
        for (int q = m.cell_offset[k]; q < m.cell_offset[k + 1]; ++q) {
          const int j = m.cell_nbr[q];
          const double w = m.cell_w[q];
          const Vec3 e = Vec3(m.V0.row(j)) - pi, ed = Vec3(V.row(j)) - vi;
          S.noalias() += w * e * ed.transpose();
          e2sum += w * ed.squaredNorm();
        }
        Eigen::Matrix3d& T = m.cell_T[k];
        if (!(S.norm() > 0)) {
          ++fallback;  // a collapsed cell keeps its previous similarity
          energy_v += e2sum;
          continue;
        }
        const Eigen::Matrix3d R = best_rotation(S);
        const double tr = (R * S).trace();
        const double scale = std::max(tr, 0.0) / m.cell_d[k];
        T = scale * R;
        energy_v += e2sum - scale * tr;
      }
    }
    r.collapsed_cells += fallback;
    // Pose attraction Σ_i c_i |v_i − v1_i|² (free vertices; 0 without it).
    double energy_a = 0;
    if (m.attracted) {
#pragma omp parallel for schedule(static) reduction(+ : energy_a) if (parallel::worth(nfl, parallel::kMotorBlend))
      for (long k = 0; k < nfl; ++k) {
        const int i = m.free[k];
        energy_a += m.attract[i] * (V.row(i) - V_edit.row(i)).squaredNorm();
      }
    }
    // E = (1 − β) E_faces + β/2 E_vertices + E_attraction (the first two ≈ 2 × area for a unit
    // mismatch), normalised.
    return std::max((1 - beta) * energy + 0.5 * beta * energy_v + energy_a, 0.0) / e_scale;
  };
  // Anderson acceleration of the fixed point x -> G(x) (one local + global step) on the free
  // coordinates (Peng et al. 2018, "Anderson acceleration for geometry optimization and physics
  // simulation", §3-4): x_{k+1} = G_k − ΔG γ, γ = argmin |f_k − ΔF γ|, f = G(x) − x, with the last
  // `anderson` differences; a step whose energy rises is replaced by the plain iterate G_k and the
  // history restarts. Affine combinations keep the pins (not part of x) exact.
  const int depth = std::max(0, m.options.anderson);
  const Eigen::Index N = 3 * nfree;
  auto gather = [&](Eigen::VectorXd& x) {
    x.resize(N);
    for (Eigen::Index k = 0; k < nfree; ++k) x.segment<3>(3 * k) = V.row(m.free[k]).transpose();
  };
  auto scatter = [&](const Eigen::VectorXd& x) {
    for (Eigen::Index k = 0; k < nfree; ++k) V.row(m.free[k]) = x.segment<3>(3 * k).transpose();
  };
  Eigen::VectorXd x, Gk, f, f_prev, G_prev, G_last;
  Eigen::MatrixXd dF(N, depth), dG(N, depth);
  int hist = 0, slot = 0;
  bool have_prev = false, accelerated = false;

  double e_prev = -1;
  for (int it = 0;; ++it) {
    auto t0 = Clock::now();
    double e_norm = local_step(vertices || (it == 0 && harmonic_start));
    if (accelerated && e_norm > e_prev) {
      scatter(G_last);  // reject the Anderson step
      hist = 0;
      slot = 0;
      have_prev = false;
      ++r.rejected_accelerations;
      e_norm = local_step(vertices);
      accelerated = false;
    }
    r.energy.push_back(e_norm);
    bool stop = e_norm <= 1e-28;
    if (it > 0 && std::abs(e_norm - e_prev) <= m.options.tolerance * e_norm) stop = true;
    e_prev = e_norm;
    if (stop || it >= m.options.max_iterations) {
      // Return a plain iterate: it meets the linearised constraint, an Anderson combination need not.
      if (accelerated) scatter(G_last);
      r.converged = stop;
      r.local_ms += ms_since(t0);
      break;
    }
    accelerated = false;
    // Harmonic start (first step only): the edit's creases (an LBS elbow folds its inner side) make
    // the similarities fitted at V1 wrong in the free region, and the fold takes the iteration long
    // to undo. Instead, interpolate the similarities of the pinned cells harmonically over the free
    // vertices (L_FF x_F = −L_FP x_P for the quaternion of R_i, sign-aligned, and log s_i: the same
    // factor, 5 columns) and take the first global step with vertex cells only.
    const bool harmonic = it == 0 && harmonic_start;
    if (harmonic) {
      Eigen::MatrixXd hv(c, 5);
      Eigen::Quaterniond ref(1, 0, 0, 0);
      bool have_ref = false;
      for (Eigen::Index k = 0; k < c; ++k) {
        const int ci = m.cell_of[m.pins[k]];
        Eigen::Quaterniond q = ref;
        double logs = 0;
        if (ci >= 0) {
          const double sc = m.cell_T[ci].col(0).norm();
          if (sc > 0) {
            q = Eigen::Quaterniond(Eigen::Matrix3d(m.cell_T[ci] / sc));
            logs = std::log(sc);
            if (!have_ref) {
              ref = q;
              have_ref = true;
            }
            if (q.dot(ref) < 0) q.coeffs() *= -1;
          }
        }
        hv.row(k) << q.w(), q.x(), q.y(), q.z(), logs;
      }
      const auto th = Clock::now();
      // With the pose attraction the solver's matrix is L + C: the interpolation then becomes
      // (L + C)_FF x_F = C x̂_F − L_FP x_P, screened toward x̂ = the similarities fitted to the edit
      // (where the edit is trusted, its own similarities; harmonic where c = 0).
      Eigen::MatrixXd hb;
      if (m.attracted) {
        hb.setZero(m.n, 5);
        for (Eigen::Index k = 0; k < nfree; ++k) {
          const int i = m.free[k];
          const Eigen::Matrix3d& Ti = m.cell_T[m.cell_of[i]];
          const double sc = Ti.col(0).norm();
          if (!(sc > 0) || m.attract[i] == 0) continue;
          Eigen::Quaterniond q(Eigen::Matrix3d(Ti / sc));
          if (q.dot(ref) < 0) q.coeffs() *= -1;
          hb.row(i) << q.w(), q.x(), q.y(), q.z(), std::log(sc);
          hb.row(i) *= m.attract[i];
        }
      }
      const Eigen::MatrixXd X = m.attracted ? m.solver.solve(hb, hv) : m.solver.solve(hv);
      r.solve_ms += ms_since(th);
      for (Eigen::Index k = 0; k < nfree; ++k) {
        const int i = m.free[k];
        Eigen::Quaterniond q(X(i, 0), X(i, 1), X(i, 2), X(i, 3));
        if (!(q.norm() > 1e-12)) continue;  // antipodal pins cancel: keep the fitted similarity
        q.normalize();
        m.cell_T[m.cell_of[i]] = std::exp(X(i, 4)) * q.toRotationMatrix();
      }
    }
    const double bv = harmonic ? 1.0 : beta, bf = harmonic ? 0.0 : 1 - beta;
    // Right-hand side b_i (face cells: Σ A_f T_f ∇φ_i; vertex cells: ½ Σ_j w_ij (T_i + T_j)(p_i − p_j))
    // and the constraint gradient g_i, per free vertex.
    double gV = 0;
#pragma omp parallel for schedule(static) reduction(+ : gV) if (parallel::worth(nfl, parallel::kMotorBlend))
    for (long k = 0; k < nfl; ++k) {
      const int i = m.free[k];
      Vec3 b = Vec3::Zero(), g = Vec3::Zero();
      if (vertices || harmonic) {
        const int ci = m.cell_of[i];
        const Vec3 pi = m.V0.row(i);
        for (int q = m.cell_offset[ci]; q < m.cell_offset[ci + 1]; ++q) {
          const int j = m.cell_nbr[q];
          b += 0.5 * m.cell_w[q] * ((m.cell_T[ci] + m.cell_T[m.cell_of[j]]) * (pi - Vec3(m.V0.row(j))));
        }
        b *= bv;
      }
      for (int q = m.inc_offset[k]; q < m.inc_offset[k + 1]; ++q) {
        const auto [f, corner] = m.inc[q];
        const ActiveFace& af = m.active[f];
        if (faces && !harmonic) {
          const std::array<Vec3, 2>& T = m.T[f];
          b += bf * af.area * (af.grad[2 * corner] * T[0] + af.grad[2 * corner + 1] * T[1]);
        }
        if (constrained) {
          const Vec3 vj = V.row(af.v[(corner + 1) % 3]), vk = V.row(af.v[(corner + 2) % 3]);
          if (vol) {
            g += vj.cross(vk) / 6.0;
          } else {
            const Vec3 vi = V.row(af.v[corner]);
            const Vec3 nv = (vj - vi).cross(vk - vi);
            const double len = nv.norm();
            if (len > 0) g += 0.5 * (nv / len).cross(vk - vj);
          }
        }
      }
      if (m.attracted) b += m.attract[i] * V_edit.row(i).transpose();
      m.B.row(i).head<3>() = b;
      if (constrained) {
        m.B.row(i).tail<3>() = g;
        gV += g.dot(V.row(i).transpose());
      }
    }
    const double current = constrained ? fixed + m.measure_active(V) : 0.0;
    r.local_ms += ms_since(t0);

    // Global step: one back-substitution of 3 (or 6) columns, then the multiplier.
    t0 = Clock::now();
    const Eigen::MatrixXd X = m.solver.solve(m.B, m.values);
    r.solve_ms += ms_since(t0);
    double mu = 0;
    if (constrained) {
      const double rhs = m.rest_measure - current + gV;
      double ga = 0, gg = 0;
      for (Eigen::Index k = 0; k < nfree; ++k) {
        const int i = m.free[k];
        const Vec3 g = m.B.row(i).tail<3>();
        ga += g.dot(X.row(i).head<3>().transpose());
        gg += g.dot(X.row(i).tail<3>().transpose());
      }
      if (gg > 0) mu = (ga - rhs) / gg;
    }
    if (depth > 0) gather(x);
    for (Eigen::Index k = 0; k < nfree; ++k) {
      const int i = m.free[k];
      V.row(i) = X.row(i).head<3>();
      if (constrained) V.row(i) -= mu * X.row(i).tail<3>();
    }
    if (depth > 0) {
      gather(Gk);
      f = Gk - x;
      if (have_prev && !harmonic) {
        dF.col(slot) = f - f_prev;
        dG.col(slot) = Gk - G_prev;
        slot = (slot + 1) % depth;
        hist = std::min(hist + 1, depth);
      }
      f_prev = f;
      G_prev = Gk;
      have_prev = true;
      if (hist > 0) {
        const Eigen::MatrixXd A = dF.leftCols(hist);
        const Eigen::VectorXd gamma = A.colPivHouseholderQr().solve(f);
        if (gamma.allFinite()) {
          G_last = Gk;
          scatter(Gk - dG.leftCols(hist) * gamma);
          accelerated = true;
        }
      }
    }
    ++r.iterations;
    if (m.options.record_quasi_conformal) r.q_mean.push_back(quasi_conformal_summary(m.V0, m.F, V).q_mean);
  }
  V_out = V;
  for (Eigen::Index k = 0; k < c; ++k) V_out.row(m.pins[k]) = V_edit.row(m.pins[k]);  // bit for bit
  r.measure = m.measure_all(V_out);
  const double diag = (V_edit.colwise().maxCoeff() - V_edit.colwise().minCoeff()).norm();
  double err = 0;
  for (Eigen::Index k = 0; k < c; ++k)
    err = std::max(err, (V_out.row(m.pins[k]) - V_edit.row(m.pins[k])).norm());
  r.pin_error = diag > 0 ? err / diag : err;
  if (m.options.warm_start) {
    m.prev_edit = V_edit;
    m.prev_out = V_out;
    m.have_prev = true;
  }
  r.total_ms = ms_since(t_start);
  return r;
}

void PinnedCleanup::reset() noexcept { impl_->have_prev = false; }

Eigen::Index PinnedCleanup::vertices() const { return impl_->n; }
const Eigen::VectorXi& PinnedCleanup::pins() const { return impl_->pins; }
const Eigen::VectorXi& PinnedCleanup::free_vertices() const { return impl_->free; }
bool PinnedCleanup::closed() const { return impl_->closed; }
CleanupKeep PinnedCleanup::keep() const { return impl_->keep; }
double PinnedCleanup::bind_ms() const { return impl_->bind_ms; }
const PinnedCleanupOptions& PinnedCleanup::options() const { return impl_->options; }

Eigen::VectorXi read_pin_file(const std::filesystem::path& path, Eigen::Index n) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot read the pin file");
  std::vector<int> out;
  std::string line;
  for (int lineno = 1; std::getline(in, line); ++lineno) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream ls(line);
    std::string tok;
    while (ls >> tok) {
      long long v = -1;
      size_t used = 0;
      try {
        v = std::stoll(tok, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != tok.size() || v < 0) {
        std::ostringstream s;
        s << path.string() << ":" << lineno << ": '" << tok
          << "' is not a vertex index (a non-negative integer)";
        throw Error(s.str());
      }
      if (v >= n) {
        std::ostringstream s;
        s << path.string() << ":" << lineno << ": vertex " << v << " is out of range (the mesh has " << n
          << " vertices)";
        throw Error(s.str());
      }
      out.push_back(static_cast<int>(v));
    }
  }
  if (in.bad()) throw Error(path.string() + ": read error");
  if (out.empty()) throw Error(path.string() + ": the pin file lists no vertex");
  return Eigen::Map<const Eigen::VectorXi>(out.data(), static_cast<Eigen::Index>(out.size()));
}

}  // namespace spinmotor
