// Pose-keeping conformal cleanup: local/global ASAP with pins and a volume (or area) multiplier.
// See pinned_cleanup.hpp for the equations.
#include "spinmotor/spin/pinned_cleanup.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/fit/cells.hpp"
#include "spinmotor/fit/local_global.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/mass_matrix.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/mesh/topology.hpp"

namespace spinmotor {

namespace {

using Vec3 = Eigen::Vector3d;
using Clock = std::chrono::steady_clock;
using fit::RowMatrix3;

}  // namespace

struct PinnedCleanup::Impl {
  PinnedCleanupOptions options;
  CleanupKeep keep = CleanupKeep::None;
  bool closed = false;
  Eigen::Index n = 0;
  Eigen::MatrixXd V0;
  Eigen::MatrixXi F;
  Eigen::VectorXi pins, free;
  fit::SimilarityFaces faces;     // faces with a free corner
  fit::SimilarityOneRings rings;  // the free vertices' one-rings (and their neighbours')
  fit::LocalGlobal solver;        // L + C with the pins as Dirichlet values, the kept measure's row
  fit::MeasureKind measure_kind = fit::MeasureKind::None;
  double rest_measure = 0;
  // Pose attraction (header comment): c_i = γ a_i m_i / A_rest per vertex (0 on pins and when γ = 0).
  Eigen::VectorXd attract;
  bool attracted = false;
  double bind_ms = 0;
  // per-frame scratch
  RowMatrix3 X, values, edit;
  // warm start: the previous frame's edit and result (have_prev after a successful cleanup)
  Eigen::MatrixXd prev_edit, prev_out;
  bool have_prev = false;

  struct Frame;  // one cleanup's fit::Problem

  void bind_pins(std::span<const int> pins, std::span<const double> attraction, std::vector<char>& pinned);
  void bind_cells(const Mesh& rest, const Eigen::SparseMatrix<double>& L, const std::vector<char>& pinned,
                  std::span<const double> attraction);
};

/// The frame's Problem (fit/local_global.hpp): (1 − β) face cells + β/2 vertex cells + the attraction,
/// normalised; the harmonic start on the first step.
struct PinnedCleanup::Impl::Frame final : fit::Problem {
  PinnedCleanup::Impl& m;
  const RowMatrix3& edit;
  PinnedCleanupResult& result;
  bool harmonic_start;
  double beta, e_scale;
  bool faces, vertices;

  Frame(PinnedCleanup::Impl& impl, const RowMatrix3& e, PinnedCleanupResult& r, bool harmonic)
      : m(impl), edit(e), result(r), harmonic_start(harmonic), beta(impl.options.vertex_cell_weight) {
    faces = beta<1, vertices = beta> 0;
    e_scale = (1 - beta) * 2 * m.faces.area() + 0.5 * beta * m.rings.rest_scale();
  }
  double fit(const RowMatrix3& X, int it, fit::SolveReport& r) override {
    // The vertex cells are fitted also when β = 0 for the harmonic start's pinned values.
    const bool fit_vertices = vertices || (it == 0 && harmonic_start);
    const double energy = faces ? m.faces.fit(X, r.fallback_fits) : 0.0;
    const double energy_v = fit_vertices ? m.rings.fit(X, r.fallback_fits) : 0.0;
    // Pose attraction Σ_i c_i |v_i − v1_i|² (free vertices; 0 without it).
    double energy_a = 0;
    if (m.attracted) {
      const long nfl = static_cast<long>(m.free.size());
#pragma omp parallel for schedule(static) reduction(+ : energy_a) if (parallel::worth(nfl, parallel::kMotorBlend))
      for (long k = 0; k < nfl; ++k) {
        const int i = m.free[k];
        energy_a += m.attract[i] * (X.row(i) - edit.row(i)).squaredNorm();
      }
    }
    // E = (1 − β) E_faces + β/2 E_vertices + E_attraction (the first two ≈ 2 × area for a unit
    // mismatch), normalised.
    return std::max((1 - beta) * energy + 0.5 * beta * energy_v + energy_a, 0.0) / e_scale;
  }
  void rhs(int it, const fit::LocalGlobal& solver, RowMatrix3& B) override {
    const bool harmonic = it == 0 && harmonic_start;
    if (harmonic) harmonic_similarities(solver);
    const double bv = harmonic ? 1.0 : beta, bf = harmonic ? 0.0 : 1 - beta;
    const long nfl = static_cast<long>(m.free.size());
    // b_i (face cells: Σ A_f T_f ∇φ_i; vertex cells: ½ Σ_j w_ij (T_i + T_j)(p_i − p_j)) per free vertex.
#pragma omp parallel for schedule(static) if (parallel::worth(nfl, parallel::kMotorBlend))
    for (long k = 0; k < nfl; ++k) {
      Vec3 b = Vec3::Zero();
      if (vertices || harmonic) m.rings.add_rhs(m.free[k], bv, b);
      if (faces && !harmonic) m.faces.add_rhs(k, bf, b);
      B.row(k) = b.transpose();
    }
  }
  bool plain_step(int it) const override { return !(it == 0 && harmonic_start); }
  double energy_scale() const override { return 1.0; }
  void after_step(const RowMatrix3& X, int) override {
    if (m.options.record_quasi_conformal)
      result.q_mean.push_back(quasi_conformal_summary(m.V0, m.F, Eigen::MatrixXd(X)).q_mean);
  }
  void harmonic_similarities(const fit::LocalGlobal& solver);
};

/// Harmonic start (first step only): the edit's creases (an LBS elbow folds its inner side) make the
/// similarities fitted at V1 wrong in the free region, and the fold takes the iteration long to undo.
/// Instead, the similarities of the pinned cells are interpolated harmonically over the free vertices
/// (L_FF x_F = −L_FP x_P for the quaternion of R_i, sign-aligned, and log s_i: the same factor, 5
/// columns) and the first global step takes vertex cells only. With the pose attraction the matrix is
/// L + C: (L + C)_FF x_F = C x̂_F − L_FP x_P, screened toward x̂ = the similarities fitted to the edit.
void PinnedCleanup::Impl::Frame::harmonic_similarities(const fit::LocalGlobal& solver) {
  const Eigen::Index c = m.pins.size(), nfree = m.free.size();
  // A similarity as a row (w, x, y, z, log s). The quaternion's sign: first the canonical one (w > 0
  // when |w| > ½, else the largest of x, y, z positive), then the one nearest to the first pinned
  // cell's. Where a cell is a half turn from that cell (q · ref ≈ 0: a 180° twist) the canonical sign
  // decides, the same for all such cells. (Chaining the signs over neighbouring cells instead spreads
  // the half turn evenly over the free region, a twisted tube: on a 180° twisted arm E 0.147 after 8
  // iterations, against 0.0083 after 61.)
  ga::Rot ref(1.0, 0.0, 0.0, 0.0);
  bool have_ref = false;
  auto row = [&](const ga::Similarity& s, auto out) {
    Eigen::Vector4d q(s.rotor.w(), s.rotor.x(), s.rotor.y(), s.rotor.z());
    Eigen::Index big = 0;
    if (!(q[0] * q[0] > 0.25)) q.tail<3>().cwiseAbs().maxCoeff(&big), ++big;
    if (q[big] < 0) q = -q;
    if (!have_ref) ref = ga::Rot(q[0], q[1], q[2], q[3]), have_ref = true;
    if (q[0] * ref.w() + q[1] * ref.x() + q[2] * ref.y() + q[3] * ref.z() < 0) q = -q;
    out << q.transpose(), std::log(s.scale);
  };
  Eigen::MatrixXd hv(c, 5);
  for (Eigen::Index k = 0; k < c; ++k) {
    const int ci = m.rings.cell_of(m.pins[k]);
    if (ci >= 0 && m.rings.similarity(ci).scale > 0) {
      row(m.rings.similarity(ci), hv.row(k));
    } else {
      hv.row(k) << ref.w(), ref.x(), ref.y(), ref.z(), 0.0;
    }
  }
  Eigen::MatrixXd hb;
  if (m.attracted) {
    hb.setZero(m.n, 5);
    for (Eigen::Index k = 0; k < nfree; ++k) {
      const int i = m.free[k];
      const ga::Similarity& s = m.rings.similarity(m.rings.cell_of(i));
      if (!(s.scale > 0) || m.attract[i] == 0) continue;
      row(s, hb.row(i));
      hb.row(i) *= m.attract[i];
    }
  }
  const Eigen::MatrixXd X = m.attracted ? solver.dirichlet().solve(hb, hv) : solver.dirichlet().solve(hv);
  for (Eigen::Index k = 0; k < nfree; ++k) {
    const int i = m.free[k];
    const double qn = X.row(i).head<4>().norm();
    if (!(qn > 1e-12)) continue;  // antipodal pins cancel: keep the fitted similarity
    ga::Similarity s;
    s.rotor = ga::Rot(X(i, 0) / qn, X(i, 1) / qn, X(i, 2) / qn, X(i, 3) / qn);
    s.scale = std::exp(X(i, 4));
    m.rings.set_similarity(m.rings.cell_of(i), s);
  }
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

/// Pins (sorted, without repeats; range-checked), the free vertices, the attraction weights' checks and
/// the components' anchors (a pin or, with the pose attraction, an attracted free vertex).
void PinnedCleanup::Impl::bind_pins(std::span<const int> pins_in, std::span<const double> attraction,
                                    std::vector<char>& pinned) {
  const bool attracting = options.pose_weight > 0;
  if (pins_in.empty() && !attracting)
    throw Error("PinnedCleanup: no pinned vertex (give at least one per connected component)");
  std::vector<int> p(pins_in.begin(), pins_in.end());
  for (size_t r = 0; r < p.size(); ++r)
    if (p[r] < 0 || p[r] >= n) {
      std::ostringstream s;
      s << "PinnedCleanup: pin " << r << " is vertex " << p[r] << ", out of range [0, " << n << ")";
      throw Error(s.str());
    }
  std::sort(p.begin(), p.end());
  p.erase(std::unique(p.begin(), p.end()), p.end());
  pins = Eigen::Map<const Eigen::VectorXi>(p.data(), static_cast<Eigen::Index>(p.size()));
  pinned.assign(n, 0);
  for (const int i : p) pinned[i] = 1;
  std::vector<int> fr;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!pinned[i]) fr.push_back(static_cast<int>(i));
  free = Eigen::Map<const Eigen::VectorXi>(fr.data(), static_cast<Eigen::Index>(fr.size()));
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
  // Every connected component needs an anchor, else its free vertices float.
  int ncomp = 0;
  const Eigen::VectorXi comp = vertex_components(F, n, &ncomp);
  std::vector<char> anchored(ncomp, 0);
  for (Eigen::Index i = 0; i < n; ++i)
    if (pinned[i] || (attracting && (attraction.empty() || attraction[i] > 0))) anchored[comp[i]] = 1;
  for (int c = 0; c < ncomp; ++c) {
    if (anchored[c]) continue;
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

/// The cells (faces with a free corner, the one-rings), the attraction C and the factorisation of
/// (L + C)_FF with the kept measure's row.
void PinnedCleanup::Impl::bind_cells(const Mesh& rest, const Eigen::SparseMatrix<double>& L,
                                     const std::vector<char>& pinned, std::span<const double> attraction) {
  faces = fit::SimilarityFaces::bind(rest.V, rest.F, pinned, free);
  attract.setZero(n);
  attracted = options.pose_weight > 0;
  if (attracted) {
    const Eigen::VectorXd mass = vertex_areas(rest.V, rest.F, MassType::Barycentric);
    const double area = mass.sum();
    for (Eigen::Index k = 0; k < free.size(); ++k) {
      const int i = free[k];
      attract[i] = options.pose_weight * (attraction.empty() ? 1.0 : attraction[i]) * mass[i] / area;
    }
  }
  fit::LocalGlobal::Bind b;
  b.L = L;
  b.constrained = pins;
  if (attracted) b.attraction = attract;
  b.measure = keep == CleanupKeep::Volume ? fit::MeasureKind::Volume
              : keep == CleanupKeep::Area ? fit::MeasureKind::Area
                                          : fit::MeasureKind::None;
  b.F = rest.F;
  if (free.size() > 0) solver.bind(b);
  measure_kind = b.measure;
  rest_measure = fit::total_measure(measure_kind, F, RowMatrix3(rest.V));
  // Vertex cells from the Laplacian's off-diagonal entries. A cell whose cotangent weights sum to ≤ 0 (a
  // one-ring of obtuse triangles, common on coarse game meshes) can fit no similarity: the cleanup then
  // uses face cells only (vertex_cell_weight = 0, no harmonic start), which every non-degenerate mesh
  // allows; options() reports the options in effect.
  if (options.vertex_cell_weight > 0 || options.harmonic_start)
    rings = fit::SimilarityOneRings::bind(rest.V, L, free);
  if (!rings.ok() || !(options.vertex_cell_weight > 0 || options.harmonic_start)) {
    options.vertex_cell_weight = 0;
    options.harmonic_start = false;
    rings = fit::SimilarityOneRings();
  }
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
  m.n = rest.V.rows();
  m.V0 = rest.V;
  m.F = rest.F;
  // The cotangent Laplacian validates indices, finiteness and degenerate faces (naming them).
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(rest.V, rest.F);
  std::vector<char> pinned;
  m.bind_pins(pins, attraction, pinned);
  m.closed = boundary_vertices(rest.F, m.n).size() == 0;
  m.keep =
      options.keep == CleanupKeep::Auto ? (m.closed ? CleanupKeep::Volume : CleanupKeep::Area) : options.keep;
  if (m.keep == CleanupKeep::Volume && !m.closed)
    throw Error("PinnedCleanup: keep = volume needs a closed mesh (this one has boundary edges); use area");
  m.bind_cells(rest, L, pinned, attraction);
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
  m.edit = V_edit;
  r.edit_measure = fit::total_measure(m.measure_kind, m.F, m.edit);
  if (V_out.rows() != m.n || V_out.cols() != 3) V_out.resize(m.n, 3);
  if (m.free.size() == 0) {
    V_out = V_edit;
    r.all_pinned = true;
    r.converged = true;
    r.measure = r.edit_measure;
    r.total_ms = ms_since(t_start);
    return r;
  }
  m.X = m.edit;
  // Warm start (header comment): carry the previous frame's correction along with the edit.
  const bool warm = m.options.warm_start && m.have_prev;
  m.have_prev = false;  // until this frame succeeds
  if (warm)
    for (Eigen::Index k = 0; k < m.free.size(); ++k) {
      const int i = m.free[k];
      m.X.row(i) += m.prev_out.row(i) - m.prev_edit.row(i);
    }
  m.values.resize(m.pins.size(), 3);
  for (Eigen::Index k = 0; k < m.pins.size(); ++k) m.values.row(k) = m.edit.row(m.pins[k]);
  m.faces.reset();
  m.rings.reset();
  Impl::Frame problem(m, m.edit, r, m.options.harmonic_start && !warm);
  fit::SolveOptions so;
  so.max_iterations = m.options.max_iterations;
  so.tolerance = m.options.tolerance;
  so.anderson = m.options.anderson;
  static_cast<fit::SolveReport&>(r) =
      m.solver.solve(problem, m.X, m.values, m.attracted ? &m.edit : nullptr, m.rest_measure, so);
  V_out = m.X;
  for (Eigen::Index k = 0; k < m.pins.size(); ++k)
    V_out.row(m.pins[k]) = V_edit.row(m.pins[k]);  // bit for bit
  r.measure = fit::total_measure(m.measure_kind, m.F, RowMatrix3(V_out));
  const double diag = (V_edit.colwise().maxCoeff() - V_edit.colwise().minCoeff()).norm();
  double err = 0;
  for (Eigen::Index k = 0; k < m.pins.size(); ++k)
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
