#pragma once
// SplineIkDeformer: a spline-aligned deformation driven by inverse kinematics (CGA paper §III.C,
// Fig. 5) — the one place where FABRIK, the joint-chain fit and the spline deformer meet.
//
// Bind (rig.handles = {from, to}, rig.ik = the rest joint chain and its target): the harmonic
//   parameter λ from `from` (0) to `to` (1) and the cubic B-spline spline deformer (SplineDeformer,
//   options.spline with basis BSpline and keys = options.controls), then a first solve toward the rest
//   target. One control, "ik.target", anchored at the rest target.
// Pose (one motor: it carries the rest target to this frame's target): when the target moved, FABRIK
//   (fabrik.hpp) from the rest chain to it, the joint motors of the solved chain and their B-spline fit
//   with the ends pinned (chain_fit.hpp); then the spline pose with the fitted generators. No harmonic
//   field is recomputed: the per-frame work is the IK solve (k joints), the fit (a small least-squares
//   problem) and the motor blend over the vertices. The `to` handle then lands on the target as far
//   as FABRIK reached it.
// Errors: bind throws Error for a rig without two handles or an ik chain, a chain of fewer than two
//   joints, controls < degree + 1, and as SplineDeformer::bind; pose throws as check_motors and as the
//   fit (a degenerate solved chain).
#include <Eigen/Core>
#include <span>
#include <vector>

#include "spinmotor/deform/chain_fit.hpp"
#include "spinmotor/deform/deformer.hpp"
#include "spinmotor/deform/fabrik.hpp"
#include "spinmotor/deform/spline_deformer.hpp"

namespace spinmotor {

class SplineIkDeformer {
 public:
  struct Options {
    int controls = 5;  ///< B-spline controls of the fit (≥ degree + 1)
    int degree = 3;    ///< B-spline degree
    HarmonicWeights weights = HarmonicWeights::MeanValue;
    /// Start FABRIK from the last solved chain instead of the rest chain: a redundant chain then
    /// moves continuously through an animation (the solution depends on the start).
    bool warm_start = false;
  };

  /// The name of the one control.
  static constexpr const char* kTarget = "ik.target";

  static SplineIkDeformer bind(const Mesh& rest, const Rig& rig, const Options& options);

  /// One motor: the motion of the IK target (identity: the rest target).
  void pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out);

  const std::vector<Control>& controls() const { return controls_; }
  Eigen::Index vertices() const { return spline_.vertices(); }
  const Options& options() const { return options_; }
  const IkChain& ik() const { return ik_; }
  const SplineDeformer& spline() const { return spline_; }

  /// The target of the last solve, its FABRIK result and chain fit, and their times (ms).
  const Eigen::Vector3d& target() const { return target_; }
  const FabrikResult& fabrik_result() const { return fabrik_; }
  const ChainFit& chain_fit() const { return fit_; }
  double fabrik_ms() const { return fabrik_ms_; }
  double fit_ms() const { return fit_ms_; }

 private:
  void solve(const Eigen::Vector3d& target);

  Options options_;
  IkChain ik_;
  Eigen::MatrixXd start_;  // where FABRIK starts: the rest chain, or the last solve (warm_start)
  SplineDeformer spline_;
  std::vector<Control> controls_;
  Eigen::MatrixXd V_rest_;
  Eigen::Vector3d target_;
  FabrikResult fabrik_;
  ChainFit fit_;
  double fabrik_ms_ = 0, fit_ms_ = 0;
};

}  // namespace spinmotor
