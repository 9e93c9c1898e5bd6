#include "spinmotor/mesh/metrics/deformation_metrics.hpp"

#include "spinmotor/mesh/metrics/area_distortion.hpp"
#include "spinmotor/mesh/metrics/edge_distortion.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/mesh/metrics/willmore.hpp"

namespace spinmotor {

DeformationMetrics compute_metrics(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                   const Eigen::MatrixXd& V_def, const MetricsOptions& options) {
  DeformationMetrics r;
  r.vertices = V_rest.rows();
  r.faces = F.rows();
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
