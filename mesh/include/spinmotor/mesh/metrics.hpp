#pragma once
// Quality metrics of deformations and surfaces (docs/design.md: every deformer and spin routine is judged
// with these). One header per metric family:
//   metrics/quasi_conformal.hpp     per-face quasi-conformal error Q, area-weighted Q_mean, Q_max
//   metrics/area_distortion.hpp     log area ratio per face, global scale removed
//   metrics/edge_distortion.hpp     log length ratio per edge, global scale removed
//   metrics/distances.hpp           per-vertex distances, Umeyama similarity / rigid alignment
//   metrics/hausdorff.hpp           point-to-surface distances, one-sided and symmetric Hausdorff
//   metrics/willmore.hpp            Willmore energy ∫H² dA
//   metrics/deformation_metrics.hpp all of the above for one deformation: compute_metrics()
// The JSON form (metrics/json.hpp) is separate so that this umbrella does not pull in nlohmann-json.
#include "spinmotor/mesh/metrics/area_distortion.hpp"
#include "spinmotor/mesh/metrics/deformation_metrics.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/mesh/metrics/edge_distortion.hpp"
#include "spinmotor/mesh/metrics/hausdorff.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/mesh/metrics/willmore.hpp"
