#include "spinmotor/spin/conformal_snap.hpp"

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/ga/quaternion.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/mass_matrix.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/mesh/validate.hpp"

namespace spinmotor {

namespace {

using Clock = std::chrono::steady_clock;

ga::Quat row_quat(const Eigen::MatrixXd& Q, Eigen::Index i) {
  return ga::Quat(Q(i, 0), Q(i, 1), Q(i, 2), Q(i, 3));
}

void check_positions(const Eigen::MatrixXd& V, Eigen::Index n, const char* what) {
  if (V.rows() != n || V.cols() != 3) {
    std::ostringstream m;
    m << "conformal_snap: " << what << " has " << V.rows() << " x " << V.cols()
      << " coordinates, the rest mesh " << n << " x 3 (same vertex count and order needed)";
    throw Error(m.str());
  }
  for (Eigen::Index i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(V(i, c))) {
        std::ostringstream m;
        m << "conformal_snap: " << what << " vertex " << i << " coordinate "
          << "xyz"[c] << " is not finite (" << V(i, c) << ")";
        throw Error(m.str());
      }
}

// Orthonormal frame [u w n] of a triangle's plane (u along e1, n the CCW normal) and the 2×2 matrix
// of its edges e1, e2 in that frame. Returns false if the triangle is collapsed.
bool planar_frame(const Eigen::Vector3d& e1, const Eigen::Vector3d& e2, Eigen::Matrix3d& frame,
                  Eigen::Matrix2d& P) {
  const Eigen::Vector3d c = e1.cross(e2);
  const double l2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (e2 - e1).squaredNorm()});
  if (!(c.norm() > kDegenerateFace * l2)) return false;
  const Eigen::Vector3d n = c.normalized(), u = e1.normalized(), w = n.cross(u);
  frame.col(0) = u, frame.col(1) = w, frame.col(2) = n;
  P << e1.dot(u), e2.dot(u), 0.0, e2.dot(w);
  return true;
}

}  // namespace

Eigen::MatrixXd best_fit_similarities(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                      const Eigen::MatrixXd& V_edit, Eigen::Index* collapsed) {
  const Eigen::Index n = V_rest.rows(), m = F.rows();
  check_positions(V_rest, n, "rest mesh");
  check_positions(V_edit, n, "edited mesh");
  if (F.cols() != 3) throw Error("conformal_snap: F must be m x 3");
  Eigen::MatrixXd S(m, 4);
  Eigen::Index bad = 0;
  for (Eigen::Index f = 0; f < m; ++f) {
    int idx[3];
    for (int c = 0; c < 3; ++c) {
      idx[c] = F(f, c);
      if (idx[c] < 0 || idx[c] >= n) {
        std::ostringstream msg;
        msg << "conformal_snap: face " << f << " has vertex index " << idx[c] << " outside [0, " << n << ")";
        throw Error(msg.str());
      }
    }
    Eigen::Matrix3d F1, F2;
    Eigen::Matrix2d P1, P2;
    const Eigen::Vector3d p0 = V_rest.row(idx[0]).transpose(), q0 = V_edit.row(idx[0]).transpose();
    if (!planar_frame(V_rest.row(idx[1]).transpose() - p0, V_rest.row(idx[2]).transpose() - p0, F1, P1)) {
      std::ostringstream msg;
      msg << "conformal_snap: rest face " << f << " is degenerate";
      throw Error(msg.str());
    }
    if (!planar_frame(V_edit.row(idx[1]).transpose() - q0, V_edit.row(idx[2]).transpose() - q0, F2, P2)) {
      S.row(f).setZero();
      ++bad;
      continue;
    }
    // B maps the rest triangle's planar coordinates to the edit's (det B > 0: both planes are
    // oriented by their own normals). B = RY: R is the rotation by the angle of B's conformal part,
    // and det Y = det B.
    const Eigen::Matrix2d B = P2 * P1.inverse();
    const double theta = std::atan2(B(1, 0) - B(0, 1), B(0, 0) + B(1, 1));
    const double sigma = std::sqrt(B.determinant());
    Eigen::Matrix3d R2 = Eigen::Matrix3d::Identity();
    R2(0, 0) = std::cos(theta), R2(0, 1) = -std::sin(theta);
    R2(1, 0) = std::sin(theta), R2(1, 1) = std::cos(theta);
    // §7.2: S = sqrt(det Y) A₂⁻¹ R A₁ with A_k = F_kᵀ (rest/edit frame → common plane).
    const Eigen::Matrix3d rot = F2 * R2 * F1.transpose();
    const Eigen::Quaterniond q(rot);  // rot v = q v q̄
    // conj(μ) v μ = σ q v q̄  ⇔  μ = sqrt(σ) q̄.
    const double s = std::sqrt(sigma);
    S.row(f) << s * q.w(), -s * q.x(), -s * q.y(), -s * q.z();
  }
  if (collapsed) *collapsed = bad;
  return S;
}

Eigen::MatrixXd vertex_similarities(const Eigen::MatrixXi& F, Eigen::Index n, const Eigen::MatrixXd& Sf,
                                    const Eigen::VectorXd& face_weights) {
  const Eigen::Index m = F.rows();
  if (Sf.rows() != m || Sf.cols() != 4 || face_weights.size() != m)
    throw Error("vertex_similarities: Sf must be m x 4 and face_weights m values (m = faces)");
  // Signs: breadth-first over faces across shared edges, each face aligned with the face it was
  // reached from (q and −q: Re(q̄ p) ≥ 0 between neighbours).
  Eigen::MatrixXd Q = Sf;
  std::vector<char> valid(m), seen(m, 0);
  for (Eigen::Index f = 0; f < m; ++f) valid[f] = Q.row(f).squaredNorm() > 0 && face_weights[f] > 0;
  const EdgeTopology topo = edge_topology(F);
  std::vector<Eigen::Index> queue;
  queue.reserve(m);
  for (Eigen::Index root = 0; root < m; ++root) {
    if (seen[root] || !valid[root]) continue;
    seen[root] = 1;
    queue.assign(1, root);
    for (std::size_t h = 0; h < queue.size(); ++h) {
      const Eigen::Index f = queue[h];
      for (int c = 0; c < 3; ++c) {
        const int e = topo.FE(f, c);
        for (int k = topo.EF_offset[e]; k < topo.EF_offset[e + 1]; ++k) {
          const int g = topo.EF_face[k];
          if (seen[g] || !valid[g]) continue;
          seen[g] = 1;
          if (Q.row(g).dot(Q.row(f)) < 0) Q.row(g) *= -1.0;
          queue.push_back(g);
        }
      }
    }
  }
  // Weighted averages, each incident face aligned with the vertex's first one (a no-op unless the
  // propagation met a sign conflict, i.e. a field with no consistent lift around some loop).
  Eigen::MatrixXd mu = Eigen::MatrixXd::Zero(n, 4);
  Eigen::MatrixXd first = Eigen::MatrixXd::Zero(n, 4);
  std::vector<char> has(n, 0);
  for (Eigen::Index f = 0; f < m; ++f) {
    if (!valid[f]) continue;
    for (int c = 0; c < 3; ++c) {
      const int i = F(f, c);
      Eigen::RowVector4d q = Q.row(f);
      if (!has[i]) {
        has[i] = 1;
        first.row(i) = q;
      } else if (q.dot(first.row(i)) < 0) {
        q = -q;
      }
      mu.row(i) += face_weights[f] * q;
    }
  }
  Eigen::VectorXd wsum = Eigen::VectorXd::Zero(n);
  for (Eigen::Index f = 0; f < m; ++f)
    if (valid[f])
      for (int c = 0; c < 3; ++c) wsum[F(f, c)] += face_weights[f];
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(wsum[i] > 0)) {
      std::ostringstream msg;
      msg << "vertex_similarities: vertex " << i
          << " has no incident face with a similarity (all collapsed?)";
      throw Error(msg.str());
    }
    mu.row(i) /= wsum[i];
  }
  // Global sign (the whole field's −μ is the same similarity field): first nonzero summed component
  // positive, so that the output does not depend on the sign of the root face.
  const Eigen::RowVector4d sum = mu.colwise().sum();
  for (int c = 0; c < 4; ++c)
    if (std::abs(sum[c]) > 1e-12 * sum.norm()) {
      if (sum[c] < 0) mu *= -1.0;
      break;
    }
  return mu;
}

Eigen::VectorXd nearest_rho(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& mu) {
  const Eigen::Index m = F.rows();
  if (mu.rows() != V.rows() || mu.cols() != 4) throw Error("nearest_rho: mu must be n x 4");
  Eigen::VectorXd rho(m);
  for (Eigen::Index f = 0; f < m; ++f) {
    Eigen::Vector3d p[3];
    ga::Quat q[3];
    for (int c = 0; c < 3; ++c) p[c] = V.row(F(f, c)).transpose(), q[c] = row_quat(mu, F(f, c));
    const double A = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    if (!(A > 0)) {
      std::ostringstream msg;
      msg << "nearest_rho: face " << f << " is degenerate";
      throw Error(msg.str());
    }
    // (Dμ)_f = Σ_c −e_c μ_c / (2A) (eq. 5), e_c opposite corner c, CCW; (Bμ)_f = Σ_c μ_c / 3 (§5.3).
    ga::Quat Dmu(0.0, 0.0, 0.0, 0.0), Bmu(0.0, 0.0, 0.0, 0.0);
    for (int c = 0; c < 3; ++c) {
      const ga::Quat e = ga::imaginary(p[(c + 2) % 3] - p[(c + 1) % 3]);
      Dmu += (-1.0 / (2.0 * A)) * (e * q[c]);
      Bmu += (1.0 / 3.0) * q[c];
    }
    const double b2 = ga::norm2(Bmu);
    if (!(b2 > 0)) {
      std::ostringstream msg;
      msg << "nearest_rho: the averaged similarity (B mu) vanishes on face " << f;
      throw numerical_error(msg.str());
    }
    // §7.2: ρ_f = Re(conj(Bμ)_f (Dμ)_f) / |(Bμ)_f|².
    rho[f] = (ga::conj(Bmu) * Dmu).w() / b2;
  }
  return rho;
}

struct ConformalSnap::Impl {
  Mesh rest;
  ConformalSnapOptions opt;
  bool open = false;
  std::optional<SpinTransform> st;  // bound once unless the boundary tangents follow the edit
  Eigen::VectorXd face_area, vertex_area;
  std::vector<int> next;  // boundary successor (surface on the left), −1 inside
  double mean_edge = 1;   // mean edge length of the rest mesh
  EdgeTopology topo;      // face adjacency for rho_smoothing
  double bind_ms = 0;

  SpinTransformOptions spin_options() const {
    SpinTransformOptions so;
    so.problem = opt.problem;
    so.tolerance = opt.tolerance;
    so.iterations = opt.iterations;
    so.ordering = opt.ordering;
    so.scale = SpinScale::None;  // keep the scale and rotation λ carries (aligned with μ)
    return so;
  }
};

ConformalSnap::ConformalSnap(const Mesh& rest, const ConformalSnapOptions& options)
    : impl_(std::make_unique<Impl>()) {
  const auto t0 = Clock::now();
  Impl& s = *impl_;
  s.rest.V = rest.V;
  s.rest.F = rest.F;
  s.opt = options;
  set_tradeoff(options.tradeoff);
  if (options.problem == SpinEigenProblem::Unweighted)
    throw Error("conformal_snap: problem must be standard (eq. 7) or generalized (eq. 6)");
  require(s.rest,
          {.finite = true,
           .manifold = true,
           .oriented = true,
           .no_degenerate = true,
           .closed = options.problem == SpinEigenProblem::Generalized,
           .single_component = true,
           .no_unreferenced = true},
          "conformal_snap");
  const Eigen::Index n = rest.V.rows();
  s.face_area = face_areas(rest.V, rest.F);
  s.vertex_area = barycentric_vertex_areas(rest.F, s.face_area, n);
  {
    double sum = 0;
    for (Eigen::Index f = 0; f < rest.F.rows(); ++f)
      for (int c = 0; c < 3; ++c)
        sum += (rest.V.row(rest.F(f, c)) - rest.V.row(rest.F(f, (c + 1) % 3))).norm();
    s.mean_edge = sum / (3.0 * static_cast<double>(rest.F.rows()));
  }
  if (options.rho_smoothing < 0) throw Error("conformal_snap: rho_smoothing must be >= 0");
  if (options.rho_smoothing > 0) s.topo = edge_topology(rest.F);
  s.next.assign(n, -1);
  for (const auto& loop : boundary_loops(rest.F)) {
    s.open = true;
    for (std::size_t k = 0; k < loop.size(); ++k) s.next[loop[k]] = loop[(k + 1) % loop.size()];
  }
  if (!(s.open && options.boundary_tangents)) s.st.emplace(s.rest, s.spin_options());
  s.bind_ms = ms_since(t0);
}

ConformalSnap::~ConformalSnap() = default;
ConformalSnap::ConformalSnap(ConformalSnap&&) noexcept = default;
ConformalSnap& ConformalSnap::operator=(ConformalSnap&&) noexcept = default;

const ConformalSnapOptions& ConformalSnap::options() const { return impl_->opt; }
double ConformalSnap::bind_ms() const { return impl_->bind_ms; }
const Mesh& ConformalSnap::rest() const { return impl_->rest; }
void ConformalSnap::set_tradeoff(double t) {
  if (!(t >= 0.0 && t <= 1.0)) {
    std::ostringstream m;
    m << "conformal_snap: tradeoff " << t << " is outside [0, 1]";
    throw Error(m.str());
  }
  impl_->opt.tradeoff = t;
}

ConformalSnapResult ConformalSnap::snap(const Eigen::MatrixXd& V_edit) {
  Impl& s = *impl_;
  check_positions(V_edit, s.rest.V.rows(), "edited mesh");
  const auto t0 = Clock::now();
  Eigen::Index collapsed = 0;
  const Eigen::MatrixXd Sf = best_fit_similarities(s.rest.V, s.rest.F, V_edit, &collapsed);
  const double fit_ms = ms_since(t0);
  ConformalSnapResult r = snap_face_similarities(Sf, V_edit);
  r.collapsed_faces = collapsed;
  r.timings.similarity_fit += fit_ms;
  return r;
}

ConformalSnapResult ConformalSnap::snap_face_similarities(const Eigen::MatrixXd& Sf,
                                                          const Eigen::MatrixXd& V_edit) {
  Impl& s = *impl_;
  const Eigen::Index n = s.rest.V.rows(), m = s.rest.F.rows();
  check_positions(V_edit, n, "edited mesh");
  if (Sf.rows() != m || Sf.cols() != 4 || !Sf.allFinite())
    throw Error(
        "conformal_snap: face similarities must be a finite m x 4 matrix (m = faces of the rest mesh)");
  ConformalSnapResult r;
  auto t = Clock::now();
  r.mu = vertex_similarities(s.rest.F, n, Sf, s.face_area);
  r.rho = nearest_rho(s.rest.V, s.rest.F, r.mu);
  // An edit that is a similarity up to rounding gives ρ at roundoff level (≈ 1e-16/h); eq. 6 with
  // such a ρ would factor a singular A*A (its kernel, the constants, is only perturbed by rounding).
  // Below 1e-10/h the field is the similarity's ρ = 0, which both problems solve exactly.
  if (r.rho.cwiseAbs().maxCoeff() * s.mean_edge < 1e-10) r.rho.setZero();
  for (int pass = 0; pass < s.opt.rho_smoothing; ++pass) {
    Eigen::VectorXd sm(m);
    for (Eigen::Index f = 0; f < m; ++f) {
      double num = s.face_area[f] * r.rho[f], den = s.face_area[f];
      for (int c = 0; c < 3; ++c) {
        const int e = s.topo.FE(f, c);
        for (int k = s.topo.EF_offset[e]; k < s.topo.EF_offset[e + 1]; ++k) {
          const int g = s.topo.EF_face[k];
          if (g != f) num += s.face_area[g] * r.rho[g], den += s.face_area[g];
        }
      }
      sm[f] = num / den;
    }
    r.rho.swap(sm);
  }
  r.timings.similarity_fit = ms_since(t);

  // Open mesh with the edit's boundary tangents (§5.7, §7.4): bind for this edit.
  std::optional<SpinTransform> local;
  SpinTransform* st = s.st ? &*s.st : nullptr;
  if (!st) {
    t = Clock::now();
    SpinTransformOptions so = s.spin_options();
    std::vector<int> verts;
    for (Eigen::Index i = 0; i < n; ++i)
      if (s.next[i] >= 0) verts.push_back(static_cast<int>(i));
    so.boundary.vertices.resize(static_cast<Eigen::Index>(verts.size()));
    so.boundary.targets.resize(static_cast<Eigen::Index>(verts.size()), 3);
    for (std::size_t k = 0; k < verts.size(); ++k) {
      const int i = verts[k];
      so.boundary.vertices[static_cast<Eigen::Index>(k)] = i;
      const Eigen::RowVector3d T = V_edit.row(s.next[i]) - V_edit.row(i);
      if (!(T.norm() > 0)) {
        std::ostringstream msg;
        msg << "conformal_snap: boundary edge (" << i << ", " << s.next[i] << ") has zero length in the edit";
        throw Error(msg.str());
      }
      so.boundary.targets.row(static_cast<Eigen::Index>(k)) = T;
    }
    local.emplace(s.rest, so);
    st = &*local;
    r.timings.bind = ms_since(t);
  }

  const SpinTransformResult sr = st->solve_similarity(r.rho);
  r.eigenvalue = sr.eigenvalue;
  r.iterations = sr.iterations;
  r.residual = sr.residual;
  r.timings.eigen = sr.timings.assembly + sr.timings.factor + sr.timings.eigen;

  t = Clock::now();
  // λ̂ = λ q, q = Σ M_i conj(λ_i) μ_i / Σ M_i |λ_i|² (least squares over the quaternion gauge).
  ga::Quat num(0.0, 0.0, 0.0, 0.0);
  double den = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const ga::Quat l = row_quat(sr.lambda, i);
    num += s.vertex_area[i] * (ga::conj(l) * row_quat(r.mu, i));
    den += s.vertex_area[i] * ga::norm2(l);
  }
  if (!(ga::norm2(num) > 0) || !(den > 0))
    throw numerical_error(
        "conformal_snap: the spin transformation's similarity field is orthogonal to the edit's");
  const ga::Quat q = num / den;
  r.lambda.resize(n, 4);
  for (Eigen::Index i = 0; i < n; ++i) r.lambda.row(i) = (row_quat(sr.lambda, i) * q).coeffs().transpose();
  // Fig. 21: interpolate between the edit's similarities (t = 0) and the conformal ones (t = 1).
  const double tt = s.opt.tradeoff;
  const Eigen::MatrixXd blend = tt == 1.0 ? r.lambda : ((1.0 - tt) * r.mu + tt * r.lambda).eval();
  Eigen::MatrixXd Vs = st->reconstruct(blend);
  switch (s.opt.alignment) {
    case SnapAlignment::Similarity:
      r.alignment = umeyama_fit(Vs, V_edit, true);
      break;
    case SnapAlignment::Translation:
      r.alignment.t = (V_edit.colwise().mean() - Vs.colwise().mean()).transpose();
      break;
    case SnapAlignment::None:
      break;
  }
  r.V = r.alignment.apply(Vs);
  if (!r.V.allFinite()) throw numerical_error("conformal_snap: the snapped positions are not finite");
  r.timings.poisson = ms_since(t);
  return r;
}

ConformalSnapResult conformal_snap(const Mesh& rest, const Eigen::MatrixXd& V_edit,
                                   const ConformalSnapOptions& options) {
  ConformalSnap cs(rest, options);
  return cs.snap(V_edit);
}

}  // namespace spinmotor
