#include "spinmotor/mesh/metrics/distances.hpp"

#include "metric_checks.hpp"
#include "spinmotor/ga/rotor_fit.hpp"

namespace spinmotor {

Similarity umeyama_fit(const Eigen::MatrixXd& src, const Eigen::MatrixXd& dst, bool with_scale) {
  detail::check_points(src, "umeyama_fit", "source");
  detail::check_points(dst, "umeyama_fit", "target");
  if (src.rows() != dst.rows())
    throw Error("umeyama_fit: " + std::to_string(src.rows()) + " source points but " +
                std::to_string(dst.rows()) + " target points");
  if (src.rows() == 0) throw Error("umeyama_fit: no points");
  const double n = static_cast<double>(src.rows());
  const Eigen::RowVector3d mu_s = src.colwise().mean(), mu_d = dst.colwise().mean();
  const Eigen::MatrixXd xs = src.rowwise() - mu_s, xd = dst.rowwise() - mu_d;
  const Eigen::Matrix3d cov = xd.transpose() * xs / n;  // Σ_xy, eq. (38)
  const double var_s = xs.squaredNorm() / n;            // σ²_x, eq. (36)
  // Eqs. (40), (43): R maximises tr(Rᵀ Σ_xy) = tr(R Σ_xyᵀ), a proper rotation (ga/rotor_fit.hpp), and
  // max tr(R Σ_xyᵀ) = tr(D S) of eq. (42).
  ga::RotationInfo info;
  Similarity T;
  T.R = ga::rotation_matrix(ga::best_rotation(cov.transpose(), ga::Rot(1.0, 0.0, 0.0, 0.0), &info));
  if (with_scale) {
    if (!(var_s > 0)) throw Error("umeyama_fit: the source points all coincide: the scale is undefined");
    T.scale = info.trace / var_s;  // eq. (42)
  }
  T.t = mu_d.transpose() - T.scale * T.R * mu_s.transpose();  // eq. (41)
  return T;
}

VertexDistances vertex_distances(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V_def,
                                 Alignment alignment) {
  detail::check_points(V_rest, "vertex_distances", "rest");
  detail::check_points(V_def, "vertex_distances", "deformed");
  if (V_rest.rows() != V_def.rows())
    throw Error("vertex_distances: rest has " + std::to_string(V_rest.rows()) + " vertices, deformed has " +
                std::to_string(V_def.rows()));
  if (V_rest.rows() == 0) throw Error("vertex_distances: no vertices");
  VertexDistances r;
  r.diagonal = (V_rest.colwise().maxCoeff() - V_rest.colwise().minCoeff()).norm();
  if (!(r.diagonal > 0)) throw Error("vertex_distances: the rest bounding box has zero diagonal");
  switch (alignment) {
    case Alignment::None:
      break;
    case Alignment::Translation:
      r.transform.t = (V_rest.colwise().mean() - V_def.colwise().mean()).transpose();
      break;
    case Alignment::Rigid:
      r.transform = umeyama_fit(V_def, V_rest, false);
      break;
    case Alignment::Similarity:
      r.transform = umeyama_fit(V_def, V_rest, true);
      break;
  }
  const Eigen::MatrixXd aligned = alignment == Alignment::None ? V_def : r.transform.apply(V_def);
  r.d = (aligned - V_rest).rowwise().norm();
  r.rms = std::sqrt(r.d.squaredNorm() / static_cast<double>(r.d.size())) / r.diagonal;
  r.max = r.d.maxCoeff() / r.diagonal;
  return r;
}

}  // namespace spinmotor
