#include "spinmotor/deform/arap.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/ga/rotor_fit.hpp"
#include "spinmotor/linalg/geometric_ordering.hpp"
#include "spinmotor/mesh/cotangent_laplacian.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/validate.hpp"  // require(): names a degenerate face

namespace spinmotor {

namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kWho = "ArapDeformer";
// Loops over fewer vertices run serially: waking the threads every iteration costs more than it saves.

/// Cheap unit-motor check (no string built on the good path); the message comes from checked_unit_motor.
ga::Mot unit_motor(const ga::Mot& m, std::size_t j, const std::string& handle) {
  bool finite = true;
  for (double c : m.c) finite = finite && std::isfinite(c);
  if (finite) {
    const auto nn = m * ga::reverse(m);
    const double alpha = nn.get<ga::blade::s>(), beta = nn.get<ga::blade::e123ni>();
    if (std::abs(alpha - 1.0) <= 1e-6 && std::abs(beta) <= 1e-6) return ga::normalize(m);
  }
  return checked_unit_motor(
      m, std::string(kWho) + ": motor " + std::to_string(j) + " (handle '" + handle + "')");
}

}  // namespace

ArapDeformer ArapDeformer::bind(const Mesh& rest, std::span<const Handle> handles) {
  return bind(rest, handles, Options{});
}

ArapDeformer ArapDeformer::bind(const Mesh& rest, std::span<const Handle> handles, const Options& options) {
  if (options.iterations < 0)
    throw Error(std::string(kWho) + ": iterations must be >= 0, got " + std::to_string(options.iterations));
  if (!(options.tolerance >= 0.0) || !std::isfinite(options.tolerance))
    throw Error(std::string(kWho) + ": tolerance must be finite and >= 0, got " +
                std::to_string(options.tolerance));
  require_ordering(options.ordering, Options::kOrderings, kWho);
  if (handles.empty())
    throw Error(std::string(kWho) +
                ": needs at least one handle (ARAP is determined only up to a rigid motion)");
  check_handles(handles, rest.V.rows(), kWho);

  ArapDeformer d;
  d.options_ = options;
  d.F_ = rest.F;
  d.P_ = rest.V;

  // Phases: weights (cotangent Laplacian, corner cotangents), cells (fit::RigidCells: the one-ring CSR,
  // the energy's per-cell coefficients, the global matrix from the same weights), handles (component
  // check and the factorization of L_FF, bind_handles).
  const auto t_weights = Clock::now();
  Eigen::SparseMatrix<double> L;
  Eigen::MatrixXd C;  // ½ cot per face corner (spokes and rims)
  try {
    L = cotangent_laplacian(rest.V, rest.F);
    if (options.energy == ArapEnergy::SpokesAndRims) C = 0.5 * cotangents(rest.V, rest.F);
  } catch (const Error&) {
    // A degenerate face, a bad index or a non-finite coordinate: require() names it in the words of
    // the mesh report ("ArapDeformer needs non-degenerate faces: face 2073 has zero area ...").
    require(rest, {.finite = true, .no_degenerate = true}, kWho);
    throw;
  }
  d.bind_report_.weights_ms = ms_since(t_weights);
  const auto t_cells = Clock::now();
  d.cells_ =
      fit::RigidCells::bind(d.P_, d.F_, L, C,
                            options.energy == ArapEnergy::Spokes ? fit::RigidCells::Kind::Spokes
                                                                 : fit::RigidCells::Kind::SpokesAndRims,
                            options.clamp_negative_weights);
  d.find_unreferenced();
  d.bind_report_.cells_ms = ms_since(t_cells);
  d.bind_handles(handles);
  d.X_ = d.P_;
  return d;
}

// ---- bind phases ---------------------------------------------------------------------------------

/// Vertices that no face references: constrained at rest (or by their handle).
void ArapDeformer::find_unreferenced() {
  const int n = static_cast<int>(P_.rows());
  std::vector<char> referenced(n, 0);
  for (Eigen::Index t = 0; t < F_.rows(); ++t)
    for (int k = 0; k < 3; ++k) referenced[F_(t, k)] = 1;
  std::vector<int> unref;
  for (int i = 0; i < n; ++i)
    if (!referenced[i]) unref.push_back(i);
  unreferenced_ = Eigen::Map<Eigen::VectorXi>(unref.data(), static_cast<Eigen::Index>(unref.size()));
}

void ArapDeformer::bind_handles(std::span<const Handle> handles) {
  controls_ = handle_controls(Eigen::MatrixXd(P_), handles);
  const int n = static_cast<int>(P_.rows());
  std::vector<int> handle_of(n, -1);
  std::vector<int> cons, cons_handle;
  for (std::size_t h = 0; h < handles.size(); ++h)
    for (Eigen::Index k = 0; k < handles[h].vertices.size(); ++k) {
      handle_of[handles[h].vertices[k]] = static_cast<int>(h);
      cons.push_back(handles[h].vertices[k]);
      cons_handle.push_back(static_cast<int>(h));
    }
  for (Eigen::Index k = 0; k < unreferenced_.size(); ++k)
    if (handle_of[unreferenced_[k]] < 0) {
      cons.push_back(unreferenced_[k]);
      cons_handle.push_back(-1);
    }

  // Every component needs a handle vertex (ogre.obj: 44 components): checked by the DirichletSolver
  // in factorize().
  const auto t_factor = Clock::now();
  factorize(cons);
  constrained_ = Eigen::Map<const Eigen::VectorXi>(cons.data(), static_cast<Eigen::Index>(cons.size()));
  constrained_handle_ =
      Eigen::Map<Eigen::VectorXi>(cons_handle.data(), static_cast<Eigen::Index>(cons_handle.size()));
  handle_sets_.clear();
  handle_names_.clear();
  for (const Handle& h : handles) {
    handle_sets_.push_back(h.vertices);
    handle_names_.push_back(h.name);
  }
  values_.setZero(constrained_.size(), 3);
  bind_report_.factor_ms = ms_since(t_factor);
  bind_harmonic();
}

namespace {

/// ARAP's words for the components without a handle (the DirichletSolver found them).
[[noreturn]] void throw_floating(const FloatingComponentError& e) {
  const auto& missing = e.floating();
  const FloatingComponentError::Component& c = missing[0];
  std::ostringstream s;
  s << kWho << ": connected component " << c.id << " of " << e.count() << " (" << c.size
    << " vertices, e.g. vertex " << c.first
    << ") has no handle vertex, so its position is undetermined: add a handle on it";
  if (missing.size() > 1) {
    s << " (" << missing.size() << " components have none:";
    for (std::size_t k = 0; k < std::min<std::size_t>(missing.size(), 8); ++k)
      s << " " << missing[k].id << " (vertex " << missing[k].first << ")";
    if (missing.size() > 8) s << " ...";
    s << ")";
  }
  throw Error(s.str());
}

}  // namespace

void ArapDeformer::factorize(const std::vector<int>& cons) {
  const int n = static_cast<int>(P_.rows());
  // Free vertices in a geometric nested-dissection order: the rows of L_FF.
  std::vector<char> constrained(n, 0);
  for (int v : cons) constrained[v] = 1;
  const std::vector<int> order = geometric_nested_dissection(P_, cells_.off(), cells_.nbr(), constrained);
  const int nf = static_cast<int>(order.size());

  // Fill-reducing ordering: AMD on L_FF, or the nested dissection above as is (natural); with Auto
  // both are analysed (symbolic only, cheap) and the one with fewer factorization flops is factorized.
  const bool supernodal =
      options_.factorization == Options::Factorization::Supernodal ||
      (options_.factorization == Options::Factorization::Auto && nf >= Options::kSupernodalFrom);
  fit::LocalGlobal::Bind b;
  b.solver.cholesky.supernodal = supernodal;
  b.solver.cholesky.ordering =
      options_.ordering == Ordering::NestedDissection ? Ordering::Natural : Ordering::AMD;
  b.solver.cholesky.try_natural = options_.ordering == Ordering::Auto;
  b.L = cells_.global_matrix();
  b.constrained = Eigen::Map<const Eigen::VectorXi>(cons.data(), static_cast<Eigen::Index>(cons.size()));
  b.free_order = Eigen::Map<const Eigen::VectorXi>(order.data(), nf);
  try {
    solver_.bind(b);
  } catch (const FloatingComponentError& e) {
    throw_floating(e);
  } catch (const Error& e) {
    throw Error(std::string(kWho) +
                    ": factorizing the free block of the Laplacian failed (its row r is vertex "
                    "free_order()[r]): " +
                    e.what(),
                e.kind());
  }
  const CholeskySolver& chol = solver_.dirichlet().cholesky();
  bind_report_.ordering =
      nf == 0 ? "none"
              : std::string(option_name(chol.ordering_used() == Ordering::Natural ? Ordering::NestedDissection
                                                                                  : Ordering::AMD));
  bind_report_.factor_nonzeros = nf == 0 ? 0.0 : chol.factor_nonzeros();
  bind_report_.factor_flops = nf == 0 ? 0.0 : chol.factor_flops();
  bind_report_.supernodal = supernodal;
}

void ArapDeformer::bind_harmonic() {
  const auto t_harmonic = Clock::now();
  has_harmonic_ = false;
  if (options_.initial == ArapInitial::Harmonic) {
    // §IV with cotangent weights: λ_j = 1 on handle j, 0 on the others (unreferenced vertices: any
    // partition of unity, their positions are fixed anyway), one solve with k right-hand sides.
    const Eigen::Index k = static_cast<Eigen::Index>(handle_sets_.size());
    Eigen::MatrixXd lambda = Eigen::MatrixXd::Zero(constrained_.size(), k);
    for (Eigen::Index r = 0; r < constrained_.size(); ++r)
      lambda(r, std::max(constrained_handle_[r], 0)) = 1.0;
    harmonic_ = MotorBlendField::bind(
        Eigen::MatrixXd(P_), MotorBlendField::Weights(solver_.dirichlet().solve(lambda)), ga::Blend::Log);
    has_harmonic_ = true;
  }
  bind_report_.harmonic_ms = ms_since(t_harmonic);
}

bool ArapDeformer::set_handles(std::span<const Handle> handles) {
  if (handles.empty())
    throw Error(std::string(kWho) +
                ": needs at least one handle (ARAP is determined only up to a rigid motion)");
  check_handles(handles, P_.rows(), kWho);
  // Same union of constrained vertices (handles + unreferenced) → keep the factorization.
  std::vector<int> now(constrained_.data(), constrained_.data() + constrained_.size());
  std::vector<int> next;
  std::vector<char> in_handle(P_.rows(), 0);
  for (const Handle& h : handles)
    for (Eigen::Index k = 0; k < h.vertices.size(); ++k)
      next.push_back(h.vertices[k]), in_handle[h.vertices[k]] = 1;
  for (Eigen::Index k = 0; k < unreferenced_.size(); ++k)
    if (!in_handle[unreferenced_[k]]) next.push_back(unreferenced_[k]);
  std::sort(now.begin(), now.end());
  std::sort(next.begin(), next.end());
  if (now != next) {
    bind_handles(handles);
    return true;
  }
  std::vector<int> handle_of(P_.rows(), -1);
  for (std::size_t h = 0; h < handles.size(); ++h)
    for (Eigen::Index k = 0; k < handles[h].vertices.size(); ++k)
      handle_of[handles[h].vertices[k]] = static_cast<int>(h);
  for (Eigen::Index r = 0; r < constrained_.size(); ++r) constrained_handle_[r] = handle_of[constrained_[r]];
  handle_sets_.clear();
  handle_names_.clear();
  for (const Handle& h : handles) {
    handle_sets_.push_back(h.vertices);
    handle_names_.push_back(h.name);
  }
  bind_harmonic();
  return false;
}

/// The solve's Problem: ARAP's rigid cells (fit/cells.hpp) with the energy unnormalised.
struct ArapDeformer::Cells final : fit::Problem {
  fit::RigidCells& cells;
  explicit Cells(fit::RigidCells& c) : cells(c) {}
  double fit(const fit::RowMatrix3& X, int, fit::SolveReport& r) override {
    return cells.fit(X, r.fallback_fits);
  }
  void rhs(int, const fit::LocalGlobal& solver, fit::RowMatrix3& B) override { cells.rhs(solver.free(), B); }
  double energy_scale() const override { return cells.energy_scale(); }
};

void ArapDeformer::pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out) {
  const auto t0 = Clock::now();
  const std::size_t k = handle_sets_.size();
  if (motors.size() != k) {
    std::ostringstream s;
    s << kWho << ": pose() got " << motors.size() << " motors for " << k << " handles";
    throw Error(s.str());
  }
  motors_.resize(k);
  for (std::size_t j = 0; j < k; ++j) motors_[j] = unit_motor(motors[j], j, handle_names_[j]);
  report_ = ArapReport{};

  // Handles placed by their motors; unreferenced vertices stay at rest.
  for (Eigen::Index r = 0; r < constrained_.size(); ++r) {
    const int h = constrained_handle_[r];
    const Eigen::Vector3d p = P_.row(constrained_[r]).transpose();
    values_.row(r) = (h >= 0 ? ga::transform(motors_[h], p) : p).transpose();
  }
  const bool previous = options_.initial == ArapInitial::Previous && has_previous_;
  if (!previous) {
    if (options_.initial == ArapInitial::Harmonic && has_harmonic_) {
      harmonic_.pose(motors_, Xcol_);
      X_ = Xcol_;
    } else {
      X_ = P_;
    }
  }
  report_.initial_ms = ms_since(t0);
  fit::SolveOptions so;
  so.max_iterations = options_.iterations;
  so.tolerance = options_.tolerance;
  Cells problem(cells_);
  try {
    static_cast<fit::SolveReport&>(report_) = solver_.solve(problem, X_, values_, nullptr, 0.0, so);
  } catch (const Error& e) {
    throw Error(std::string(kWho) + ": " + e.what(), e.kind());
  }
  if (V_out.rows() != X_.rows() || V_out.cols() != 3) V_out.resize(X_.rows(), 3);
  V_out = X_;
  has_previous_ = true;
}

double ArapDeformer::energy(const Eigen::MatrixXd& V) const {
  if (V.rows() != P_.rows() || V.cols() != 3) {
    std::ostringstream s;
    s << kWho << ": energy() got " << V.rows() << "x" << V.cols() << " positions for " << P_.rows()
      << " vertices";
    throw Error(s.str());
  }
  return cells_.energy(RowMatrix3(V));
}

}  // namespace spinmotor
