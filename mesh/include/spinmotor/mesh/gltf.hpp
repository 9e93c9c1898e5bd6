#pragma once
// glTF 2.0 skinned characters, read as the file holds them: every skinned mesh of the scene (or those
// named), its morph targets, the skins, the node hierarchy and the animations. Evaluating the file
// (sampling an animation, the joint matrices, skinning) is deform/'s: deform/gltf_animation.hpp and
// deform/gltf_skin.hpp. This header also writes and reads back baked morph-target animations.
//
// What read_gltf keeps (glTF 2.0 specification, §3.7 "Meshes" and §3.8 "Skins"):
//   - pieces: every node of the default scene (or of every node when the file has no scene) that has
//     both `mesh` and `skin`, in node order, or those GltfReadOptions::meshes names (node or mesh
//     name). Each piece's TRIANGLES primitives (mode 4 or absent; strips and fans are triangulated;
//     LINES and POINTS primitives are skipped with a warning) are merged; each needs POSITION (float
//     VEC3, or quantised integers under KHR_mesh_quantization) and JOINTS_0/WEIGHTS_0. `indices`
//     (unsigned byte/short/int) are optional.
//   - welding, per piece: file vertices of one piece whose positions are exactly equal (== on the stored
//     floats, −0 == +0) become one surface vertex, so that a character split at UV seams and materials is
//     one surface again. Pieces are never welded to each other. The surface of all pieces is `mesh`, piece
//     after piece; file_to_surface maps each file vertex (pieces, then primitives, concatenated) to its
//     surface vertex and surface_to_file each surface vertex to its lowest file vertex, whose weights
//     and morph displacements it takes; file vertices welded to a vertex with other weights (> 1e-6) are
//     counted (weld_weight_mismatches, a warning). Triangles that welding collapses are dropped and
//     counted.
//   - UVs: Mesh::UV holds one row per file vertex, v flipped (glTF's origin is the top-left of the
//     image, OBJ's the bottom-left), and FUV the file vertex of each corner: seams survive.
//   - weights: every set JOINTS_n/WEIGHTS_n (unsigned byte/short joints; float or normalised unsigned
//     byte/short weights). A joint index ≥ the skin's joint count (with a non-zero weight), a negative
//     or non-finite weight or an all-zero row is an error. Rows are renormalised to sum 1 (as Blender's
//     armature does); rows whose sum is off 1 by more than their storage allows (1e-5 for floats, half a
//     step per stored weight for normalised integers) are counted (renormalised_rows) and reported
//     with the range of the sums.
//   - joints: one per distinct (node, inverse bind matrix) over the skins the pieces use: with one skin,
//     its joints in order. The weights matrix is n×J in this numbering. Inverse bind matrices are kept as
//     stored (they may scale, rotate or place the bind space anywhere: the spec multiplies them by the
//     joints' global matrices and ignores the skinned node's own transform).
//   - morph targets (§3.7.2.2): the POSITION displacements of every target (a target without POSITION
//     displaces nothing), in the piece's welded numbering; the default weights are the node's
//     `weights`, else the mesh's, else 0; target names from mesh.extras.targetNames.
//   - nodes: the whole hierarchy (a node with two parents or a cycle is an error), each with `matrix` or
//     T·R·S (rotation normalised); sparse accessors are applied.
//   - animations: channels on translation, rotation, scale and weights, LINEAR (slerp for rotations),
//     STEP or CUBICSPLINE; key times finite and strictly increasing, outputs finite, of the right type and
//     count. A `weights` channel on a node that is not a selected piece, or a channel without a target
//     node, is ignored (counted in ignored_channels); a channel on a node given by `matrix` is an error.
//   - rejected: no skinned mesh (or a named one that does not exist, listing those that do), a required
//     extension that changes geometry (Draco, meshopt), NaN/Inf in any accessor read, an inverse bind
//     matrix whose last row is not (0 0 0 1), fewer inverse bind matrices than joints, a joint listed twice
//     in one skin, morph targets whose count differs between the primitives of a mesh.
// Every problem throws spinmotor::Error "FILE: <element>: <what>" naming the accessor, node, mesh,
// primitive, vertex or animation channel. Materials, images, normals and cameras are not read.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <filesystem>
#include <string>
#include <vector>

#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

struct GltfNode {
  std::string name;  ///< the file's name, or "node <index>" when it has none
  int parent = -1;   ///< node index, −1 for a root
  bool has_matrix = false;
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();  ///< the `matrix` (has_matrix)
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  ///< normalised
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
};

enum class GltfPath { Translation, Rotation, Scale, Weights };
enum class GltfInterpolation { Linear, Step, CubicSpline };

/// One animated property of one node (sample it with deform/gltf_animation.hpp).
struct GltfChannel {
  int node = -1;
  GltfPath path = GltfPath::Translation;
  GltfInterpolation interpolation = GltfInterpolation::Linear;
  Eigen::VectorXd times;  ///< k key times in seconds, strictly increasing
  /// k×c values: c = 3 (translation, scale), 4 (rotation, x y z w, normalised for LINEAR and STEP) or the
  /// node's morph target count (weights); CUBICSPLINE: 3k×c, per key in-tangent, value, out-tangent.
  Eigen::MatrixXd values;
};

struct GltfAnimation {
  std::string name;               ///< the file's name, or "animation <index>"
  double start = 0.0, end = 0.0;  ///< the first and last key time over all channels
  std::vector<GltfChannel> channels;
  double duration() const { return end - start; }
};

/// One skinned mesh node of the file, welded: surface vertices [first_vertex, first_vertex + vertices)
/// and faces [first_face, first_face + faces) of GltfRig::mesh.
struct GltfPiece {
  std::string name;  ///< the node's name, else the mesh's, else "mesh <index>"
  int node = -1;     ///< the skinned node
  int mesh = -1;     ///< the glTF mesh index
  int skin = -1;     ///< index into GltfRig::skins
  Eigen::Index first_vertex = 0, vertices = 0;
  Eigen::Index first_face = 0, faces = 0;
  /// File vertices of the piece's primitives, concatenated: [first_file_vertex, + file_vertices) of
  /// file_to_surface; primitive p of the glTF mesh starts at file vertex primitive_start[p] (global),
  /// skipped primitives (LINES, POINTS) have no vertices.
  Eigen::Index first_file_vertex = 0, file_vertices = 0;
  std::vector<Eigen::Index> primitive_start;
  int dropped_faces = 0;  ///< triangles collapsed by welding
  /// Morph targets: T POSITION displacement fields, each vertices×3 (the piece's surface vertices).
  std::vector<Eigen::MatrixXd> targets;
  std::vector<std::string> target_names;  ///< T names (mesh.extras.targetNames, else "target <k>")
  Eigen::VectorXd default_weights;        ///< T weights at rest (node, else mesh, else 0)
  Eigen::Index num_targets() const { return static_cast<Eigen::Index>(targets.size()); }
};

struct GltfSkin {
  std::string name;         ///< the file's name, or "skin <index>"
  int file_index = -1;      ///< index of the skin in the file
  int skeleton = -1;        ///< the `skeleton` node, −1 when not given
  std::vector<int> joints;  ///< the skin's joints in its own order, as indices into GltfRig's joints
};

struct GltfRig {
  std::filesystem::path file;
  std::vector<GltfNode> nodes;  ///< the file's whole node hierarchy
  std::vector<GltfPiece> pieces;
  std::vector<GltfSkin> skins;  ///< the skins the pieces use

  Mesh mesh;  ///< every piece's welded surface in its POSITION frame (UV per file vertex)
  Eigen::VectorXi file_to_surface;  ///< file vertex -> surface vertex
  Eigen::VectorXi surface_to_file;  ///< surface vertex -> its lowest file vertex
  Eigen::Index file_vertices = 0;   ///< vertices of the pieces' primitives (before welding)
  int dropped_faces = 0;            ///< over all pieces

  // Joints: J entries (see the header comment).
  std::vector<int> joint_nodes;               ///< node index of each joint
  std::vector<std::string> joint_names;       ///< the node names
  std::vector<int> joint_parents;             ///< nearest ancestor that is a joint, −1 for none
  std::vector<int> joint_skins;               ///< the first skin (index into skins) that lists the joint
  std::vector<Eigen::Matrix4d> inverse_bind;  ///< IBM_j (identity when the skin has none)

  Eigen::SparseMatrix<double> weights;  ///< n×J surface weights, rows sum to 1
  int renormalised_rows = 0;  ///< file vertices whose weight sum is off 1 by more than storage precision
  double min_weight_sum = 1.0, max_weight_sum = 1.0;  ///< over the file's rows
  int weld_weight_mismatches = 0;                     ///< welded file vertices whose weights differ (> 1e-6)
  double weld_weight_max_difference = 0.0;

  std::vector<GltfAnimation> animations;
  int ignored_channels = 0;           ///< channels on nothing read (weights of other meshes, no target)
  std::vector<std::string> warnings;  ///< renormalised weights, weld mismatches, skipped primitives, ...

  Eigen::Index num_joints() const { return static_cast<Eigen::Index>(joint_nodes.size()); }
  /// The piece holding surface vertex v (Error for a vertex out of range).
  int piece_of_vertex(Eigen::Index v) const;
  /// Where surface vertex v comes from, in the file's own numbering: "mesh 'Body' primitive 2 vertex 17"
  /// (the vertex's lowest file vertex; the index is the primitive's own).
  std::string vertex_label(Eigen::Index v) const;
};

struct GltfReadOptions {
  /// Pieces to read by node or mesh name (every one must exist); empty: every skinned mesh of the scene.
  std::vector<std::string> meshes;
};

/// Reads a .gltf (buffers as data: URIs or side files in its folder) or .glb. See the header comment for
/// what is read and rejected. Throws Error naming the file and the element.
GltfRig read_gltf(const std::filesystem::path& path, const GltfReadOptions& options = {});

/// Names of the skinned meshes of a file (node name, mesh name) in the order read_gltf reads them,
/// without reading their data. Throws Error as read_gltf for a file that cannot be parsed.
std::vector<std::pair<std::string, std::string>> gltf_skinned_meshes(const std::filesystem::path& path);

/// A piece of a surface written as its own glTF mesh and node: vertices [first_vertex, + vertices) and
/// faces [first_face, + faces) (the faces use only the piece's vertices).
struct GltfMorphPiece {
  std::string name;
  Eigen::Index first_vertex = 0, vertices = 0, first_face = 0, faces = 0;
};

/// Writes a baked animation as glTF 2.0 (.gltf with the buffer as a data: URI, or .glb by extension):
/// one mesh node per piece (default: one piece, the whole of `rest`, named `name`), each holding its part
/// of `rest` (UVs, if any, un-welded into glTF vertices at seams and flipped back) and one morph target
/// per frame (POSITION displacements frames[f] − rest.V), driven by a STEP `weights` animation that is
/// one-hot on target f from times[f] on. So Blender, three.js, ... play the baked frames (targets named
/// "frame 0000", ... in mesh.extras.targetNames, which Blender uses for the shape keys). The piece nodes
/// are children of one root node whose matrix is `node_matrix` (it must be affine). Sizes: frames[f]
/// n×3, times strictly increasing, as many as frames. Positions are stored as float32. Atomic; throws
/// Error naming the frame or piece for a size mismatch or non-finite entry.
void write_gltf_morph_animation(const std::filesystem::path& path, const Mesh& rest,
                                const std::vector<Eigen::MatrixXd>& frames, const std::vector<double>& times,
                                const std::string& name = "baked",
                                const Eigen::Matrix4d& node_matrix = Eigen::Matrix4d::Identity(),
                                const std::vector<GltfMorphPiece>& pieces = {});

/// A baked morph-target animation read back (the output of write_gltf_morph_animation, or any glTF
/// whose mesh nodes carry POSITION morph targets).
struct GltfMorphAnimation {
  Mesh mesh;  ///< the base surface, welded like read_gltf (UV/FUV per file vertex, v flipped)
  std::vector<Eigen::MatrixXd> frames;  ///< per target: base + displacement (n×3, welded vertices)
  std::vector<double> times;            ///< per target: its key time in the first `weights` animation
  Eigen::Matrix4d node_matrix = Eigen::Matrix4d::Identity();  ///< the first mesh node's global matrix
  std::string name;                                           ///< the first mesh's name
  std::vector<GltfMorphPiece> pieces;                         ///< one per mesh node read
};

/// Reads every node (in index order) with a mesh whose primitives carry POSITION morph targets, each
/// with the same number of targets: primitives merged (TRIANGLES, POSITION float VEC3, each target
/// with a float VEC3 POSITION), file vertices of one node with equal base positions welded (a welded
/// vertex takes the frame positions of its first file vertex), the nodes' surfaces concatenated (in
/// their own coordinates: the first node's global matrix is node_matrix). Target f's time is the first
/// key of the first animation channel on the first node's `weights` where target f's weight is the
/// largest (a one-hot STEP animation as written above gives back its times); without such a channel,
/// times are 0, 1, 2, ... Throws Error naming the file and the element.
GltfMorphAnimation read_gltf_morph_animation(const std::filesystem::path& path);

}  // namespace spinmotor
