// Posing and baking a glTF rig: see rig_pose.hpp.
#include "spinmotor/scene/rig_pose.hpp"

#include <cmath>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/rig_skin.hpp"

namespace spinmotor::scene {

namespace {

const RigPoseOptions& checked(const GltfRig& rig, const RigPoseOptions& o) {
  if (o.animation < -1 || o.animation >= static_cast<int>(rig.animations.size()))
    throw Error("rig: animation " + std::to_string(o.animation) + " out of range (the rig has " +
                std::to_string(rig.animations.size()) + "; -1 is the rest pose)");
  (void)option_name(o.blend);  // an enum value outside the table (cast from an integer) throws
  (void)option_name(o.cleanup);
  (void)option_name(o.space);
  if (o.cleanup == RigCleanupMode::Pinned) {
    const RigCleanupOptions& c = o.cleanup_options;
    if (!(c.pin_threshold >= 0.5 && c.pin_threshold <= 1.0))
      throw Error("rig: pin threshold " + std::to_string(c.pin_threshold) + " outside [0.5, 1]");
    if (!std::isfinite(c.pin_margin)) throw Error("rig: pin margin is not finite");
  }
  return o;
}

}  // namespace

RigPoser::RigPoser(const GltfRig& rig, const RigPoseOptions& options)
    : rig_(rig), options_(checked(rig, options)), skin_(bind_rig(rig, options.blend)) {
  if (options_.cleanup == RigCleanupMode::None) return;
  const RigSkin skin = rig_skin(rig);
  cleanup_.emplace(RigCleanup::bind(rig.mesh, skin.weights, skin.bones, options_.cleanup_options));
  pins_ = cleanup_->pins;
  margins_ = cleanup_->margins;
}

Eigen::MatrixXd RigPoser::pose_mesh_space(double t) {
  if (!std::isfinite(t)) throw Error("rig: time " + std::to_string(t) + " is not finite");
  Eigen::MatrixXd V;
  skin_.pose(rig_pose_motors(rig_, options_.animation, t), V);
  if (cleanup_) {
    (void)(*cleanup_)(V, scratch_);
    V.swap(scratch_);
  }
  return V;
}

Eigen::MatrixXd RigPoser::pose(double t) {
  Eigen::MatrixXd V = pose_mesh_space(t);
  if (options_.space == RigSpace::Scene) {
    const Eigen::Matrix4d w = node_world_matrices(rig_, options_.animation, t)[rig_.mesh_node];
    V = ((V * w.topLeftCorner<3, 3>().transpose()).rowwise() + w.topRightCorner<3, 1>().transpose()).eval();
  }
  return V;
}

std::vector<double> rig_frame_times(const GltfRig& rig, int animation, int frames) {
  if (frames < 1) throw Error("rig: " + std::to_string(frames) + " frames (at least 1)");
  if (animation < -1 || animation >= static_cast<int>(rig.animations.size()))
    throw Error("rig: animation " + std::to_string(animation) + " out of range (the rig has " +
                std::to_string(rig.animations.size()) + "; -1 is the rest pose)");
  std::vector<double> times(static_cast<size_t>(frames), 0.0);
  if (animation >= 0)
    for (int f = 0; f < frames; ++f) times[f] = gltf_frame_time(rig.animations[animation], f, frames);
  return times;
}

std::vector<Eigen::MatrixXd> bake_rig_gltf(const std::filesystem::path& path, RigPoser& poser,
                                           const std::vector<double>& times, const std::string& name) {
  if (times.empty()) throw Error(path.string() + ": no frame time to bake");
  for (size_t f = 0; f < times.size(); ++f)
    if (!std::isfinite(times[f]) || (f > 0 && !(times[f] > times[f - 1])))
      throw Error(path.string() + ": time of frame " + std::to_string(f) +
                  " is not finite or not after the previous one");
  std::vector<Eigen::MatrixXd> frames(times.size());
  for (size_t f = 0; f < times.size(); ++f) frames[f] = poser.pose_mesh_space(times[f]);
  const GltfRig& rig = poser.rig();
  const Eigen::Matrix4d node = poser.options().space == RigSpace::Scene
                                   ? node_world_matrices(rig, -1, 0.0)[rig.mesh_node]
                                   : Eigen::Matrix4d::Identity();
  write_gltf_morph_animation(path, rig.mesh, frames, times, name, node);
  return frames;
}

}  // namespace spinmotor::scene
