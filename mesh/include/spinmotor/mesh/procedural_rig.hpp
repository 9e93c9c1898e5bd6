#pragma once
// Procedural rigged characters: the project's own glTF-style characters, so that the demo, the tests and
// the benchmarks can pose, clean up and write rigs without any external file (write_gltf_rig turns one
// into a .gltf/.glb that read_gltf and Blender read back).
//
// limb_rig: a capsule limb on a chain of joints.
//   Geometry: capsule(radius, length, rings, sides) (generators.hpp): the cylinder from z = 0 to
//   z = length closed by hemispheres, with its per-corner UVs.
//   Skeleton: a chain of `joints` joints "joint0" → "joint1" → ... along +z, joint k at z_k = k·s with
//   the segment s = length / joints (node translations (0, 0, s)). The skinned mesh node "limb" is a
//   second root with the identity transform; inverse bind matrices translate by (0, 0, −z_k).
//   Weights (at most two per vertex, rows sum to 1): a vertex at height z belongs to segment
//   k = clamp(⌊z / s⌋, 0, J−1), weight 1, except in the band of half-width h = blend·s/2 around each
//   inner joint z_k, where joint k gets u = smoothstep((z − z_k + h) / 2h) (3u² − 2u³) and joint k−1
//   gets 1 − u. Vertices with weight 1 form the rigid parts the pose-keeping cleanup pins.
//   Animations (LINEAR rotation channels, keys at 0, duration/2, duration, rotation 0 → angle → 0):
//     0 "bend":  every inner joint rotates about its x axis by bend_degrees;
//     1 "twist": the last joint rotates about z by twist_degrees (LBS's candy wrapper).
//   Requires radius > 0, length > 0, joints ≥ 2, blend ∈ (0, 1], |angles| < 180, duration > 0, and the
//   capsule's own limits on rings and sides; throws Error naming the parameter otherwise.
//
// character_rig: a standing figure of seven separate pieces on one skin, in the layouts production files
// come in. Scene space is glTF's: +Y up, metres, the figure 1.8 tall, facing +Z, feet at y = 0.
//   Pieces (each its own glTF mesh and node, never welded to another; pieces overlap as armour does):
//     "Torso" a capsule from the hips (y = 0.95) to the neck (1.55), radius 0.16, weighted on hips,
//             spine, chest, neck and both shoulders by Gaussians of the height (up to six influences:
//             JOINTS_1 is written), so it has no rigid vertex;
//     "Head"  a sphere of radius 0.12 at (0, 1.72, 0), weight 1 on "head" (moves rigidly); with
//             morph_targets, targets "bulge" (the upper half pushed out by 0.03 along the normal) and
//             "squint" (the front flattened), animated by a weights channel;
//     "ArmL", "ArmR" capsules from the shoulders (±0.22, 1.5, 0) to the wrists (±0.82, 1.5, 0),
//             radius 0.05, smoothstep bands at the elbow (shoulder → elbow), rigid elsewhere;
//     "LegL", "LegR" capsules from the hips (±0.1, 0.92, 0) to the ankles (±0.1, 0.06, 0), radius 0.07,
//             bands at the knee;
//     "Cap"   a small disc (an open piece) on top of the head, weight 1 on "head".
//   Skeleton (nodes, parent first): hips → spine → chest → neck → head; chest → shoulderL → elbowL →
//   wristL (and R); hips → thighL → kneeL → ankleL (and R).
//   Layout (CharacterLayout): where the skeleton and the POSITION data live.
//     Scene    joints and meshes are roots; POSITION in scene units; IBM_j = W_j⁻¹ at rest.
//     Mixamo   an "Armature" node (rotation −90° about x, scale armature_scale) is the parent of the
//              root joint and of every mesh node; joint translations in its units (1/armature_scale:
//              centimetres for 0.01, Z-up); POSITION in scene units and IBM_j = (A J_j)⁻¹, so the mesh
//              nodes' own global matrices (A) are not the bind space: glTF ignores them (§3.7.3).
//     Armature as Mixamo but POSITION in the armature's own units and frame and IBM_j = J_j⁻¹ (the bind
//              space is the armature's): the scene sees A · POSITION.
//   mesh_node_offset: the skinned nodes carry a translation (0.5, 0, 0) and a rotation (which the
//   spec says to ignore).
//   Animations (LINEAR, keys every 1/8 s over 1 s):
//     0 "walk":  thighs swing ±walk_degrees about x, knees bend 0 … walk_degrees, shoulders swing
//                opposite, elbows bend, the head nods, the hips bob; with morph_targets the Head's
//                weights go 0 → 1 → 0 (bulge) and 0 → 0.5 (squint);
//     1 "squash" (scale_animation): the chest scales uniformly 1 → 1.2 → 1 and elbowL non-uniformly
//                (1, 1.5, 1) → (1, 1, 1): joint transforms that are not rigid motions.
//   resolution scales the tessellation (1: about 3,000 vertices; 2: about 11,000).
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

/// The limb described above: rig.file is empty, file_to_surface the identity, every derived field
/// (joint parents, skin, inverse bind matrices, animation ranges) filled as read_gltf would.
GltfRig limb_rig(const LimbRigOptions& options = {});

enum class CharacterLayout { Scene, Mixamo, Armature };

struct CharacterRigOptions {
  CharacterLayout layout = CharacterLayout::Scene;
  double armature_scale = 0.01;   ///< Mixamo and Armature layouts
  bool mesh_node_offset = false;  ///< a transform on every skinned node (to be ignored)
  bool morph_targets = true;      ///< the Head's two targets and their weights channel
  bool scale_animation = true;    ///< animation 1 "squash"
  double walk_degrees = 35.0;
  int resolution = 1;  ///< ≥ 1
};

/// The standing character described above, filled as read_gltf would fill it. Throws Error for
/// resolution < 1, a non-positive or non-finite armature_scale, |walk_degrees| ≥ 90.
GltfRig character_rig(const CharacterRigOptions& options = {});

}  // namespace spinmotor
