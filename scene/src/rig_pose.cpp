// Posing and baking a glTF rig: see rig_pose.hpp.
#include "spinmotor/scene/rig_pose.hpp"

#include <cmath>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/gltf_animation.hpp"

namespace spinmotor::scene {

namespace {

const RigPoseOptions& checked(const GltfRig& rig, const RigPoseOptions& o) {
  if (o.animation < -1 || o.animation >= static_cast<int>(rig.animations.size()))
    throw Error("rig: animation " + std::to_string(o.animation) + " out of range (the rig has " +
                std::to_string(rig.animations.size()) + "; -1 is the rest pose)");
  (void)option_name(o.blend);  // an enum value outside the table (cast from an integer) throws
  (void)option_name(o.cleanup);
  (void)option_name(o.space);
  return o;
}

}  // namespace

RigPoser::RigPoser(const GltfRig& rig, const RigPoseOptions& options)
    : rig_(rig), options_(checked(rig, options)), skinner_(rig, options.blend) {
  if (options_.cleanup == RigCleanupMode::None) return;
  const RigSkin& s = skinner_.skin();
  cleanup_.emplace(RigCleanup::bind(s.rest, s.rig.weights, s.rig.skeleton, options_.cleanup_options,
                                    [&rig](Eigen::Index v) { return rig.vertex_label(v); }));
}

void RigPoser::skin(double t, Eigen::MatrixXd& V_out) {
  if (!std::isfinite(t)) throw Error("rig: time " + std::to_string(t) + " is not finite");
  skinner_.pose(options_.animation, t, V_out);
}

Eigen::MatrixXd RigPoser::clean(const Eigen::MatrixXd& skinned) {
  if (!cleanup_) return skinned;
  Eigen::MatrixXd V;
  last_ = (*cleanup_)(skinned, V);
  return V;
}

Eigen::MatrixXd RigPoser::pose_scene(double t) {
  Eigen::MatrixXd V;
  skin(t, V);
  return clean(V);
}

void RigPoser::to_space(Eigen::MatrixXd& V) const {
  if (options_.space == RigSpace::Scene) return;
  const RigSkin& s = skinner_.skin();
  for (const GltfPiece& p : rig_.pieces) {
    const Eigen::Matrix4d& Bi = s.bind_inverse[p.skin];
    auto block = V.middleRows(p.first_vertex, p.vertices);
    block = ((block * Bi.topLeftCorner<3, 3>().transpose()).rowwise() + Bi.topRightCorner<3, 1>().transpose())
                .eval();
  }
}

Mesh RigPoser::rest() const {
  Mesh m = skinner_.skin().rest;
  if (options_.space == RigSpace::Scene) return m;
  m.V = rig_.mesh.V;
  for (const GltfPiece& p : rig_.pieces)
    for (Eigen::Index k = 0; k < p.num_targets(); ++k)
      if (p.default_weights[k] != 0)
        m.V.middleRows(p.first_vertex, p.vertices) += p.default_weights[k] * p.targets[k];
  return m;
}

Eigen::MatrixXd RigPoser::pose(double t) {
  Eigen::MatrixXd V = pose_scene(t);
  to_space(V);
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
  const GltfRig& rig = poser.rig();
  const RigSkin& skin = poser.rig_skin();
  Eigen::Matrix4d node = Eigen::Matrix4d::Identity();
  Mesh rest = skin.rest;
  if (poser.options().space == RigSpace::Mesh) {
    for (const GltfPiece& p : rig.pieces)
      if (!skin.bind[p.skin].isApprox(skin.bind[rig.pieces[0].skin], 1e-9))
        throw Error(path.string() + ": the pieces' skins have different bind matrices: bake in scene space");
    node = skin.bind[rig.pieces[0].skin];
    rest = poser.rest();
  }
  std::vector<Eigen::MatrixXd> frames(times.size());
  for (size_t f = 0; f < times.size(); ++f) frames[f] = poser.pose(times[f]);
  std::vector<GltfMorphPiece> pieces;
  for (const GltfPiece& p : rig.pieces)
    pieces.push_back({p.name, p.first_vertex, p.vertices, p.first_face, p.faces});
  write_gltf_morph_animation(path, rest, frames, times, name, node, pieces);
  return frames;
}

}  // namespace spinmotor::scene
