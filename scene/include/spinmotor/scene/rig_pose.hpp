#pragma once
// Posing and baking a glTF rig (mesh/gltf.hpp): every piece skinned as the glTF specification defines it
// with any blend (deform/gltf_skin.hpp), optionally the pose-keeping cleanup of every frame
// (rig_cleanup.hpp), in scene or bind coordinates, and the baked glTF morph-target animation
// (write_gltf_morph_animation). One implementation for `spinmotor rig pose` and the Python module's
// Rig.poser / Rig.bake.
//
// Space: Scene is the file's scene (glTF's world, as viewers and Blender show it; the default); Mesh is
// each piece's POSITION frame (its skin's bind space: B_s⁻¹ applied, deform/gltf_skin.hpp). The cleanup
// runs in scene coordinates, on the rest surface of RigSkin.
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/gltf_skin.hpp"
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
  /// cleanup pinned: pins, pose attraction and the cleanup's own options (rig_cleanup.hpp, whose
  /// defaults these are).
  RigCleanupOptions cleanup_options{};
  RigSpace space = RigSpace::Scene;
};

class RigPoser {
 public:
  /// Bind. Inputs: the rig (must outlive the poser), options. Binds the skin and, with cleanup pinned,
  /// the rig cleanup. Throws Error for an animation out of range, bad cleanup options, a skeleton the
  /// skin deformer refuses, a rest surface the cleanup refuses.
  explicit RigPoser(const GltfRig& rig, const RigPoseOptions& options = {});

  /// Positions (n×3) at time t (seconds, clamped to the animation's range): skinned, cleaned up as
  /// asked, in the options' space. Throws Error for a non-finite t or a mirroring joint transform.
  Eigen::MatrixXd pose(double t);
  /// Same in scene coordinates whatever options.space says.
  Eigen::MatrixXd pose_scene(double t);
  /// The skinned pose alone (no cleanup), scene coordinates.
  void skin(double t, Eigen::MatrixXd& V_out);
  /// The cleanup of a skinned pose (scene coordinates; a copy without cleanup). pose_scene(t) is
  /// clean(skin(t)).
  Eigen::MatrixXd clean(const Eigen::MatrixXd& skinned);
  /// Scene coordinates to the options' space, in place (identity for Scene).
  void to_space(Eigen::MatrixXd& V) const;
  /// The rest surface in the options' space: RigSkin::rest, or for Mesh the POSITION data as stored
  /// (with the default morph weights), not mapped there and back.
  Mesh rest() const;

  const RigPoseOptions& options() const { return options_; }
  const GltfRig& rig() const { return rig_; }
  const RigSkin& rig_skin() const { return skinner_.skin(); }
  /// The bound cleanup (null without cleanup) and the last frame's figures.
  const RigCleanup* cleanup() const { return cleanup_ ? &*cleanup_ : nullptr; }
  RigCleanup* cleanup() { return cleanup_ ? &*cleanup_ : nullptr; }
  const RigCleanupResult& last_cleanup() const { return last_; }

 private:
  const GltfRig& rig_;
  RigPoseOptions options_;
  RigSkinner skinner_;
  std::optional<RigCleanup> cleanup_;
  RigCleanupResult last_;
};

/// Times of `frames` frames (≥ 1) spread evenly over animation `animation` (gltf_frame_time); Error for
/// an animation out of range (−1, the rest pose, gives zeros).
std::vector<double> rig_frame_times(const GltfRig& rig, int animation, int frames);

/// Poses `poser` at every time and writes the frames as a glTF morph-target animation (.gltf or .glb,
/// atomic; write_gltf_morph_animation), one node per piece, named `name`: in scene coordinates (node
/// matrices identity), or with RigSpace::Mesh in the bind space with the bind matrix as the root node's
/// matrix (Error when the pieces' skins have different bind matrices). Times strictly increasing. Returns
/// the frames written (the options' space). Throws Error before writing anything on a bad time or frame.
std::vector<Eigen::MatrixXd> bake_rig_gltf(const std::filesystem::path& path, RigPoser& poser,
                                           const std::vector<double>& times,
                                           const std::string& name = "baked");

}  // namespace spinmotor::scene
