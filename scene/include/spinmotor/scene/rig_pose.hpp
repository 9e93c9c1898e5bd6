#pragma once
// Posing and baking a glTF rig (mesh/gltf.hpp): the skin deformer with any blend (deform/rig_skin.hpp),
// optionally the pose-keeping cleanup of every frame (spin/pinned_cleanup.hpp with pins from the skin
// weights, deform/rig_pins.hpp), placed in mesh or scene space, and the baked glTF morph-target
// animation (write_gltf_morph_animation). One implementation for `spinmotor rig pose` and the Python
// module's Rig.poser / Rig.bake.
//
// Cleanup "pinned": the rig cleanup (scene/rig_cleanup.hpp: pins and pose attraction from the skin
// weights, the pose-keeping cleanup), bound once per RigPoser with its options and defaults.
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
  RigCleanupOptions cleanup_options;  ///< cleanup pinned: pins, pose attraction, the cleanup's options
  RigSpace space = RigSpace::Mesh;
};

class RigPoser {
 public:
  /// Bind. Inputs: the rig (must outlive the poser), options. Binds the skin deformer and, with cleanup
  /// pinned, the rig cleanup (RigCleanup::bind). Throws Error for an animation out of range, a pin
  /// threshold outside [0.5, 1], a non-finite margin or a negative pose weight, no pin found, a skeleton
  /// the skin deformer refuses, a rest mesh the cleanup refuses.
  explicit RigPoser(const GltfRig& rig, const RigPoseOptions& options = {});

  /// Positions (n×3) at time t (seconds, clamped to the animation's range): skinned, cleaned up as
  /// asked, in the options' space. Throws Error for a non-finite t or a non-rigid skinning transform.
  Eigen::MatrixXd pose(double t);
  /// Same in mesh space whatever options.space says (what a baked glTF stores).
  Eigen::MatrixXd pose_mesh_space(double t);

  const RigPoseOptions& options() const { return options_; }
  const GltfRig& rig() const { return rig_; }
  /// Pinned vertices (sorted; empty without cleanup) and the per-bone margins used.
  const Eigen::VectorXi& pins() const { return cleanup_ ? cleanup_->pins : no_pins_; }
  const Eigen::VectorXd& pin_margins() const { return cleanup_ ? cleanup_->margins : no_margins_; }

 private:
  const GltfRig& rig_;
  RigPoseOptions options_;
  SkinDeformer skin_;
  std::optional<RigCleanup> cleanup_;
  Eigen::VectorXi no_pins_;
  Eigen::VectorXd no_margins_;
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
