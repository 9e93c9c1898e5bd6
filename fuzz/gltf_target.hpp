#pragma once
// The body of fuzz_gltf and fuzz_glb (the same readers; tinygltf tells .gltf JSON from .glb by the
// extension): read_gltf, then what the rig promises and the evaluations a caller runs next (rest
// frames, skinning at the rest pose and at the ends and middle of every animation); and, independently,
// read_gltf_morph_animation. An Error from the evaluations is a refusal too (e.g. a joint transform that
// is not a similarity, which read_gltf cannot see for every animation time).
#include <optional>
#include <string>

#include "fuzz_support.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor::fuzz {

inline void check_rig(const GltfRig& rig) {
  check_mesh(rig.mesh);
  const Eigen::Index n = rig.mesh.V.rows(), J = rig.num_joints();
  check(J > 0 && rig.weights.rows() == n && rig.weights.cols() == J, "weights are n x J");
  check(static_cast<Eigen::Index>(rig.joint_names.size()) == J &&
            static_cast<Eigen::Index>(rig.joint_parents.size()) == J &&
            static_cast<Eigen::Index>(rig.joint_rest_local.size()) == J &&
            static_cast<Eigen::Index>(rig.inverse_bind.size()) == J,
        "one name, parent, rest transform and inverse bind matrix per joint");
  check(rig.file_to_surface.size() == rig.file_vertices, "file_to_surface has one entry per file vertex");
  if (rig.file_to_surface.size() > 0)
    check(rig.file_to_surface.minCoeff() >= 0 && rig.file_to_surface.maxCoeff() < n,
          "file_to_surface maps to surface vertices");
  const int N = static_cast<int>(rig.nodes.size());
  check(rig.mesh_node >= 0 && rig.mesh_node < N, "mesh_node is a node");
  for (const GltfNode& node : rig.nodes) check(node.parent >= -1 && node.parent < N, "parents are nodes");
  for (int j : rig.joint_nodes) check(j >= 0 && j < N, "joints are nodes");
}

inline void evaluate_rig(const GltfRig& rig) {
  try {
    (void)joint_rest_frames(rig);
    (void)skin_positions(rig, -1, 0.0);
    for (int a = 0; a < static_cast<int>(rig.animations.size()); ++a)
      for (int f = 0; f < 3; ++f) (void)skin_positions(rig, a, gltf_frame_time(rig.animations[a], f, 3));
  } catch (const Error& e) {
    refused(e);
  }
}

inline int fuzz_gltf_input(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const std::filesystem::path path = write_input(data, size, name);
  // The checks run outside the try blocks: an Error from validate() there is a finding.
  std::optional<GltfRig> rig;
  try {
    rig = read_gltf(path);
  } catch (const Error& e) {
    refused(e);
  }
  if (rig) {
    check_rig(*rig);
    evaluate_rig(*rig);
  }
  std::optional<GltfMorphAnimation> anim;
  try {
    anim = read_gltf_morph_animation(path);
  } catch (const Error& e) {
    refused(e);
  }
  if (anim) {
    check_mesh(anim->mesh);
    check(anim->times.size() == anim->frames.size(), "one time per frame");
    for (const Eigen::MatrixXd& frame : anim->frames)
      check(frame.rows() == anim->mesh.V.rows() && frame.cols() == 3, "frames are n x 3");
  }
  return 0;
}

}  // namespace spinmotor::fuzz
