#pragma once
// Sampling a glTF rig's animations (mesh/gltf.hpp): channel values at any time, the nodes' local and
// global matrices and the pieces' morph weights. Skinning with them is gltf_skin.hpp's.
//
//   sample_channel   glTF 2.0 Appendix C "Interpolation": LINEAR (spherical, shortest arc, for
//                    rotations), STEP, CUBICSPLINE (Hermite with the stored tangents scaled by the key
//                    interval); times clamped to [first key, last key]; rotation results normalised.
//   node matrices    each node's `matrix`, or T·R·S from its rest translation, rotation and scale with
//                    the animated ones replacing them (§3.5.3), composed from the roots down.
//   morph weights    per piece: its default weights, replaced by the animation's `weights` channel on the
//                    piece's node when there is one (§3.7.2.2).
// Inputs: anim is an index into rig.animations or −1 for the rest pose (no channel applied); t seconds.
// Errors (spinmotor::Error): an animation index out of range, a non-finite time.
#include <Eigen/Core>
#include <vector>

#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor {

/// The value of a channel at time t (a row of c values; see GltfChannel).
Eigen::VectorXd sample_channel(const GltfChannel& channel, double t);

/// Time of frame f of n (n ≥ 1) evenly spread over [start, end] of the animation (n = 1: start).
double gltf_frame_time(const GltfAnimation& anim, int f, int n);

/// The local matrix of every node at time t of animation `anim` (−1: the rest pose).
std::vector<Eigen::Matrix4d> node_local_matrices(const GltfRig& rig, int anim, double t);

/// The global (scene) matrix of every node: parent global · local, from the roots down.
std::vector<Eigen::Matrix4d> node_world_matrices(const GltfRig& rig, int anim, double t);

/// The morph weights of every piece at time t (piece p: rig.pieces[p].num_targets() values).
std::vector<Eigen::VectorXd> morph_weights(const GltfRig& rig, int anim, double t);

/// Throws Error naming the file for an animation index out of [−1, animations) or a non-finite t.
void check_animation_time(const GltfRig& rig, int anim, double t);

}  // namespace spinmotor
