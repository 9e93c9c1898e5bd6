#include "spinmotor/mesh/metrics/area_distortion.hpp"

#include <vector>

#include "metric_checks.hpp"

namespace spinmotor {
namespace {

struct Areas {
  Eigen::VectorXd rest, def;
  std::vector<char> collapsed;
  double rest_total = 0, def_total = 0;
};

Areas areas(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F, const Eigen::MatrixXd& V_def,
            const char* who) {
  detail::check_pair(V_rest, F, V_def, who);
  const Eigen::Index m = F.rows();
  Areas a;
  a.rest.resize(m);
  a.def.resize(m);
  a.collapsed.assign(static_cast<size_t>(m), 0);
  std::vector<char> rest_bad(static_cast<size_t>(m), 0);
#pragma omp parallel for schedule(static)
  for (Eigen::Index f = 0; f < m; ++f) {
    bool dr, dd;
    a.rest[f] = 0.5 * detail::double_area(V_rest, F, f, &dr);
    a.def[f] = 0.5 * detail::double_area(V_def, F, f, &dd);
    rest_bad[f] = dr;
    a.collapsed[f] = dd;
  }
  for (Eigen::Index f = 0; f < m; ++f) {
    if (rest_bad[f])
      throw Error(std::string(who) + ": rest face " + std::to_string(f) +
                  " is degenerate: its area ratio is undefined");
    a.rest_total += a.rest[f];
    a.def_total += a.def[f];
  }
  if (!(a.def_total > 0)) throw Error(std::string(who) + ": the deformed mesh has zero area");
  return a;
}

Eigen::VectorXd log_ratio(const Areas& a) {
  const double global = std::log(a.def_total / a.rest_total);
  Eigen::VectorXd d(a.rest.size());
  for (Eigen::Index f = 0; f < d.size(); ++f)
    d[f] =
        a.collapsed[f] ? -std::numeric_limits<double>::infinity() : std::log(a.def[f] / a.rest[f]) - global;
  return d;
}

}  // namespace

Eigen::VectorXd log_area_distortion(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                    const Eigen::MatrixXd& V_def) {
  return log_ratio(areas(V_rest, F, V_def, "log_area_distortion"));
}

AreaDistortionSummary area_distortion_summary(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                              const Eigen::MatrixXd& V_def) {
  const Areas a = areas(V_rest, F, V_def, "area_distortion_summary");
  const Eigen::VectorXd d = log_ratio(a);
  AreaDistortionSummary s;
  s.global_scale = a.def_total / a.rest_total;
  double num = 0, den = 0;
  for (Eigen::Index f = 0; f < d.size(); ++f) {
    if (a.collapsed[f]) {
      ++s.collapsed_faces;
      s.max_abs = std::numeric_limits<double>::infinity();
      continue;
    }
    num += a.rest[f] * std::abs(d[f]);
    den += a.rest[f];
    s.max_abs = std::max(s.max_abs, std::abs(d[f]));
  }
  s.mean_abs = den > 0 ? num / den : std::numeric_limits<double>::infinity();
  return s;
}

}  // namespace spinmotor
