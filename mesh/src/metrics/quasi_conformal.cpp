#include "spinmotor/mesh/metrics/quasi_conformal.hpp"

#include <algorithm>

#include "metric_checks.hpp"

namespace spinmotor {
namespace {

// A triangle in an orthonormal frame of its own plane: x0 at the origin, x1 = (l1, 0), x2 = (p, h).
struct PlanarTriangle {
  double l1, p, h;
  bool degenerate;
};

PlanarTriangle planar(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::Index f) {
  const Eigen::Vector3d x0 = V.row(F(f, 0)), x1 = V.row(F(f, 1)), x2 = V.row(F(f, 2));
  const Eigen::Vector3d e1 = x1 - x0, e2 = x2 - x0;
  const double a2 = e1.cross(e2).norm();
  const double l2max = std::max({e1.squaredNorm(), e2.squaredNorm(), (x2 - x1).squaredNorm()});
  const double l1 = e1.norm();
  if (!(a2 > kDegenerateFace * l2max)) return {l1, 0.0, 0.0, true};
  return {l1, e1.dot(e2) / l1, a2 / l1, false};
}

constexpr double kRestDegenerate = -1.0;  // marker, reported after the parallel loop

}  // namespace

Eigen::VectorXd quasi_conformal_error(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                      const Eigen::MatrixXd& V_def) {
  detail::check_pair(V_rest, F, V_def, "quasi_conformal_error");
  const Eigen::Index m = F.rows();
  Eigen::VectorXd Q(m);
#pragma omp parallel for schedule(static)
  for (Eigen::Index f = 0; f < m; ++f) {
    const PlanarTriangle r = planar(V_rest, F, f), s = planar(V_def, F, f);
    if (r.degenerate) {
      Q[f] = kRestDegenerate;
      continue;
    }
    if (s.degenerate) {
      Q[f] = std::numeric_limits<double>::infinity();
      continue;
    }
    // A maps (l1, 0) ↦ (l1', 0) and (p, h) ↦ (p', h'): A = [a b; 0 d] (Crane et al. 2011, §6.1).
    const double a = s.l1 / r.l1, d = s.h / r.h, b = (s.p - a * r.p) / r.h;
    const double E = 0.5 * std::hypot(a + d, b), G = 0.5 * std::hypot(a - d, b);
    // σ1/σ2 = (E + G)² / (σ1 σ2) with σ1 σ2 = det A = a d: no cancellation when G ≈ E (strong
    // anisotropy), but for a similarity (G ≈ 0) a d and E² round differently, so the quotient can land
    // one ulp below 1 (seen under -O1 -fsanitize, other FMA contractions); Q ≥ 1 by definition.
    Q[f] = std::max(1.0, (E + G) * (E + G) / (a * d));
  }
  for (Eigen::Index f = 0; f < m; ++f)
    if (Q[f] == kRestDegenerate)
      throw Error("quasi_conformal_error: rest face " + std::to_string(f) + " (vertices " +
                  std::to_string(F(f, 0)) + ", " + std::to_string(F(f, 1)) + ", " + std::to_string(F(f, 2)) +
                  ") is degenerate: Q is undefined");
  return Q;
}

QuasiConformalSummary summarize_quasi_conformal(const Eigen::VectorXd& Q, const Eigen::VectorXd& rest_areas) {
  if (Q.size() != rest_areas.size())
    throw Error("summarize_quasi_conformal: " + std::to_string(Q.size()) + " values but " +
                std::to_string(rest_areas.size()) + " areas");
  QuasiConformalSummary s;
  double num = 0, den = 0;
  for (Eigen::Index f = 0; f < Q.size(); ++f) {
    if (std::isinf(Q[f])) {
      if (s.collapsed_faces++ == 0) {
        s.q_max = Q[f];
        s.worst_face = f;
      }
      continue;
    }
    num += rest_areas[f] * Q[f];
    den += rest_areas[f];
    if (s.collapsed_faces == 0 && (s.worst_face < 0 || Q[f] > s.q_max)) {
      s.q_max = Q[f];
      s.worst_face = f;
    }
  }
  s.q_mean = den > 0 ? num / den : std::numeric_limits<double>::infinity();
  return s;
}

QuasiConformalSummary quasi_conformal_summary(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                              const Eigen::MatrixXd& V_def) {
  const Eigen::VectorXd Q = quasi_conformal_error(V_rest, F, V_def);
  Eigen::VectorXd A(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    bool degenerate;
    A[f] = 0.5 * detail::double_area(V_rest, F, f, &degenerate);
  }
  return summarize_quasi_conformal(Q, A);
}

}  // namespace spinmotor
