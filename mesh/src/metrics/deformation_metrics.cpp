#include "spinmotor/mesh/metrics/deformation_metrics.hpp"

#include "metric_checks.hpp"
#include "spinmotor/mesh/metrics/area_distortion.hpp"
#include "spinmotor/mesh/metrics/edge_distortion.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/mesh/metrics/willmore.hpp"
#include "spinmotor/mesh/topology.hpp"

namespace spinmotor {

namespace {

double signed_volume(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  double s = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    s += Eigen::Vector3d(V.row(F(f, 0)))
             .dot(Eigen::Vector3d(V.row(F(f, 1))).cross(Eigen::Vector3d(V.row(F(f, 2)))));
  return s / 6.0;
}

/// The faces of F that are not degenerate in V (detail::double_area's test).
Eigen::MatrixXi non_degenerate(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXi out(F.rows(), 3);
  Eigen::Index m = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    bool degenerate = false;
    detail::double_area(V, F, f, &degenerate);
    if (!degenerate) out.row(m++) = F.row(f);
  }
  out.conservativeResize(m, 3);
  return out;
}

}  // namespace

DeformationMetrics compute_metrics(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F_all,
                                   const Eigen::MatrixXd& V_def, const MetricsOptions& options) {
  DeformationMetrics r;
  detail::check_pair(V_rest, F_all, V_def, "compute_metrics");
  const Eigen::MatrixXi F = options.skip_degenerate_rest ? non_degenerate(V_rest, F_all) : F_all;
  r.degenerate_rest_faces = F_all.rows() - F.rows();
  if (F.rows() == 0) throw Error("compute_metrics: every rest face is degenerate");
  r.vertices = V_rest.rows();
  r.faces = F_all.rows();
  if (boundary_vertices(F_all, V_rest.rows()).size() == 0)
    if (const double v0 = signed_volume(V_rest, F_all); v0 != 0)
      r.volume_ratio = signed_volume(V_def, F_all) / v0;
  const QuasiConformalSummary q = quasi_conformal_summary(V_rest, F, V_def);  // validates the input
  r.q_mean = q.q_mean;
  r.q_max = q.q_max;
  r.collapsed_faces = q.collapsed_faces;
  const AreaDistortionSummary a = area_distortion_summary(V_rest, F, V_def);
  r.area_distortion = a.mean_abs;
  r.area_distortion_max = a.max_abs;
  r.area_scale = a.global_scale;
  const EdgeDistortionSummary e = edge_distortion_summary(V_rest, F, V_def);
  r.edge_distortion = e.mean_abs;
  r.edge_distortion_max = e.max_abs;
  const VertexDistances d = vertex_distances(V_rest, V_def, options.alignment);
  r.rms = d.rms;
  r.max = d.max;
  r.diagonal = d.diagonal;
  r.alignment = options.alignment;
  r.transform = d.transform;
  if (options.willmore) {
    r.willmore_rest = willmore_energy(V_rest, F);
    if (r.collapsed_faces == 0) r.willmore_deformed = willmore_energy(V_def, F);
  }
  return r;
}

}  // namespace spinmotor
