#pragma once
// Writing a skinned character back out as glTF 2.0: the inverse of read_gltf (gltf.hpp) for what a
// GltfRig holds — so a rig built or repaired by the project (a procedural rig, procedural_rig.hpp; a
// rig with renormalised weights) opens in Blender, three.js, assimp, ... and in read_gltf itself.
//
// Input: a GltfRig (as read_gltf returns it, or built by hand with the same invariants: nodes with
// parents forming a forest, mesh_node and joint_nodes indices into nodes, weights n×J with rows ≥ 0
// and not all zero, inverse_bind J matrices with last row (0 0 0 1), channels on existing nodes with
// k key times and k (CUBICSPLINE: 3k) values of 3 (rotation: 4, x y z w) columns).
// Output (.gltf with the buffer as a data: URI, or .glb, by extension; written atomically):
//   - every node with its name and either `matrix` or the non-identity parts of T, R, S; children from
//     the parents; the scene's roots are the nodes without a parent;
//   - the mesh node holds mesh 0 and skin 0: one TRIANGLES primitive with POSITION (float32),
//     TEXCOORD_0 (when the mesh has UVs: per-corner UVs split into glTF vertices at seams, v flipped
//     back to glTF's top-left origin), JOINTS_n (unsigned short) / WEIGHTS_n (float32) sets of four
//     influences, largest first (as many sets as the most influenced vertex needs), and uint32
//     indices. glTF vertex v is surface vertex v (seam duplicates follow), so read_gltf, which welds
//     equal positions in file order, returns the surface in the same vertex and face order (when no
//     two vertices round to the same float32 position);
//   - skin 0: the joints (joint_nodes) and their inverse bind matrices (float32 MAT4);
//   - every animation, one sampler per channel (float32 times and values, the channel's
//     interpolation).
// Throws Error "<file>: <what>" for a wrong extension, an inconsistent rig (naming the node, joint,
// vertex or channel) or a non-finite value; nothing is written then.
#include <filesystem>

#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor {

void write_gltf_rig(const std::filesystem::path& path, const GltfRig& rig);

}  // namespace spinmotor
