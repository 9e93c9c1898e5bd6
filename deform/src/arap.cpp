#include "spinmotor/deform/arap.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/deform/arap_rotation.hpp"
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
  const int n = static_cast<int>(rest.V.rows());

  // Phases: weights (cotangent Laplacian, corner cotangents), cells (one-ring CSR, the energy's
  // per-cell coefficients, the global matrix from the same weights), handles (component check and
  // the factorization of L_FF, bind_handles).
  const auto t_weights = Clock::now();
  Eigen::MatrixXd C;  // ½ cot per face corner (spokes and rims)
  try {
    d.L_ = cotangent_laplacian(rest.V, rest.F);
    if (options.energy == ArapEnergy::SpokesAndRims) C = 0.5 * cotangents(rest.V, rest.F);
  } catch (const Error&) {
    // A degenerate face, a bad index or a non-finite coordinate: require() names it in the words of
    // the mesh report ("ArapDeformer needs non-degenerate faces: face 2073 has zero area ...").
    require(rest, {.finite = true, .no_degenerate = true}, kWho);
    throw;
  }
  d.bind_report_.weights_ms = ms_since(t_weights);
  const auto t_cells = Clock::now();
  d.build_one_ring();
  d.w_.setZero(d.off_[n]);
  d.kappa_.setZero(d.off_[n], 3);
  d.h_.setZero(d.off_[n], 3);
  d.h_self_.setZero(n, 3);
  d.a_rest_.setZero(n);
  if (options.energy == ArapEnergy::Spokes)
    d.bind_spoke_cells();
  else
    d.bind_rim_cells(options.clamp_negative_weights ? Eigen::MatrixXd(C.cwiseMax(0.0)) : C);
  d.assemble_global_matrix();
  d.energy_scale_ = d.a_rest_.cwiseAbs().sum();
  d.find_unreferenced();
  d.bind_report_.cells_ms = ms_since(t_cells);
  d.bind_handles(handles);

  d.X_ = d.P_;
  d.rot_.assign(n, ga::Rot(1.0, 0.0, 0.0, 0.0));
  d.Rm_.assign(n, Eigen::Matrix3d::Identity());
  return d;
}

// ---- bind phases ---------------------------------------------------------------------------------

/// The one-ring CSR: the off-diagonal pattern of the cotangent Laplacian (rows sorted per column).
void ArapDeformer::build_one_ring() {
  const int n = static_cast<int>(P_.rows());
  off_.assign(n + 1, 0);
  for (int i = 0; i < n; ++i)
    for (Eigen::SparseMatrix<double>::InnerIterator it(L_, i); it; ++it)
      if (it.row() != i) ++off_[i + 1];
  for (int i = 0; i < n; ++i) off_[i + 1] += off_[i];
  nbr_.resize(off_[n]);
  for (int i = 0, k = 0; i < n; ++i)
    for (Eigen::SparseMatrix<double>::InnerIterator it(L_, i); it; ++it)
      if (it.row() != i) nbr_[k++] = static_cast<int>(it.row());
}

/// The CSR slot of neighbour j in vertex i's one-ring.
int ArapDeformer::slot(int i, int j) const {
  const auto b = nbr_.begin() + off_[i], e = nbr_.begin() + off_[i + 1];
  return static_cast<int>(std::lower_bound(b, e, j) - nbr_.begin());
}

/// Eq. (9): cell i = its spokes (i, j), w_ij = −L_ij. S_i = Σ_j w_ij e_ij e'_ijᵀ = Σ_j κ_ij (x'_j − x'_i)ᵀ
/// with κ_ij = −w_ij e_ij; eq. (12): B_i = ½ Σ_j w_ij (R_i + R_j) e_ij.
void ArapDeformer::bind_spoke_cells() {
  const int n = static_cast<int>(P_.rows());
  const bool clamp = options_.clamp_negative_weights;
  for (int i = 0; i < n; ++i) {
    int k = off_[i];
    for (Eigen::SparseMatrix<double>::InnerIterator it(L_, i); it; ++it) {
      if (it.row() == i) continue;
      const double w = clamp ? std::max(-it.value(), 0.0) : -it.value();
      const Eigen::RowVector3d e = P_.row(i) - P_.row(it.row());
      w_[k] = w;
      kappa_.row(k) = -w * e;
      h_.row(k) = 0.5 * w * e;
      h_self_.row(i) += 0.5 * w * e;
      a_rest_[i] += w * e.squaredNorm();
      ++k;
    }
  }
}

/// Spokes and rims: cell a = every face t ∋ a with its three edges e_k (opposite corner k, e_k =
/// x_{k+2} − x_{k+1}) weighted c_k = ½ cot of corner k (C, clamped if asked). Per face
/// Σ_k c_k e_k e'_kᵀ = Σ_k G_k x'_kᵀ with G_k = W_{k+1} − W_{k+2}, W_k = c_k e_k (Σ_k G_k = 0), and G_k is
/// also the face's share of (L x) at corner k, so B_a = ⅓ Σ_{t ∋ a} (R_t0 + R_t1 + R_t2) G_{t,k(a)}.
void ArapDeformer::bind_rim_cells(const Eigen::MatrixXd& C) {
  const int n = static_cast<int>(P_.rows());
  const Eigen::Index m = F_.rows();
  const RowMatrix3& P = P_;
  const Eigen::MatrixXi& F = F_;
  rim_off_.assign(n + 1, 0);
  for (Eigen::Index t = 0; t < m; ++t)
    for (int k = 0; k < 3; ++k) ++rim_off_[F(t, k) + 1];
  for (int i = 0; i < n; ++i) rim_off_[i + 1] += rim_off_[i];
  const int rims = rim_off_[n];
  rim_l_.resize(rims);
  rim_m_.resize(rims);
  rim_c_.resize(rims);
  std::vector<int> cursor(rim_off_.begin(), rim_off_.end() - 1);
  for (Eigen::Index t = 0; t < m; ++t) {
    Eigen::Matrix3d W;  // rows W_k
    double face_energy = 0.0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::RowVector3d e = P.row(F(t, (k + 2) % 3)) - P.row(F(t, (k + 1) % 3));
      W.row(k) = C(t, k) * e;
      face_energy += C(t, k) * e.squaredNorm();
    }
    Eigen::Matrix3d G;
    for (int k = 0; k < 3; ++k) G.row(k) = W.row((k + 1) % 3) - W.row((k + 2) % 3);
    for (int k = 0; k < 3; ++k) {
      const int a = F(t, k);
      for (int kk = 1; kk <= 2; ++kk) {
        const int kl = (k + kk) % 3, l = F(t, kl);
        const int s = slot(a, l);
        kappa_.row(s) += G.row(kl);
        h_.row(s) += G.row(k) / 3.0;
        w_[s] += C(t, 3 - k - kl);  // edge (a, l) is opposite the third corner
      }
      h_self_.row(a) += G.row(k) / 3.0;
      a_rest_[a] += face_energy;
      const int r = cursor[a]++;
      rim_l_[r] = F(t, (k + 1) % 3);
      rim_m_[r] = F(t, (k + 2) % 3);
      rim_c_[r] = C(t, k);
    }
  }
}

/// The global matrix from the cells' weights (eq. 12: Σ_j w_ij (x'_i − x'_j) = B_i), in place in L_.
void ArapDeformer::assemble_global_matrix() {
  const int n = static_cast<int>(P_.rows());
  for (int i = 0; i < n; ++i) {
    int k = off_[i];
    double diag = 0.0;
    double* diag_value = nullptr;
    for (Eigen::SparseMatrix<double>::InnerIterator it(L_, i); it; ++it) {
      if (it.row() == i) {
        diag_value = &it.valueRef();
        continue;
      }
      const int j = static_cast<int>(it.row());
      // Symmetric to the last bit: the lower-triangle weight is taken from the smaller index's slot.
      const double w = j > i ? w_[k] : w_[slot(j, i)];
      it.valueRef() = -w;
      diag += w;
      ++k;
    }
    if (diag_value) *diag_value = diag;
  }
}

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
  const std::vector<int> order = geometric_nested_dissection(P_, off_, nbr_, constrained);
  const int nf = static_cast<int>(order.size());

  // Fill-reducing ordering: AMD on L_FF, or the nested dissection above as is (natural); with Auto
  // both are analysed (symbolic only, cheap) and the one with fewer factorization flops is factorized.
  const bool supernodal =
      options_.factorization == Options::Factorization::Supernodal ||
      (options_.factorization == Options::Factorization::Auto && nf >= Options::kSupernodalFrom);
  DirichletSolver::Options o;
  o.cholesky.supernodal = supernodal;
  o.cholesky.ordering = options_.ordering == Ordering::NestedDissection ? Ordering::Natural : Ordering::AMD;
  o.cholesky.try_natural = options_.ordering == Ordering::Auto;
  dirichlet_ = DirichletSolver(o);
  L_.makeCompressed();
  try {
    dirichlet_.bind(L_,
                    Eigen::Map<const Eigen::VectorXi>(cons.data(), static_cast<Eigen::Index>(cons.size())),
                    Eigen::Map<const Eigen::VectorXi>(order.data(), nf), DirichletSolver::Kind::SPD);
  } catch (const FloatingComponentError& e) {
    throw_floating(e);
  } catch (const Error& e) {
    throw Error(std::string(kWho) +
                    ": factorizing the free block of the Laplacian failed (its row r is vertex "
                    "free_order()[r]): " +
                    e.what(),
                e.kind());
  }
  rhs_.setZero(nf, 3);
  const CholeskySolver& chol = dirichlet_.cholesky();
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
    harmonic_ = MotorBlendField::bind(Eigen::MatrixXd(P_), MotorBlendField::Weights(dirichlet_.solve(lambda)),
                                      ga::Blend::Log);
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

double ArapDeformer::cell_energy_direct(Eigen::Index i, const Eigen::Matrix3d& R, const RowMatrix3& X) const {
  double E = 0.0;
  for (int k = off_[i]; k < off_[i + 1]; ++k) {
    const int j = nbr_[k];
    const Eigen::Vector3d r = (X.row(j) - X.row(i)).transpose() - R * (P_.row(j) - P_.row(i)).transpose();
    E += w_[k] * r.squaredNorm();
  }
  if (!rim_off_.empty())
    for (int k = rim_off_[i]; k < rim_off_[i + 1]; ++k) {
      const int l = rim_l_[k], mm = rim_m_[k];
      const Eigen::Vector3d r = (X.row(mm) - X.row(l)).transpose() - R * (P_.row(mm) - P_.row(l)).transpose();
      E += rim_c_[k] * r.squaredNorm();
    }
  return E;
}

namespace {

/// S_i = Σ_k κ_k (x'_j − x'_i)ᵀ and a'_i = Σ_k w_k |x'_j − x'_i|² + Σ_rims c |x'_m − x'_l|².
[[gnu::always_inline]] inline void cell_covariance(Eigen::Index i, const int* off, const int* nbr,
                                                   const double* w, const double* kappa, const int* rim_off,
                                                   const int* rim_l, const int* rim_m, const double* rim_c,
                                                   const double* X, Eigen::Matrix3d& S, double& ap) {
  const double x0 = X[3 * i], x1 = X[3 * i + 1], x2 = X[3 * i + 2];
  double s00 = 0, s01 = 0, s02 = 0, s10 = 0, s11 = 0, s12 = 0, s20 = 0, s21 = 0, s22 = 0, q = 0;
  for (int k = off[i]; k < off[i + 1]; ++k) {
    const double* xj = X + 3 * static_cast<Eigen::Index>(nbr[k]);
    const double d0 = xj[0] - x0, d1 = xj[1] - x1, d2 = xj[2] - x2;
    const double k0 = kappa[3 * k], k1 = kappa[3 * k + 1], k2 = kappa[3 * k + 2];
    s00 += k0 * d0, s01 += k0 * d1, s02 += k0 * d2;
    s10 += k1 * d0, s11 += k1 * d1, s12 += k1 * d2;
    s20 += k2 * d0, s21 += k2 * d1, s22 += k2 * d2;
    q += w[k] * (d0 * d0 + d1 * d1 + d2 * d2);
  }
  if (rim_off)
    for (int k = rim_off[i]; k < rim_off[i + 1]; ++k) {
      const double* xl = X + 3 * static_cast<Eigen::Index>(rim_l[k]);
      const double* xm = X + 3 * static_cast<Eigen::Index>(rim_m[k]);
      const double e0 = xm[0] - xl[0], e1 = xm[1] - xl[1], e2 = xm[2] - xl[2];
      q += rim_c[k] * (e0 * e0 + e1 * e1 + e2 * e2);
    }
  S << s00, s01, s02, s10, s11, s12, s20, s21, s22;
  ap = q;
}

}  // namespace

double ArapDeformer::local_step() {
  const Eigen::Index n = P_.rows();
  const int* rim_off = rim_off_.empty() ? nullptr : rim_off_.data();
  double total = 0.0;
  Eigen::Index jacobi = 0;
#pragma omp parallel for schedule(static) reduction(+ : total, jacobi) if (parallel::worth(n, parallel::kRotationFit))
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Matrix3d S;
    double ap;
    cell_covariance(i, off_.data(), nbr_.data(), w_.data(), kappa_.data(), rim_off, rim_l_.data(),
                    rim_m_.data(), rim_c_.data(), X_.data(), S, ap);
    RotationInfo info;
    const ga::Rot q = best_rotation(S, rot_[i], &info);  // §VII: Horn's quaternion, largest eigenvector
    jacobi += !info.fast;
    const Eigen::Matrix3d R = rotation_matrix(q);
    const double trRS = R.cwiseProduct(S.transpose()).sum();
    // Cell energy Σ w |e' − R e|² = Σ w |e'|² + Σ w |e|² − 2 tr(R S); term by term where that cancels.
    double E = a_rest_[i] + ap - 2.0 * trRS;
    if (!(E > 1e-6 * (std::abs(a_rest_[i]) + std::abs(ap)))) E = cell_energy_direct(i, R, X_);
    rot_[i] = q;
    Rm_[i] = R;
    total += E;
  }
  report_.jacobi_rotations += jacobi;
  return total;
}

void ArapDeformer::global_step() {
  const Eigen::VectorXi& free_order = dirichlet_.free();
  const Eigen::Index nf = free_order.size();
  if (nf == 0) return;
  auto t = Clock::now();
  // Eq. (12)–(13): rhs_k = B_i − (L_FC X_C)_k for the free vertex i of row k, B_i = R_i h_i + Σ_j R_j h_ij.
#pragma omp parallel for schedule(static) if (parallel::worth(nf, parallel::kRotationFit))
  for (Eigen::Index k = 0; k < nf; ++k) {
    const int i = free_order[k];
    Eigen::Vector3d b = Rm_[i] * h_self_.row(i).transpose();
    for (int s = off_[i]; s < off_[i + 1]; ++s) b.noalias() += Rm_[nbr_[s]] * h_.row(s).transpose();
    rhs_(k, 0) = b[0] - FCX_(k, 0), rhs_(k, 1) = b[1] - FCX_(k, 1), rhs_(k, 2) = b[2] - FCX_(k, 2);
  }
  report_.rhs_ms += ms_since(t);
  t = Clock::now();
  XF_ = dirichlet_.solve_free(rhs_);  // L_FF X_F = B_F − L_FC X_C, three columns at once
  report_.solve_ms += ms_since(t);
#pragma omp parallel for schedule(static) if (parallel::worth(nf, parallel::kRotationFit))
  for (Eigen::Index k = 0; k < nf; ++k) {
    const int i = free_order[k];
    X_(i, 0) = XF_(k, 0), X_(i, 1) = XF_(k, 1), X_(i, 2) = XF_(k, 2);
  }
}

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
  std::vector<double> energy = std::move(report_.energy);  // keep its capacity: no allocation per pose
  energy.clear();
  report_ = ArapReport{};
  report_.energy = std::move(energy);

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
  for (Eigen::Index r = 0; r < constrained_.size(); ++r) X_.row(constrained_[r]) = values_.row(r);
  // The handles' share of the right-hand side, fixed during the iteration.
  FCX_.noalias() = dirichlet_.free_constrained_block() * values_;
  report_.initial_ms = ms_since(t0);

  double E_prev = 0.0;
  int it = 0;
  for (;; ++it) {
    auto t = Clock::now();
    const double E = local_step();  // E(X'_it) and the rotors for the next global step
    report_.local_ms += ms_since(t);
    if (!std::isfinite(E)) {
      std::ostringstream s;
      s << kWho << ": the energy is not finite at iteration " << it;
      throw numerical_error(s.str());
    }
    report_.energy.push_back(E);
    if (it > 0 && E_prev - E <= options_.tolerance * E_prev) {
      report_.converged = true;
      break;
    }
    if (E <= 1e-24 * energy_scale_) {
      report_.converged = true;
      break;
    }
    if (it == options_.iterations) break;
    t = Clock::now();
    global_step();
    report_.global_ms += ms_since(t);
    E_prev = E;
  }
  report_.iterations = it;
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
  const RowMatrix3 X = V;
  const Eigen::Index n = P_.rows();
  const int* rim_off = rim_off_.empty() ? nullptr : rim_off_.data();
  double total = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : total) if (parallel::worth(n, parallel::kRotationFit))
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Matrix3d S;
    double ap;
    cell_covariance(i, off_.data(), nbr_.data(), w_.data(), kappa_.data(), rim_off, rim_l_.data(),
                    rim_m_.data(), rim_c_.data(), X.data(), S, ap);
    total += cell_energy_direct(i, rotation_matrix(best_rotation(S)), X);
  }
  return total;
}

}  // namespace spinmotor
