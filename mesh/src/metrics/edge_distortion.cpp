#include "spinmotor/mesh/metrics/edge_distortion.hpp"

#include "metric_checks.hpp"
#include "spinmotor/mesh/topology.hpp"

namespace spinmotor {
namespace {

struct Lengths {
  Eigen::VectorXd rest, def;
  double rest_total = 0, def_total = 0;
};

Lengths lengths(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F, const Eigen::MatrixXd& V_def,
                const char* who) {
  detail::check_pair(V_rest, F, V_def, who);
  const Eigen::MatrixXi E = edge_topology(F).E;
  Lengths l;
  l.rest.resize(E.rows());
  l.def.resize(E.rows());
#pragma omp parallel for schedule(static)
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    l.rest[e] = (V_rest.row(E(e, 0)) - V_rest.row(E(e, 1))).norm();
    l.def[e] = (V_def.row(E(e, 0)) - V_def.row(E(e, 1))).norm();
  }
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    if (!(l.rest[e] > 0))
      throw Error(std::string(who) + ": rest edge " + std::to_string(e) + " (vertices " +
                  std::to_string(E(e, 0)) + ", " + std::to_string(E(e, 1)) + ") has zero length");
    l.rest_total += l.rest[e];
    l.def_total += l.def[e];
  }
  if (!(l.def_total > 0)) throw Error(std::string(who) + ": every deformed edge has zero length");
  return l;
}

Eigen::VectorXd log_ratio(const Lengths& l) {
  const double global = std::log(l.def_total / l.rest_total);
  Eigen::VectorXd d(l.rest.size());
  for (Eigen::Index e = 0; e < d.size(); ++e)
    d[e] = l.def[e] > 0 ? std::log(l.def[e] / l.rest[e]) - global : -std::numeric_limits<double>::infinity();
  return d;
}

}  // namespace

Eigen::VectorXd log_edge_distortion(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                    const Eigen::MatrixXd& V_def) {
  return log_ratio(lengths(V_rest, F, V_def, "log_edge_distortion"));
}

EdgeDistortionSummary edge_distortion_summary(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                              const Eigen::MatrixXd& V_def) {
  const Lengths l = lengths(V_rest, F, V_def, "edge_distortion_summary");
  const Eigen::VectorXd d = log_ratio(l);
  EdgeDistortionSummary s;
  s.global_scale = l.def_total / l.rest_total;
  double num = 0, den = 0;
  for (Eigen::Index e = 0; e < d.size(); ++e) {
    if (std::isinf(d[e])) {
      ++s.collapsed_edges;
      s.max_abs = std::numeric_limits<double>::infinity();
      continue;
    }
    num += l.rest[e] * std::abs(d[e]);
    den += l.rest[e];
    s.max_abs = std::max(s.max_abs, std::abs(d[e]));
  }
  s.mean_abs = den > 0 ? num / den : std::numeric_limits<double>::infinity();
  return s;
}

}  // namespace spinmotor
