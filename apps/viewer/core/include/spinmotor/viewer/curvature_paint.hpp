#pragma once
// Curvature painting (Crane, Pinkall & Schröder 2011, §5): a brush paints a change ρ of mean-curvature
// half-density on faces, and the spin transformation with that ρ is computed off the UI thread. The
// result is conformal by construction (Q ≈ 1), whatever is painted.
//
//   Eigen::VectorXd rho = Eigen::VectorXd::Zero(F.rows());
//   paint_rho(V, F, hit.point, radius, +2.0, rho);   // one dab per mouse move while the button is down
//   worker.request(rho);                              // when the stroke ends
//   if (auto r = worker.take()) show(r->V);
#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/viewer/latest_job_worker.hpp"

namespace spinmotor::viewer {

/// One brush dab: every face whose centroid (in V) lies within `radius` of `centre` gets
/// ρ_f += amount · (1 − (d/radius)²)², a bump that falls to zero with zero slope at the rim.
/// `amount` has units 1/length (ρ is a curvature). Returns the number of faces touched.
/// Error for a wrong ρ size or a radius that is not positive and finite.
int paint_rho(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& centre,
              double radius, double amount, Eigen::VectorXd& rho);

struct PaintOutcome {
  std::uint64_t generation = 0;
  Eigen::MatrixXd V;   ///< positions of the spin transformation (empty on error)
  double q_mean = 0;   ///< rest-area weighted quasi-conformal error against the rest mesh
  double bind_ms = 0;  ///< SpinTransform bind (first request only, else 0)
  double solve_ms = 0;
  std::string error;  ///< what went wrong (spinmotor::Error message), else empty
};

/// Applies painted ρ (one value per face of `rest`) as a spin transformation of `rest`; the
/// SpinTransform is bound once, on the first request, in the worker thread. A mesh with boundary
/// keeps its boundary tangent directions (§5.7): without a boundary condition the problem has no
/// unique answer there.
class SpinPaintWorker : public LatestJobWorker<Eigen::VectorXd, PaintOutcome> {
 public:
  explicit SpinPaintWorker(Mesh rest);
};

}  // namespace spinmotor::viewer
