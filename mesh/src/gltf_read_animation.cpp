// Reading a glTF 2.0 file's animations (gltf.hpp): each channel's sampler (key times, values,
// interpolation) for node transforms and morph weights; channels that target nothing the rig reads are
// counted, not kept.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "gltf_model.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor::detail {

namespace {

std::string in_quotes(const std::string& s) { return "'" + s + "'"; }

GltfInterpolation interpolation_of(const GltfAccessors& acc, const std::string& s, const std::string& label) {
  if (s == "LINEAR" || s.empty()) return GltfInterpolation::Linear;
  if (s == "STEP") return GltfInterpolation::Step;
  if (s == "CUBICSPLINE") return GltfInterpolation::CubicSpline;
  acc.fail(label + ": interpolation '" + s + "' is not supported");
}

/// One sampler's key times and values into c (c.path set; `targets`: the node's morph target count).
void read_sampler(const GltfAccessors& acc, const tinygltf::AnimationSampler& s, const std::string& slabel,
                  Eigen::Index targets, GltfChannel& c) {
  c.interpolation = interpolation_of(acc, s.interpolation, slabel);
  const GltfRows in = acc.read(s.input, TINYGLTF_TYPE_SCALAR, GltfKind::Float, "input of " + slabel);
  const std::string in_label = "accessor " + std::to_string(s.input) + " (input of " + slabel + ")";
  if (in.rows() < 1) acc.fail(in_label + ": no key times");
  for (Eigen::Index k = 1; k < in.rows(); ++k)
    if (!(in(k, 0) > in(k - 1, 0)))
      acc.fail(in_label + ": key time " + std::to_string(k) + " is not after key time " +
               std::to_string(k - 1));
  c.times = in.col(0);
  const Eigen::Index per = c.interpolation == GltfInterpolation::CubicSpline ? 3 : 1, keys = in.rows();
  const std::string out_label = "accessor " + std::to_string(s.output) + " (output of " + slabel + ")";
  if (c.path == GltfPath::Weights) {
    const GltfRows w = acc.read(s.output, TINYGLTF_TYPE_SCALAR, GltfKind::Rotation, "output of " + slabel);
    if (w.rows() != keys * per * targets)
      acc.fail(out_label + ": " + std::to_string(w.rows()) + " weights for " + std::to_string(keys) +
               " key times and " + std::to_string(targets) + " morph targets");
    c.values = Eigen::Map<const GltfRows>(w.data(), keys * per, targets);
    return;
  }
  const bool rot = c.path == GltfPath::Rotation;
  c.values = acc.read(s.output, rot ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3,
                      rot ? GltfKind::Rotation : GltfKind::Float, "output of " + slabel);
  if (c.values.rows() != keys * per)
    acc.fail(out_label + ": " + std::to_string(c.values.rows()) + " values for " + std::to_string(keys) +
             " key times (expected " + std::to_string(keys * per) + ")");
  if (!rot) return;
  for (Eigen::Index k = 0; k < c.values.rows(); ++k)
    if ((per == 1 || k % 3 == 1) && c.values.row(k).norm() < 1e-6)
      acc.fail(out_label + ": key " + std::to_string(k) + " is the zero quaternion");
  // LINEAR and STEP rotation keys are unit quaternions by the spec: normalise the stored values so that
  // slerp measures the true angle (a CUBICSPLINE's values and tangents stay as stored).
  if (per == 1) c.values.rowwise().normalize();
}

}  // namespace

GltfAnimation read_gltf_animation(const GltfAccessors& acc, const GltfRig& rig, size_t ai, int& ignored) {
  const tinygltf::Animation& a = acc.model.animations[ai];
  const int N = static_cast<int>(rig.nodes.size());
  GltfAnimation anim;
  anim.name = a.name.empty() ? "animation " + std::to_string(ai) : a.name;
  anim.start = std::numeric_limits<double>::infinity();
  anim.end = -std::numeric_limits<double>::infinity();
  for (size_t ci = 0; ci < a.channels.size(); ++ci) {
    const tinygltf::AnimationChannel& ch = a.channels[ci];
    const std::string clabel = "channel " + std::to_string(ci) + " of animation " + in_quotes(anim.name);
    if (ch.target_node < 0) {  // the spec lets extensions define the target: nothing to animate here
      ++ignored;
      continue;
    }
    if (ch.target_node >= N)
      acc.fail(clabel + ": target node " + std::to_string(ch.target_node) + " does not exist");
    GltfChannel g;
    g.node = ch.target_node;
    Eigen::Index targets = 0;
    if (ch.target_path == "translation") {
      g.path = GltfPath::Translation;
    } else if (ch.target_path == "rotation") {
      g.path = GltfPath::Rotation;
    } else if (ch.target_path == "scale") {
      g.path = GltfPath::Scale;
    } else if (ch.target_path == "weights") {
      g.path = GltfPath::Weights;
      const auto it = std::find_if(rig.pieces.begin(), rig.pieces.end(),
                                   [&](const GltfPiece& p) { return p.node == g.node; });
      if (it == rig.pieces.end() || it->targets.empty()) {  // morphs of a mesh not read here
        ++ignored;
        continue;
      }
      targets = it->num_targets();
    } else {
      acc.fail(clabel + ": target path '" + ch.target_path + "' is not supported");
    }
    if (rig.nodes[g.node].has_matrix && g.path != GltfPath::Weights)
      acc.fail(clabel + ": animates node " + in_quotes(rig.nodes[g.node].name) +
               ", which is given by a matrix (not allowed)");
    if (ch.sampler < 0 || ch.sampler >= static_cast<int>(a.samplers.size()))
      acc.fail(clabel + ": sampler " + std::to_string(ch.sampler) + " does not exist");
    read_sampler(acc, a.samplers[ch.sampler],
                 "sampler " + std::to_string(ch.sampler) + " of animation " + in_quotes(anim.name), targets,
                 g);
    anim.start = std::min(anim.start, g.times[0]);
    anim.end = std::max(anim.end, g.times[g.times.size() - 1]);
    anim.channels.push_back(std::move(g));
  }
  if (anim.channels.empty()) anim.start = anim.end = 0.0;
  return anim;
}

}  // namespace spinmotor::detail
