#include "spinmotor/spin/curvature_spin_flow.hpp"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/ga/quaternion.hpp"
#include "spinmotor/linalg/cholesky_solver.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/spin/edge_constraint_net.hpp"
#include "spinmotor/spin/face_dirac_operator.hpp"
#include "spinmotor/spin/quaternion_matrix.hpp"

namespace spinmotor {

namespace {

void check_options(const CurvatureSpinOptions& o, const char* who) {
  std::ostringstream s;
  if (!(o.alpha > 0) || !std::isfinite(o.alpha))
    s << who << ": alpha must be > 0, got " << o.alpha;
  else if (!(o.beta >= 0) || !std::isfinite(o.beta))
    s << who << ": beta must be >= 0, got " << o.beta;
  else if (!(o.area_epsilon >= 0) || !std::isfinite(o.area_epsilon))
    s << who << ": area epsilon must be >= 0, got " << o.area_epsilon;
  if (!s.str().empty()) throw Error(s.str());
}

void check_field(const Eigen::VectorXd& x, Eigen::Index m, const char* who, const char* what, bool positive) {
  if (x.size() != m) {
    std::ostringstream s;
    s << who << ": " << what << " has " << x.size() << " values for " << m << " faces";
    throw Error(s.str());
  }
  for (Eigen::Index f = 0; f < m; ++f)
    if (!std::isfinite(x[f]) || (positive && !(x[f] > 0))) {
      std::ostringstream s;
      s << who << ": " << what << " of face " << f << " is " << x[f];
      throw Error(s.str());
    }
}

// Integrated face Laplacian (dual graph): (L_f φ)_i = Σ_j w_ij (φ_i − φ_j), w_ij = |e_ij| / |c_i − c_j|.
Eigen::SparseMatrix<double> face_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                           const EdgeConstraintNet& net) {
  const Eigen::Index m = F.rows();
  Eigen::MatrixXd C(m, 3);
  for (Eigen::Index f = 0; f < m; ++f) C.row(f) = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))) / 3.0;
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(m) * 16);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) {
      const int g = net.adjacent(f, c);
      if (g < 0) continue;
      const double w = net.edge_length(f, c) / (C.row(f) - C.row(g)).norm();
      for (int a = 0; a < 4; ++a) {
        t.emplace_back(4 * f + a, 4 * f + a, w);
        t.emplace_back(4 * f + a, 4 * g + a, -w);
      }
    }
  Eigen::SparseMatrix<double> L(4 * m, 4 * m);
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

// Harmonic 1-forms (Le Folgoc Appendix B/C): an orthonormal basis (columns, k edges) of the kernel of
// the graph Helmholtzian d₀d₀ᵀ + d₁ᵀd₁, with E(e,0) → E(e,1) the edge orientation. Random edge values
// minus their exact (d₀ f) and co-exact (d₁ᵀ ψ) parts, b₁ = 2 − χ of them.
Eigen::MatrixXd harmonic_one_forms(const Eigen::MatrixXi& F, Eigen::Index n, const EdgeTopology& topo) {
  const Eigen::Index m = F.rows(), k = topo.num_edges();
  const Eigen::Index b1 = 2 - (n - k + m);
  if (b1 <= 0) return Eigen::MatrixXd(k, 0);
  std::vector<Eigen::Triplet<double>> t0, t1;
  for (Eigen::Index e = 0; e < k; ++e) {
    t0.emplace_back(e, topo.E(e, 0), -1.0);
    t0.emplace_back(e, topo.E(e, 1), 1.0);
  }
  for (Eigen::Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c)
      t1.emplace_back(f, topo.FE(f, c), F(f, (c + 1) % 3) == topo.E(topo.FE(f, c), 0) ? 1.0 : -1.0);
  Eigen::SparseMatrix<double> d0(k, n), d1(m, k);
  d0.setFromTriplets(t0.begin(), t0.end());
  d1.setFromTriplets(t1.begin(), t1.end());
  // Pin one vertex / one face (the constants span the kernels of the two graph Laplacians).
  const Eigen::SparseMatrix<double> L0 =
      Eigen::SparseMatrix<double>(d0.transpose() * d0).bottomRightCorner(n - 1, n - 1);
  const Eigen::SparseMatrix<double> L2 =
      Eigen::SparseMatrix<double>(d1 * d1.transpose()).bottomRightCorner(m - 1, m - 1);
  CholeskySolver s0, s2;
  s0.analyze(L0);
  s0.factorize(L0);
  s2.analyze(L2);
  s2.factorize(L2);
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(k, b1);
  unsigned state = 12345u;  // deterministic pseudo-random edge values
  for (Eigen::Index e = 0; e < k; ++e)
    for (Eigen::Index j = 0; j < b1; ++j) {
      state = state * 1664525u + 1013904223u;
      G(e, j) = static_cast<double>(state >> 8) / static_cast<double>(1u << 24) - 0.5;
    }
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(n, b1), psi = Eigen::MatrixXd::Zero(m, b1);
  f.bottomRows(n - 1) = s0.solve(Eigen::MatrixXd((d0.transpose() * G).bottomRows(n - 1)));
  G -= d0 * f;
  psi.bottomRows(m - 1) = s2.solve(Eigen::MatrixXd((d1 * G).bottomRows(m - 1)));
  G -= d1.transpose() * psi;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(G);
  return qr.householderQ() * Eigen::MatrixXd::Identity(k, b1);
}

}  // namespace

CurvatureSpinStep curvature_spin_step(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                      const Eigen::VectorXd& h_target, const Eigen::VectorXd& target_area,
                                      const CurvatureSpinOptions& options) {
  static constexpr const char* who = "curvature_spin_step";
  require(Mesh{V, F, {}, {}}, kClosedSurface, who);
  check_options(options, who);
  const Eigen::Index m = F.rows();
  check_field(h_target, m, who, "target half-density", false);
  const bool area = options.area_epsilon > 0;
  if (area) check_field(target_area, m, who, "target area", true);

  const EdgeConstraintNet net = edge_constraint_net(V, F);
  const Eigen::VectorXd& A = net.area;
  const double total = A.sum(), mean = total / static_cast<double>(m);
  // D_X = D_f + H (Le Folgoc eq. 5: D_X 1 = H), D_ρ = D_X − ρA with ρ = h̄ / sqrt(A).
  const Eigen::VectorXd rhoA = h_target.cwiseProduct(A.cwiseSqrt());
  const Eigen::SparseMatrix<double> Drho =
      face_dirac_operator(V, F, net, FaceDiracKind::Extrinsic) + quaternion_diagonal(net.H - rhoA);
  const Eigen::SparseMatrix<double> Q =
      Eigen::SparseMatrix<double>(Drho * quaternion_diagonal(A.cwiseInverse()) * Drho);
  // R = (A + β Ā L_f) / ΣA (eq. 8).
  const Eigen::SparseMatrix<double> R =
      (quaternion_diagonal(A) + (options.beta * mean) * face_laplacian(V, F, net)) / total;
  Eigen::SparseMatrix<double> S = Q + options.alpha * R;
  const Eigen::VectorXd one = flatten_quaternions(
      (Eigen::MatrixXd(m, 4) << Eigen::VectorXd::Ones(m), Eigen::MatrixXd::Zero(m, 3)).finished());
  // Unknown x = φ − 1: (Q + αR + CᵀΛC) x = −Q·1 − CᵀΛs (eq. 8 with the Appendix D penalty).
  Eigen::VectorXd b = -(Q * one);
  Eigen::VectorXd u;  // rank-one part of CᵀΛC = c (diag(P a) − u uᵀ), c = 16/ε²
  double c = 0.0;
  if (area) {
    const Eigen::VectorXd a = A / total;
    const double target_total = target_area.sum();
    Eigen::VectorXd s(m);  // Appendix D eq. 15: log area distortion with the global scale factored out
    for (Eigen::Index f = 0; f < m; ++f)
      s[f] = std::log(A[f] / target_area[f]) - std::log(total / target_total);
    c = 16.0 / (options.area_epsilon * options.area_epsilon);
    u = Eigen::VectorXd::Zero(4 * m);
    for (Eigen::Index f = 0; f < m; ++f) u[4 * f] = a[f];
    Eigen::VectorXd da = Eigen::VectorXd::Zero(4 * m);
    for (Eigen::Index f = 0; f < m; ++f) da[4 * f] = c * a[f];
    S += Eigen::SparseMatrix<double>(Eigen::VectorXd(da).asDiagonal());
    // CᵀΛs = (4/ε²) (P(a∘s) − u (aᵀs)).
    const double as = a.dot(s);
    for (Eigen::Index f = 0; f < m; ++f) b[4 * f] -= (c / 4.0) * (a[f] * s[f] - a[f] * as);
  }
  CholeskySolver solver;
  solver.analyze(S);
  solver.factorize(S);
  // Solves with the full matrix S − c u uᵀ: Sherman–Morrison (Appendix D: the dense term never formed).
  Eigen::VectorXd Su;
  if (area) {
    Su = solver.solve(u);
    if (!(std::abs(1.0 - c * u.dot(Su)) > 1e-14))
      throw numerical_error(std::string(who) + ": area-constrained system is singular");
  }
  const auto solve_full = [&](const Eigen::MatrixXd& B) {
    Eigen::MatrixXd X = solver.solve(B);
    if (area) X += Su * ((c / (1.0 - c * u.dot(Su))) * (u.transpose() * X));
    return X;
  };
  Eigen::VectorXd x = solve_full(b);
  CurvatureSpinStep out;
  const EdgeTopology topo = edge_topology(F);
  const Eigen::MatrixXd W = harmonic_one_forms(F, V.rows(), topo);
  // ω^k along the traversal of face f, slot c.
  const auto omega = [&](Eigen::Index f, int cc, Eigen::Index k) {
    const int e = topo.FE(f, cc);
    return (F(f, (cc + 1) % 3) == topo.E(e, 0) ? 1.0 : -1.0) * W(e, k);
  };
  {
    if (options.exactness && W.cols() > 0) {  // Appendix C, eq. 12 linearised at φ = 1: Cᵀx = 0, C = [V^k ν]
      Eigen::MatrixXd C = Eigen::MatrixXd::Zero(4 * m, 3 * W.cols());
      for (Eigen::Index k = 0; k < W.cols(); ++k)
        for (Eigen::Index f = 0; f < m; ++f) {
          Eigen::Vector4d Vk = Eigen::Vector4d::Zero();
          for (int cc = 0; cc < 3; ++cc) Vk += omega(f, cc, k) * net.hyperedge(V, F, f, cc);
          const double a = Vk[0], bq = Vk[1], cq = Vk[2], d = Vk[3];
          C.block<4, 1>(4 * f, 3 * k) << -bq, a, d, -cq;      // V i
          C.block<4, 1>(4 * f, 3 * k + 1) << -cq, -d, a, bq;  // V j
          C.block<4, 1>(4 * f, 3 * k + 2) << -d, cq, -bq, a;  // V k
        }
      const Eigen::MatrixXd SC = solve_full(C);
      x -= SC * (C.transpose() * SC).ldlt().solve(C.transpose() * x);
      out.exactness_constraints = static_cast<int>(C.cols());
    }
  }
  out.phi = unflatten_quaternions(one + x);
  if (!out.phi.allFinite())
    throw numerical_error(std::string(who) + ": the spin transformation is not finite");
  // Periods (eq. 12, not linearised): |Im Σ_i φ̄_i Σ_j E_ij ω^k_ij φ_j| / Σ |Ẽ_ij ω^k_ij|.
  for (Eigen::Index k = 0; k < W.cols(); ++k) {
    Eigen::Vector3d P = Eigen::Vector3d::Zero();
    double norm = 0.0;
    for (Eigen::Index f = 0; f < m; ++f)
      for (int cc = 0; cc < 3; ++cc) {
        const int g = net.adjacent(f, cc);
        const Eigen::Vector4d E = net.hyperedge(V, F, f, cc), pf = out.phi.row(f).transpose();
        const Eigen::Vector4d Et =
            quaternion_block(ga::Quat(pf[0], -pf[1], -pf[2], -pf[3])) *
            (quaternion_block(ga::Quat(E[0], E[1], E[2], E[3])) * out.phi.row(g).transpose());
        P += omega(f, cc, k) * Et.tail<3>();
        norm += std::abs(omega(f, cc, k)) * Et.tail<3>().norm();
      }
    out.period = std::max(out.period, P.norm() / norm);
  }
  out.V =
      face_spin_transform(V, F, out.phi, FaceDiracKind::Extrinsic, &out.closure);  // eq. 4, then eq. 9 (LS)
  return out;
}

namespace {

Eigen::MatrixXd rescale(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F, double area,
                        const Eigen::RowVector3d& c) {
  const double a = face_areas(X, F).sum();
  if (!(a > 0) || !std::isfinite(a)) throw numerical_error("curvature flow: the surface collapsed");
  return ((X.rowwise() - X.colwise().mean()) * std::sqrt(area / a)).rowwise() + c;
}

}  // namespace

CurvatureFlow curvature_fairing(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int steps, double tau,
                                const CurvatureSpinOptions& options, const CurvatureProgress& progress) {
  if (steps < 0) throw Error("curvature_fairing: steps must be >= 0, got " + std::to_string(steps));
  if (!(tau > 0 && tau <= 1)) {
    std::ostringstream s;
    s << "curvature_fairing: tau must be in (0, 1], got " << tau;
    throw Error(s.str());
  }
  CurvatureFlow out;
  out.V = V;
  const Eigen::VectorXd A0 = face_areas(V, F);
  const double total0 = A0.sum();
  const Eigen::RowVector3d c0 = V.colwise().mean();
  for (int k = 0; k < steps; ++k) {
    const EdgeConstraintNet net = edge_constraint_net(out.V, F);
    out.willmore.push_back(net.willmore);
    // Le Folgoc §6: δh = −τh; area targets A⁰ scaled to the current total (only ratios matter).
    const CurvatureSpinStep st = curvature_spin_step(out.V, F, (1.0 - tau) * net.h, A0, options);
    out.V = rescale(st.V, F, total0, c0);
    out.closure.push_back(st.closure);
    if (progress) progress(k + 1, steps);
  }
  out.willmore.push_back(face_willmore_energy(out.V, F));
  return out;
}

CurvatureFlow curvature_extrusion(const Eigen::MatrixXd& V_sphere, const Eigen::MatrixXi& F,
                                  const Eigen::MatrixXd& V_target, int steps,
                                  const CurvatureSpinOptions& options, const CurvatureProgress& progress) {
  if (V_target.rows() != V_sphere.rows()) {
    std::ostringstream s;
    s << "curvature_extrusion: the target has " << V_target.rows() << " vertices, the sphere "
      << V_sphere.rows() << " (same connectivity required)";
    throw Error(s.str());
  }
  if (steps < 1) throw Error("curvature_extrusion: steps must be >= 1, got " + std::to_string(steps));
  const EdgeConstraintNet target = edge_constraint_net(V_target, F);
  const double total = target.area.sum();
  const Eigen::RowVector3d c0 = V_target.colwise().mean();
  CurvatureFlow out;
  out.V = rescale(V_sphere, F, total, c0);
  for (int k = 0; k < steps; ++k) {
    const EdgeConstraintNet net = edge_constraint_net(out.V, F);
    out.willmore.push_back(net.willmore);
    const Eigen::VectorXd h = net.h + (target.h - net.h) / static_cast<double>(steps - k);
    const CurvatureSpinStep st = curvature_spin_step(out.V, F, h, target.area, options);
    out.V = rescale(st.V, F, total, c0);
    out.closure.push_back(st.closure);
    if (progress) progress(k + 1, steps);
  }
  out.willmore.push_back(face_willmore_energy(out.V, F));
  return out;
}

}  // namespace spinmotor
