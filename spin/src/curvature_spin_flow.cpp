#include "spinmotor/spin/curvature_spin_flow.hpp"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "spinmotor/error.hpp"
#include "spinmotor/mesh/cholesky_solver.hpp"
#include "spinmotor/mesh/face_geometry.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/spin/edge_constraint_net.hpp"
#include "spinmotor/spin/face_dirac_operator.hpp"
#include "spinmotor/spin/quaternion_matrix.hpp"

namespace spinmotor {

namespace {

void check_options(const CurvatureSpinOptions& o, const char* who) {
  std::ostringstream s;
  if (!(o.alpha > 0) || !std::isfinite(o.alpha)) s << who << ": alpha must be > 0, got " << o.alpha;
  else if (!(o.beta >= 0) || !std::isfinite(o.beta)) s << who << ": beta must be >= 0, got " << o.beta;
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

}  // namespace

CurvatureSpinStep curvature_spin_step(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                      const Eigen::VectorXd& h_target, const Eigen::VectorXd& target_area,
                                      const CurvatureSpinOptions& options) {
  static constexpr const char* who = "curvature_spin_step";
  require(Mesh{V, F, {}, {}},
          {.manifold = true, .oriented = true, .no_degenerate = true, .closed = true, .single_component = true,
           .no_unreferenced = true},
          who);
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
    for (Eigen::Index f = 0; f < m; ++f) s[f] = std::log(A[f] / target_area[f]) - std::log(total / target_total);
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
  Eigen::VectorXd x = solver.solve(b);
  if (area) {  // Sherman–Morrison for S − c u uᵀ (Appendix D: the dense term never formed)
    const Eigen::VectorXd Su = solver.solve(u);
    const double denom = 1.0 - c * u.dot(Su);
    if (!(std::abs(denom) > 1e-14)) throw numerical_error(std::string(who) + ": area-constrained system is singular");
    x += Su * (c * u.dot(x) / denom);
  }
  CurvatureSpinStep out;
  out.phi = unflatten_quaternions(one + x);
  if (!out.phi.allFinite()) throw numerical_error(std::string(who) + ": the spin transformation is not finite");
  out.V = face_spin_transform(V, F, out.phi, FaceDiracKind::Extrinsic, &out.closure);  // eq. 4, then eq. 9 (LS)
  return out;
}

namespace {

Eigen::MatrixXd rescale(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F, double area, const Eigen::RowVector3d& c) {
  const double a = face_areas(X, F).sum();
  if (!(a > 0) || !std::isfinite(a)) throw numerical_error("curvature flow: the surface collapsed");
  return ((X.rowwise() - X.colwise().mean()) * std::sqrt(area / a)).rowwise() + c;
}

}  // namespace

CurvatureFlow curvature_fairing(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int steps, double tau,
                                const CurvatureSpinOptions& options) {
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
  }
  out.willmore.push_back(face_willmore_energy(out.V, F));
  return out;
}

CurvatureFlow curvature_extrusion(const Eigen::MatrixXd& V_sphere, const Eigen::MatrixXi& F,
                                  const Eigen::MatrixXd& V_target, int steps, const CurvatureSpinOptions& options) {
  if (V_target.rows() != V_sphere.rows()) {
    std::ostringstream s;
    s << "curvature_extrusion: the target has " << V_target.rows() << " vertices, the sphere " << V_sphere.rows()
      << " (same connectivity required)";
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
  }
  out.willmore.push_back(face_willmore_energy(out.V, F));
  return out;
}

}  // namespace spinmotor
