#include "spinmotor/deform/spline_ik.hpp"

#include <chrono>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/stopwatch.hpp"

namespace spinmotor {

SplineIkDeformer SplineIkDeformer::bind(const Mesh& rest, const Rig& rig, const Options& options) {
  if (rig.handles.size() != 2)
    throw Error("SplineIkDeformer: needs exactly two handles {from, to}, got " +
                std::to_string(rig.handles.size()));
  if (!rig.ik) throw Error("SplineIkDeformer: the rig has no ik chain");
  if (rig.ik->chain.rows() < 2 || rig.ik->chain.cols() != 3 || !rig.ik->chain.allFinite())
    throw Error("SplineIkDeformer: the ik chain must be k×3 finite joint positions with k ≥ 2");
  if (!rig.ik->target.allFinite()) throw Error("SplineIkDeformer: the ik target is not finite");
  if (options.controls < options.degree + 1)
    throw Error("SplineIkDeformer: degree " + std::to_string(options.degree) + " needs at least " +
                std::to_string(options.degree + 1) + " controls, got " + std::to_string(options.controls));
  SplineIkDeformer d;
  d.options_ = options;
  d.ik_ = *rig.ik;
  SplineDeformer::Options so;
  so.basis = SplineBasis::BSpline;
  so.degree = options.degree;
  so.keys = options.controls;
  so.weights = options.weights;
  d.spline_ = SplineDeformer::bind(rest, rig.handles, so);
  d.V_rest_ = rest.V;
  d.controls_ = {{kTarget, d.ik_.target}};
  d.solve(d.ik_.target);
  return d;
}

void SplineIkDeformer::solve(const Eigen::Vector3d& target) {
  // Into locals first: a failed solve (a degenerate solved chain) leaves the last good one in place.
  const auto t0 = std::chrono::steady_clock::now();
  FabrikResult ik =
      fabrik(options_.warm_start && start_.size() ? start_ : ik_.chain, target,
             {.tolerance = ik_.tolerance, .max_iterations = ik_.iterations, .end_rotation = ik_.orientation});
  const double fabrik_ms = ms_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  ChainFit fit = fit_chain(V_rest_, spline_.parameter(), ik_.chain, ik.joints,
                           {.controls = options_.controls, .degree = options_.degree}, ik_.orientation);
  fit_ms_ = ms_since(t1);
  fabrik_ms_ = fabrik_ms;
  fabrik_ = std::move(ik);
  if (options_.warm_start) start_ = fabrik_.joints;
  fit_ = std::move(fit);
  target_ = target;
}

void SplineIkDeformer::pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out) {
  check_motors(motors, controls_, "SplineIkDeformer");
  const Eigen::Vector3d target = ga::to_isometry(motors[0]) * ik_.target;
  if (target != target_) solve(target);
  spline_.pose_generators(fit_.fit.generators, V_out);
}

}  // namespace spinmotor
