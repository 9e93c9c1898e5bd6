#pragma once
// FABRIK inverse kinematics for one chain (Aristidou & Lasenby 2011, "FABRIK: a fast, iterative
// solver for the inverse kinematics problem", Algorithm 1), as used by the CGA paper §III.C.
//
// The chain is k ≥ 2 joints p_0..p_{k−1} (bones p_i p_{i+1} of lengths d_i > 0); the root p_0 stays
// put. Reachable target (|t − p_0| ≤ Σ d_i): alternate a forward pass (p_{k−1} = t, then each joint
// moved onto the line to its successor at distance d_i) and a backward pass (p_0 back to the root,
// then outwards) until |p_{k−1} − t| ≤ tolerance or max_iterations passes. Unreachable target: the
// chain is stretched straight towards the target. A straight chain aimed along its own line stalls (no
// bending plane): its middle joint is then nudged off the line by 1% of a bone. Every pass restores
// each bone length exactly (to rounding), so bone lengths are kept to ~1e-15 relative.
//
// end_rotation (optional): the orientation of the end bone relative to the rest pose, a unit rotor R:
// the last bone must point along R d̂_rest. The sub-chain p_0..p_{k−2} is then solved for the target
// t − d_{k−2} R d̂_rest and the last joint placed along the prescribed direction.
#include <Eigen/Core>
#include <optional>

#include "spinmotor/ga.hpp"

namespace spinmotor {

struct FabrikOptions {
  double tolerance = 1e-4;  ///< distance of the end joint to the target (units of the chain)
  int max_iterations = 50;  ///< forward + backward passes
  std::optional<ga::Rot> end_rotation{};
};

struct FabrikResult {
  Eigen::MatrixXd joints;  ///< k×3 solved joint positions
  int iterations = 0;      ///< passes done
  double error = 0;        ///< |p_{k−1} − target|
  bool reachable = true;   ///< |t − p_0| ≤ total length (of the free sub-chain with end_rotation)
  bool converged = false;  ///< error ≤ tolerance
};

/// Inputs: chain (k×3 rest joint positions, k ≥ 2), target, options. Output: the solved chain.
/// Throws Error for k < 2, a non-finite joint or target, a bone of zero length (naming it), a
/// tolerance ≤ 0, max_iterations < 1 or a non-unit end rotation.
FabrikResult fabrik(const Eigen::MatrixXd& chain, const Eigen::Vector3d& target,
                    const FabrikOptions& options);

}  // namespace spinmotor
