#pragma once
// The body of fuzz_gltf and fuzz_glb (the same readers; tinygltf tells .gltf JSON from .glb by the
// extension): read_gltf, then what the rig promises and the evaluations a caller runs next (the skin's
// bones and bind matrices, skinning at the rest pose and at the ends and middle of every animation); and,
// independently, read_gltf_morph_animation. An Error from the evaluations is a refusal too (e.g. a
// singular bind matrix, which read_gltf does not evaluate).
#include <optional>
#include <string>

#include "fuzz_support.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/gltf_animation.hpp"
#include "spinmotor/deform/gltf_skin.hpp"
#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor::fuzz {

inline void check_rig(const GltfRig& rig) {
  check_mesh(rig.mesh);
  const Eigen::Index n = rig.mesh.V.rows(), J = rig.num_joints();
  check(J > 0 && rig.weights.rows() == n && rig.weights.cols() == J, "weights are n x J");
  check(static_cast<Eigen::Index>(rig.joint_names.size()) == J &&
            static_cast<Eigen::Index>(rig.joint_parents.size()) == J &&
            static_cast<Eigen::Index>(rig.joint_skins.size()) == J &&
            static_cast<Eigen::Index>(rig.inverse_bind.size()) == J,
        "one name, parent, skin and inverse bind matrix per joint");
  check(rig.file_to_surface.size() == rig.file_vertices, "file_to_surface has one entry per file vertex");
  if (rig.file_to_surface.size() > 0)
    check(rig.file_to_surface.minCoeff() >= 0 && rig.file_to_surface.maxCoeff() < n,
          "file_to_surface maps to surface vertices");
  const int N = static_cast<int>(rig.nodes.size());
  check(!rig.pieces.empty(), "a rig has a piece");
  Eigen::Index v = 0, f = 0;
  for (const GltfPiece& p : rig.pieces) {
    check(p.node >= 0 && p.node < N && p.skin >= 0 && p.skin < static_cast<int>(rig.skins.size()),
          "pieces name nodes and skins");
    check(p.first_vertex == v && p.first_face == f && p.vertices > 0 && p.faces > 0,
          "pieces tile the surface");
    for (const Eigen::MatrixXd& t : p.targets)
      check(t.rows() == p.vertices && t.cols() == 3, "targets are piece vertices x 3");
    v += p.vertices, f += p.faces;
  }
  check(v == n && f == rig.mesh.F.rows(), "pieces cover the surface");
  check(rig.surface_to_file.size() == n, "surface_to_file has one entry per surface vertex");
  for (const GltfNode& node : rig.nodes) check(node.parent >= -1 && node.parent < N, "parents are nodes");
  for (int j : rig.joint_nodes) check(j >= 0 && j < N, "joints are nodes");
}

inline void evaluate_rig(const GltfRig& rig) {
  try {
    (void)rig_skin(rig);
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
