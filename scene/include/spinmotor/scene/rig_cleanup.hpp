#pragma once
// The pose-keeping cleanup of a skinned rig, bound once: pins and pose attraction from the skin weights
// (deform/rig_pins.hpp) and the cleanup itself (spin/pinned_cleanup.hpp). One place for the rig
// defaults, shared by `spinmotor rig pose --cleanup pinned`, scene files, the viewer, Python and the
// Blender add-on.
//
//   pins        the vertices one bone moves rigidly (dominant weight ≥ pin_threshold) that lie farther
//               than the margin from every blended vertex (pin_margin, or per bone a quarter of its
//               widest joint band: default_pin_margins);
//   attraction  a_i = smoothstep of the dominant weight between attraction_low and pin_threshold
//               (pin_attraction_from_weights), with strength pose_weight (γ, PinnedCleanupOptions):
//               1 on the rigid parts, 0 in the middle of each joint, so the joints are free to become
//               conformal while the soft parts of the body stay near the skinned pose.
//
// Why γ = 10 by default: on CesiumMan (2,338 welded vertices, 62 pins at 0.999) the cleanup without
// attraction is conformal (Q_mean 1.010) but drifts 3.9% of the diagonal from the pose — a stride that
// closes — because soft weights leave most of the body unpinned; γ = 10 keeps it within 0.6% at Q_mean
// 1.022, Q_max 1.20 (LBS 1.197 / 10.8, Delta Mush 1.144 / 30, DDM 1.125 / 29) and the rest volume
// (examples/cleanup_study --rigs DIR --pose-weight 10; docs/performance.md).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <span>

#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace spinmotor::scene {

struct RigCleanupOptions {
  double pin_threshold = 0.999;  ///< pins: dominant weight ≥ this (rig_pins.hpp)
  double pin_margin = -1;        ///< pins: distance to the blended vertices; < 0: default_pin_margins
  double pose_weight = 10;       ///< γ of the pose attraction (0: the pins only)
  double attraction_low = 0.5;   ///< dominant weight at and below which a vertex is not attracted
  /// The cleanup's own options (keep, iterations, tolerance, …); its pose_weight is replaced by the
  /// one above.
  PinnedCleanupOptions cleanup;
};

/// A bound rig cleanup: pins, attraction weights and the factorised cleanup.
struct RigCleanup {
  Eigen::VectorXi pins;        ///< increasing vertex indices
  Eigen::VectorXd attraction;  ///< a_i ∈ [0, 1] per vertex
  Eigen::VectorXd margins;     ///< per bone, as used for the pins
  PinnedCleanup cleanup;

  /// Inputs: rest (n vertices), W (n×B skin weights, rows need not sum to 1), bones (B, for the
  /// default margins), options. Throws Error naming the problem (bad weights, a bone count that does
  /// not match W, no pin at the threshold and margin, and every bind error of PinnedCleanup).
  [[nodiscard]] static RigCleanup bind(const Mesh& rest, const Eigen::MatrixXd& W,
                                       std::span<const Bone> bones, const RigCleanupOptions& options = {});
  [[nodiscard]] static RigCleanup bind(const Mesh& rest, const Eigen::SparseMatrix<double>& W,
                                       std::span<const Bone> bones, const RigCleanupOptions& options = {});

  /// One frame: V_edit (n×3, the skinned pose) → V_out (n×3). See PinnedCleanup::cleanup.
  PinnedCleanupResult operator()(const Eigen::MatrixXd& V_edit, Eigen::MatrixXd& V_out) {
    return cleanup.cleanup(V_edit, V_out);
  }
};

}  // namespace spinmotor::scene
