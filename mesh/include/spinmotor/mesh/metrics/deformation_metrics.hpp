#pragma once
// All the quality metrics of one deformation (same connectivity) gathered in one struct: what the
// CLI's `spinmotor metrics`, the tests and the benchmarks report for every deformer and spin routine.
#include <optional>

#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"

namespace spinmotor {

struct MetricsOptions {
  Alignment alignment = Alignment::None;  ///< factored out before the vertex distances only
  bool willmore = true;                   ///< also compute the Willmore energies (one Laplacian each)
  /// Leave degenerate rest faces (zero area, where Q and the area ratio are undefined) out of every
  /// measure and count them, instead of the error (production meshes carry a few).
  bool skip_degenerate_rest = false;
};

struct DeformationMetrics {
  Eigen::Index vertices = 0, faces = 0;
  double q_mean = 1.0;                    ///< rest-area-weighted mean quasi-conformal error
  double q_max = 1.0;                     ///< max Q (+inf if a deformed face collapsed)
  Eigen::Index collapsed_faces = 0;       ///< deformed faces of zero area (excluded from the means)
  double area_distortion = 0.0;           ///< rest-area-weighted mean |log area ratio|, global scale removed
  double area_distortion_max = 0.0;       ///< max |log area ratio|
  double area_scale = 1.0;                ///< total deformed area / total rest area
  double edge_distortion = 0.0;           ///< rest-length-weighted mean |log length ratio|, scale removed
  double edge_distortion_max = 0.0;       ///< max |log length ratio|
  double rms = 0.0;                       ///< RMS vertex distance / rest bounding-box diagonal
  double max = 0.0;                       ///< max vertex distance / rest bounding-box diagonal
  double diagonal = 0.0;                  ///< rest bounding-box diagonal
  Alignment alignment = Alignment::None;  ///< what was factored out before rms / max
  Similarity transform;                   ///< the alignment applied to the deformed positions
  std::optional<double> willmore_rest;    ///< ∫H² dA of the rest mesh (if asked)
  std::optional<double> willmore_deformed;  ///< of the deformed mesh (if asked and no face collapsed)
  /// Enclosed volume of the deformed mesh / of the rest mesh (signed, Σ_f v0·(v1×v2)/6), when the rest
  /// mesh is closed (no boundary edge) with a non-zero volume.
  std::optional<double> volume_ratio;
  Eigen::Index degenerate_rest_faces = 0;  ///< left out (skip_degenerate_rest)
};

/// Inputs: V_rest (n×3), F (m×3), V_def (n×3), options. Output: every metric above (see
/// quasi_conformal.hpp, area_distortion.hpp, edge_distortion.hpp, distances.hpp, willmore.hpp).
/// Throws Error on mismatched sizes, bad indices, non-finite coordinates or degenerate rest faces.
DeformationMetrics compute_metrics(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                   const Eigen::MatrixXd& V_def, const MetricsOptions& options = {});

/// Same, with the rest mesh's V and F.
inline DeformationMetrics compute_metrics(const Mesh& rest, const Eigen::MatrixXd& V_def,
                                          const MetricsOptions& options = {}) {
  return compute_metrics(rest.V, rest.F, V_def, options);
}

}  // namespace spinmotor
