#pragma once
// Writing a skinned character back out as glTF 2.0: the inverse of read_gltf (gltf.hpp) for what a
// GltfRig holds, so that a rig built or changed by the project (a procedural character,
// procedural_rig.hpp; a rig with corrective morph targets, deform/gltf_correctives.hpp) opens in
// Blender, three.js, assimp, ... and in read_gltf itself.
//
// Input: a GltfRig (as read_gltf returns it, or built by hand with the same invariants: nodes with
// parents forming a forest; pieces whose vertex and face ranges tile `mesh`, each on an existing node
// and skin; skins listing joint entries; weights n×J with rows ≥ 0 and not all zero, every influence of
// a piece's vertex on a joint of the piece's skin; inverse_bind J matrices with last row (0 0 0 1);
// morph targets vertices×3 per piece with as many default weights and names; channels on existing
// nodes with k key times and k (CUBICSPLINE: 3k) values of 3 (rotation: 4, x y z w; weights: the node's
// target count) columns).
// Output (.gltf with the buffer as a data: URI, or .glb, by extension; written atomically):
//   - every node with its name and either `matrix` or the non-identity parts of T, R, S; children from
//     the parents; the scene's roots are the nodes without a parent;
//   - per piece, on its node, mesh p and its skin: one TRIANGLES primitive with POSITION (float32),
//     TEXCOORD_0 (when the mesh has UVs: per-corner UVs split into glTF vertices at seams, v flipped back
//     to glTF's top-left origin), JOINTS_n (unsigned short) / WEIGHTS_n (float32) sets of four influences,
//     largest first, its morph targets (POSITION displacements, float32; mesh.weights = the default
//     weights, names in mesh.extras.targetNames) and uint32 indices. glTF vertex v of the piece is its
//     surface vertex v (seam duplicates follow), so read_gltf, which welds equal positions in file order,
//     returns the surface in the same vertex and face order (when no two vertices of a piece round to
//     the same float32 position);
//   - the skins: their joints' nodes and inverse bind matrices (float32 MAT4);
//   - every animation, one sampler per channel (float32 times and values, the channel's interpolation).
// Throws Error "<file>: <what>" for a wrong extension, an inconsistent rig (naming the node, joint,
// piece, vertex or channel) or a non-finite value; nothing is written then.
#include <filesystem>

#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor {

void write_gltf_rig(const std::filesystem::path& path, const GltfRig& rig);

}  // namespace spinmotor
