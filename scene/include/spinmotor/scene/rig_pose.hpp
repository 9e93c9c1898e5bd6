#pragma once
// Posing and baking a glTF rig (mesh/gltf.hpp): the skin deformer with any blend (deform/rig_skin.hpp),
// optionally the pose-keeping cleanup of every frame (spin/pinned_cleanup.hpp with pins from the skin
// weights, deform/rig_pins.hpp), placed in mesh or scene space, and the baked glTF morph-target
// animation (write_gltf_morph_animation). One implementation for `spinmotor rig pose` and the Python
// module's Rig.poser / Rig.bake.
//
// Cleanup "pinned": bound once per RigPoser. The vertices of one joint (dominant weight ≥
// pin_threshold) farther than pin_margin from every blended vertex stay where the skin put them
// (pin_margin < 0: per bone, a quarter of the widest blend band of the joints it takes part in,
// default_pin_margins); the rest is held near the skinned pose by the weights' attraction and made as
// conformal as possible at the rest volume (closed surfaces) or area: RigCleanup (rig_cleanup.hpp), whose
// options and defaults RigPoseOptions::cleanup_options carries.
// Space: Mesh is the file's POSITION frame; Scene applies the mesh node's global matrix at the frame's
// time (for the Khronos samples: their Z-up root). A baked glTF stays in mesh space and carries the
// node's rest global matrix instead (Space::Scene), so that it sits in its scene as the source did.
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace spinmotor::scene {

/// Post-skinning cleanup of each frame (CLI `rig pose --cleanup`, Python `cleanup=`).
enum class RigCleanupMode { None, Pinned };
inline constexpr OptionNames<RigCleanupMode, 2> kRigCleanupModeNames{
    "cleanup", {{{RigCleanupMode::None, "none"}, {RigCleanupMode::Pinned, "pinned"}}}};
constexpr const auto& option_names(RigCleanupMode) { return kRigCleanupModeNames; }

/// Output coordinates (CLI `rig pose --space`, Python `space=`).
enum class RigSpace { Mesh, Scene };
inline constexpr OptionNames<RigSpace, 2> kRigSpaceNames{
    "space", {{{RigSpace::Mesh, "mesh"}, {RigSpace::Scene, "scene"}}}};
constexpr const auto& option_names(RigSpace) { return kRigSpaceNames; }

struct RigPoseOptions {
  int animation = 0;                 ///< index into rig.animations; −1: the rest pose
  SkinBlend blend = SkinBlend::LBS;  ///< skinning blend
  RigCleanupMode cleanup = RigCleanupMode::None;
  /// cleanup pinned: pins, pose attraction and the cleanup's own options (scene/rig_cleanup.hpp, whose
  /// defaults these are); pin_threshold must lie in [0.5, 1].
  RigCleanupOptions cleanup_options;
  RigSpace space = RigSpace::Mesh;
};

class RigPoser {
 public:
  /// Bind. Inputs: the rig (must outlive the poser), options. Binds the skin deformer and, with cleanup
  /// pinned, the cleanup (pins from the weights). Throws Error for an animation out of range, a
  /// threshold outside [0.5, 1], a non-finite margin, no pin found, a skeleton the skin deformer
  /// refuses, a rest mesh the cleanup refuses.
  explicit RigPoser(const GltfRig& rig, const RigPoseOptions& options = {});

  /// Positions (n×3) at time t (seconds, clamped to the animation's range): skinned, cleaned up as
  /// asked, in the options' space. Throws Error for a non-finite t or a non-rigid skinning transform.
  Eigen::MatrixXd pose(double t);
  /// Same in mesh space whatever options.space says (what a baked glTF stores).
  Eigen::MatrixXd pose_mesh_space(double t);

  const RigPoseOptions& options() const { return options_; }
  const GltfRig& rig() const { return rig_; }
  /// Pinned vertices (sorted; empty without cleanup) and the per-bone margins used.
  const Eigen::VectorXi& pins() const { return pins_; }
  const Eigen::VectorXd& pin_margins() const { return margins_; }

 private:
  const GltfRig& rig_;
  RigPoseOptions options_;
  SkinDeformer skin_;
  std::optional<RigCleanup> cleanup_;
  Eigen::VectorXi pins_;
  Eigen::VectorXd margins_;
  Eigen::MatrixXd scratch_;
};

/// Times of `frames` frames (≥ 1) spread evenly over animation `animation` (gltf_frame_time); Error for
/// an animation out of range (−1, the rest pose, gives zeros).
std::vector<double> rig_frame_times(const GltfRig& rig, int animation, int frames);

/// Poses `poser` at every time (mesh space) and writes the frames as a glTF morph-target animation
/// (.gltf or .glb, atomic; write_gltf_morph_animation) named `name`, the node matrix being the mesh
/// node's rest global matrix with RigSpace::Scene (identity with Mesh). Times strictly increasing.
/// Returns the frames written. Throws Error before writing anything on a bad time or frame.
std::vector<Eigen::MatrixXd> bake_rig_gltf(const std::filesystem::path& path, RigPoser& poser,
                                           const std::vector<double>& times,
                                           const std::string& name = "baked");

}  // namespace spinmotor::scene
