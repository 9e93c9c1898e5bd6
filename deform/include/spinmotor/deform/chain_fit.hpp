#pragma once
// From a posed joint chain to the key motors of a spline deformer (CGA paper §III.C, Fig. 5: the
// joints of a FABRIK chain are the key motors Q_i, fitted by a cubic B-spline that drives the
// spline-aligned deformation).
//
// chain_motors: one motor per joint, relative to the rest pose, Q_i = T(p'_i) R_i T(−p_i) (rotate
//   about the rest joint p_i, then carry it to the posed joint p'_i), so Q_i p_i ~Q_i = p'_i.
//   Bone frames are rotation-minimising (parallel transport along the chain): F_0 is the minimal
//   rotation taking the rest direction of bone 0 onto its posed direction, and F_b the minimal
//   rotation taking F_{b−1}(rest direction of bone b) onto its posed direction, composed with F_{b−1}
//   (no twist is introduced). Joint rotations: R_0 = F_0, R_i = the half-way rotor between F_{i−1}
//   and F_i at an interior joint (the joint bisects its two bones), R_{k−1} = F_{k−2} at the tip, or
//   the prescribed end rotation when one is given.
// chain_parameters: the spline parameter λ_i of each joint. The mesh's harmonic parameter λ (0 on the
//   `from` handle, 1 on the `to` handle) is not the arc length along the chain (it bends near caps and
//   handles of finite size), so the joints are matched to the field rather than to their chord length:
//   every vertex is projected onto the rest chain (closest point on the polyline, normalized arc
//   length s_v), and λ_i is the hat-weighted mean of λ over the vertices whose s_v lies within half the
//   distance to the neighbouring joints (weights 1 − |s_v − s_i|/h). The end joints get 0 and 1 (the
//   chain is assumed to run from the `from` handle to the `to` handle); a joint that no vertex
//   projects near falls back to its chord-length parameter s_i; the result is made non-decreasing.
// fit_chain: both, then fit_bspline_motors with the ends pinned (the deformed `from` and `to` handles
//   then follow the root and tip joint motors exactly, so the tip lands on the IK target).
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "spinmotor/deform/bspline_fit.hpp"
#include "spinmotor/ga.hpp"

namespace spinmotor {

/// Inputs: rest and posed chains (k×3 each, k ≥ 2, bones of equal lengths not required but > 0),
/// optional end rotation (unit rotor). Output: k joint motors. Throws Error on size mismatch, a
/// zero-length bone, non-finite input.
std::vector<ga::Mot> chain_motors(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& posed,
                                  const std::optional<ga::Rot>& end_rotation = std::nullopt);

/// Inputs: V (n×3 rest vertices), lambda (n, the harmonic parameter), chain (k×3 rest joints).
/// Output: k non-decreasing parameters in [0, 1], first 0 and last 1. Parallel over vertices.
Eigen::VectorXd chain_parameters(const Eigen::MatrixXd& V, const Eigen::VectorXd& lambda,
                                 const Eigen::MatrixXd& chain);

struct ChainFit {
  std::vector<ga::Mot> joint_motors;  ///< Q_i (chain_motors)
  Eigen::VectorXd joint_parameters;   ///< λ_i (chain_parameters)
  BSplineFit fit;                     ///< control generators for SplineDeformer::pose_generators
};

/// chain_motors + chain_parameters + fit_bspline_motors (options.interpolate_ends is forced on).
ChainFit fit_chain(const Eigen::MatrixXd& V, const Eigen::VectorXd& lambda, const Eigen::MatrixXd& rest_chain,
                   const Eigen::MatrixXd& posed_chain, const BSplineFitOptions& options,
                   const std::optional<ga::Rot>& end_rotation = std::nullopt);

}  // namespace spinmotor
