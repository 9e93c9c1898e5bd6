#pragma once
// JSON form of DeformationMetrics (nlohmann-json), header-only so that the mesh library itself does
// not depend on nlohmann: include this header where JSON is written (CLI, benchmarks, tools).
//
// Keys: vertices, faces, q_mean, q_max, collapsed_faces, area_distortion, area_distortion_max,
// area_scale, edge_distortion, edge_distortion_max, rms, max, diagonal, alignment
// ("none" | "translation" | "rigid" | "similarity"), alignment_scale, and, present only when computed:
// volume_ratio (closed rest meshes), degenerate_rest_faces (when some were skipped), willmore_rest and
// willmore_deformed. JSON has no infinity: a non-finite value (q_max
// with a collapsed face) is written as null, and collapsed_faces says why.
#include <cmath>
#include <nlohmann/json.hpp>

#include "spinmotor/mesh/metrics/deformation_metrics.hpp"

namespace spinmotor {

namespace detail {
inline nlohmann::json finite_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
}
}  // namespace detail

/// nlohmann's ADL hook: `nlohmann::json j = metrics;`.
inline void to_json(nlohmann::json& j, const DeformationMetrics& m) {
  using detail::finite_or_null;
  j = nlohmann::json{{"vertices", m.vertices},
                     {"faces", m.faces},
                     {"q_mean", finite_or_null(m.q_mean)},
                     {"q_max", finite_or_null(m.q_max)},
                     {"collapsed_faces", m.collapsed_faces},
                     {"area_distortion", finite_or_null(m.area_distortion)},
                     {"area_distortion_max", finite_or_null(m.area_distortion_max)},
                     {"area_scale", finite_or_null(m.area_scale)},
                     {"edge_distortion", finite_or_null(m.edge_distortion)},
                     {"edge_distortion_max", finite_or_null(m.edge_distortion_max)},
                     {"rms", finite_or_null(m.rms)},
                     {"max", finite_or_null(m.max)},
                     {"diagonal", finite_or_null(m.diagonal)},
                     {"alignment", std::string(option_name(m.alignment))},
                     {"alignment_scale", finite_or_null(m.transform.scale)}};
  if (m.volume_ratio) j["volume_ratio"] = finite_or_null(*m.volume_ratio);
  if (m.degenerate_rest_faces > 0) j["degenerate_rest_faces"] = m.degenerate_rest_faces;
  if (m.willmore_rest) j["willmore_rest"] = finite_or_null(*m.willmore_rest);
  if (m.willmore_deformed) j["willmore_deformed"] = finite_or_null(*m.willmore_deformed);
}

/// The JSON object of the metrics (same as the ADL hook).
inline nlohmann::json to_json(const DeformationMetrics& m) {
  nlohmann::json j;
  to_json(j, m);
  return j;
}

}  // namespace spinmotor
