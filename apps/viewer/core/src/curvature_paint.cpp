#include "spinmotor/viewer/curvature_paint.hpp"

#include <chrono>
#include <cmath>
#include <memory>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/spin/boundary_prescription.hpp"
#include "spinmotor/spin/spin_transform.hpp"

namespace spinmotor::viewer {

int paint_rho(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& centre,
              double radius, double amount, Eigen::VectorXd& rho) {
  if (rho.size() != F.rows())
    throw Error("paint_rho: rho has " + std::to_string(rho.size()) + " values for " +
                std::to_string(F.rows()) + " faces");
  if (!(radius > 0) || !std::isfinite(radius)) throw Error("paint_rho: the brush radius must be positive");
  if (!std::isfinite(amount) || !centre.allFinite())
    throw Error("paint_rho: non-finite brush amount or centre");
  int touched = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d c = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3.0;
    const double s = (c - centre).squaredNorm() / (radius * radius);
    if (s >= 1) continue;
    rho[f] += amount * (1 - s) * (1 - s);
    ++touched;
  }
  return touched;
}

SpinPaintWorker::SpinPaintWorker(Mesh rest)
    : LatestJobWorker(
          [rest = std::make_shared<const Mesh>(std::move(rest)), spin = std::shared_ptr<SpinTransform>()](
              Eigen::VectorXd& rho, std::uint64_t generation) mutable {
            return outcome_of<PaintOutcome>(generation, [&](PaintOutcome& out) {
              auto t0 = std::chrono::steady_clock::now();
              if (!spin) {
                // On a surface with boundary the kernel of D is large (any conformal map of a disk is a spin
                // transformation with ρ = 0), so the smallest eigenvector of D − ρ is arbitrary: an open
                // 100k-vertex tube gave Q_mean 2.7 for any bump. The boundary keeps its rest tangent
                // directions (§5.7, as in the §7.4 boundary prescription with unchanged targets).
                SpinTransformOptions o;
                if (!boundary_loops(rest->F).empty()) o.boundary = boundary_tangents(rest->V, rest->F);
                spin = std::make_shared<SpinTransform>(*rest, o);
                out.bind_ms = spin->bind_ms();
                t0 = std::chrono::steady_clock::now();
              }
              out.V = spin->solve(rho).V;
              out.solve_ms =
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
              out.q_mean = quasi_conformal_summary(rest->V, rest->F, out.V).q_mean;
            });
          }) {}

}  // namespace spinmotor::viewer
