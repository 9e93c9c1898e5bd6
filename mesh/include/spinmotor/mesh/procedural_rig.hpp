#pragma once
// A procedural rigged limb: the project's own glTF-style character, so that the demo, the tests and the
// benchmarks can pose, clean up and write a rig without any external file (write_gltf_rig turns it
// into a .gltf/.glb that read_gltf reads back).
//
// Geometry: capsule(radius, length, rings, sides) (generators.hpp): the cylinder from z = 0 to
// z = length closed by hemispheres, with its per-corner UVs.
// Skeleton: a chain of `joints` joints "joint0" → "joint1" → ... along +z, joint k at z_k = k·s with the
// segment s = length / joints (node translations (0, 0, s), no rotation or scale). The skinned mesh
// node "limb" is a second root with the identity transform, so mesh space is scene space; inverse bind
// matrices translate by (0, 0, −z_k).
// Weights (n×J, at most two per vertex, rows sum to 1): a vertex at height z belongs to segment
// k = clamp(⌊z / s⌋, 0, J−1), weight 1, except in the band of half-width h = blend·s/2 around each
// inner joint z_k (k = 1..J−1), where joint k gets u = smoothstep((z − z_k + h) / 2h) (3u² − 2u³) and
// joint k−1 gets 1 − u. Vertices with weight 1 form the rigid parts the pose-keeping cleanup pins.
// Animations (LINEAR rotation channels, keys at 0, duration/2, duration, rotation 0 → angle → 0):
//   0 "bend":  every inner joint rotates about its x axis by bend_degrees (the limb curls in the yz
//              plane; the blend bands collapse on the inside under LBS);
//   1 "twist": the last joint rotates about z by twist_degrees (LBS's candy wrapper).
// Requires radius > 0, length > 0, joints ≥ 2, blend ∈ (0, 1], |angles| < 180, duration > 0, and the
// capsule's own limits on rings and sides; throws Error naming the parameter otherwise.
#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor {

struct LimbRigOptions {
  double radius = 0.5;
  double length = 4.0;
  int rings = 96;  ///< capsule rings (along the profile) and sides (around it)
  int sides = 48;
  int joints = 3;
  double blend = 0.5;  ///< width of each joint's weight band, as a fraction of a segment
  double bend_degrees = 60.0;
  double twist_degrees = 90.0;
  double duration = 2.0;  ///< seconds, both animations
};

/// The rig described above: rig.file is empty, file_to_surface the identity, every derived field
/// (joint parents, rest transforms, inverse bind matrices, animation ranges) filled as read_gltf would.
GltfRig limb_rig(const LimbRigOptions& options = {});

}  // namespace spinmotor
