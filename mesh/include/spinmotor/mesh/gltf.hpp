#pragma once
// glTF 2.0 skinned characters: read a rig (surface, skeleton, skin weights, animations), evaluate its
// joint and skinning transforms at any time, and write a baked animation back as glTF morph targets.
//
// Spaces. POSITION data lives in the *mesh space* (the local frame of the skinned mesh node). The
// skinning matrix of joint j is, as the glTF 2.0 spec and its skinning tutorial define it,
//     S_j = W_mesh⁻¹ · W_j · IBM_j
// (W the node's global matrix at the same time, IBM_j the inverse bind matrix, identity when the skin
// has none), and a vertex moves to Σ_j w_j S_j v. Everything this header returns (positions, joint
// rest frames, skinning matrices) is in mesh space, so for a file whose bind pose is its rest pose
// (global(joint) · IBM = global(mesh node), true of the Khronos samples) S_j = I at rest and the rest
// pose reproduces POSITION. W_mesh places the result in the scene (joint_world_matrices is in scene
// space).
//
// What read_gltf keeps and checks (every problem throws spinmotor::Error "FILE: <element>: <what>"
// naming the accessor index, node, mesh primitive or animation channel):
//   - the skinned mesh: the first node (lowest index) that has both `mesh` and `skin`. All of its
//     primitives are merged; each must be TRIANGLES (mode 4 or absent; strips, fans, lines and points
//     are rejected), carry POSITION (VEC3 float) and JOINTS_0/WEIGHTS_0, and have no morph targets.
//     `indices` (unsigned byte/short/int) are optional; indices ≥ the primitive's vertex count are an
//     error. TEXCOORD_0 (float or normalised unsigned byte/short) is kept per corner.
//   - welding: glTF splits a vertex wherever its UV or normal changes; file vertices whose positions
//     are exactly equal (== on the stored floats, −0 == +0) become one surface vertex, so that a
//     closed character is a closed manifold surface. file_to_surface maps each file vertex (primitives
//     concatenated in order) to its surface vertex; the surface vertex takes the weights of its
//     lowest-numbered file vertex, and file vertices whose (renormalised) weights differ from those by
//     more than 1e-6 are counted in weld_weight_mismatches (max difference weld_weight_max_difference;
//     a warning is added). Triangles that welding collapses (two equal corner positions) are dropped
//     and counted.
//   - UVs: Mesh::UV holds one row per file vertex, with v flipped (glTF's origin is the top-left of
//     the image, OBJ's the bottom-left), and FUV the file vertex of each corner: seams survive.
//   - weights: all sets JOINTS_n/WEIGHTS_n (n = 0, 1, ...; unsigned byte/short joints; float or
//     normalised unsigned byte/short weights). A joint index ≥ joints.length (whatever its weight), a
//     negative or non-finite weight or an all-zero row is an error. Rows are renormalised to sum 1;
//     rows whose sum was off by more than 1e-5 are counted (renormalised_rows, over file vertices) and
//     reported as a warning — exporters that drop influences beyond four leave such rows.
//   - nodes: the whole hierarchy (parents from `children`; a node with two parents or a cycle is an
//     error), each with `matrix` or T·R·S (rotation normalised). Sparse accessors are applied.
//   - animations: channels on translation / rotation / scale with LINEAR (slerp for rotations), STEP
//     or CUBICSPLINE samplers; key times must be finite and strictly increasing, outputs finite, of
//     the right type and count. `weights` channels (morph targets) are skipped with a warning; a
//     channel on a node given by `matrix` is an error (the spec forbids it).
//   - scale: the motor representation (ScaledMotor) holds rigid motions with a uniform scale. A
//     joint or the mesh node whose scale (rest or any animation key) is non-uniform by more than
//     kGltfScaleTolerance (relative), or not positive, or whose `matrix` is not a similarity, is an
//     error naming the node. Other nodes may scale freely: a transform common to the mesh node and
//     the joints (a root's axis change) cancels in W_mesh⁻¹ W_j; one in between makes a joint's rest
//     transform non-similar (error naming the joint) or, animated, a skinning transform (error from
//     skinning_motors / rig_pose_motors naming the joint and the time). Uniform scales — and the
//     float noise of exporters (0.9999998) — are kept exactly in the 4×4 matrices and folded into
//     ScaledMotor::scale (cube root of the determinant) in the motor representation.
//   - rejected: no skinned mesh node, extensionsRequired (Draco, quantisation, ...), NaN/Inf in any
//     accessor read, an inverse bind matrix whose last row is not (0 0 0 1), fewer inverse bind
//     matrices than joints, a joint listed twice.
// Materials, textures, normals, cameras and other meshes are not read (images are not decoded).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <filesystem>
#include <string>
#include <vector>

#include "spinmotor/ga/interop.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

/// Relative tolerance of the uniform-scale and similarity checks (exporter noise is ~1e-6).
inline constexpr double kGltfScaleTolerance = 1e-4;

/// A similarity x ↦ M (s x) ~M: a unit motor M (rotation, then translation) after a uniform scale s > 0.
struct ScaledMotor {
  ga::Mot motor{1, 0, 0, 0, 0, 0, 0, 0};
  double scale = 1.0;
};

/// The similarity of a 4×4 matrix [s R  t; 0 0 0 1]: s = cbrt(det), R the rotation nearest to the
/// linear part / s. Throws Error "<what>: ..." when the last row is not (0 0 0 1), an entry is not
/// finite, det ≤ 0 (a reflection or a collapse), or |LᵀL / s² − I| > tolerance (shear or
/// non-uniform scale).
ScaledMotor scaled_motor(const Eigen::Matrix4d& m, const std::string& what,
                         double tolerance = kGltfScaleTolerance);

/// The 4×4 matrix of a similarity (inverse of scaled_motor up to its projection onto similarities).
Eigen::Matrix4d to_matrix(const ScaledMotor& s);

struct GltfNode {
  std::string name;  ///< the file's name, or "node <index>" when it has none
  int parent = -1;   ///< node index, −1 for a root
  bool has_matrix = false;
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();  ///< the `matrix` (has_matrix)
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  ///< normalised
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
};

enum class GltfPath { Translation, Rotation, Scale };
enum class GltfInterpolation { Linear, Step, CubicSpline };

/// One animated property of one node.
struct GltfChannel {
  int node = -1;
  GltfPath path = GltfPath::Translation;
  GltfInterpolation interpolation = GltfInterpolation::Linear;
  Eigen::VectorXd times;  ///< k key times in seconds, strictly increasing
  /// k×c values (c = 3, rotations c = 4 as x y z w, normalised for LINEAR and STEP); CUBICSPLINE:
  /// 3k×c, per key in-tangent, value, out-tangent (the file's layout).
  Eigen::MatrixXd values;

  /// The value at time t, clamped to [times(0), times(k−1)] (glTF spec, Appendix C "Interpolation").
  /// Rotations: LINEAR is the shortest-arc slerp; every rotation result is normalised.
  Eigen::VectorXd sample(double t) const;
};

struct GltfAnimation {
  std::string name;               ///< the file's name, or "animation <index>"
  double start = 0.0, end = 0.0;  ///< the first and last key time over all channels
  std::vector<GltfChannel> channels;
  double duration() const { return end - start; }
};

struct GltfRig {
  std::filesystem::path file;
  Mesh mesh;                        ///< welded surface in mesh space (UV per corner, see above)
  Eigen::VectorXi file_to_surface;  ///< file vertex -> surface vertex
  Eigen::Index file_vertices = 0;   ///< vertices of the file's primitives (before welding)
  int dropped_faces = 0;            ///< triangles collapsed by welding
  int mesh_node = -1;               ///< index into nodes of the skinned mesh node
  std::string mesh_name;

  std::vector<GltfNode> nodes;  ///< the file's whole node hierarchy

  // Skeleton: J joints in the skin's order (JOINTS_n index into this list).
  std::vector<int> joint_nodes;          ///< node index of each joint
  std::vector<std::string> joint_names;  ///< the node names
  std::vector<int> joint_parents;        ///< nearest ancestor that is a joint, −1 for none
  /// Rest transform of each joint relative to its parent joint (root joints: relative to mesh space),
  /// as similarities: composing them down the joint tree gives joint_rest_frames().
  std::vector<ScaledMotor> joint_rest_local;
  std::vector<Eigen::Matrix4d> inverse_bind;  ///< IBM_j (identity when the skin has none)

  Eigen::SparseMatrix<double> weights;  ///< n×J surface weights, rows sum to 1
  int renormalised_rows = 0;            ///< file vertices whose weight sum differed from 1 by > 1e-5
  double min_weight_sum = 1.0;          ///< the smallest row sum in the file
  int weld_weight_mismatches = 0;       ///< welded file vertices whose weights differ (> 1e-6)
  double weld_weight_max_difference = 0.0;

  std::vector<GltfAnimation> animations;
  std::vector<std::string> warnings;  ///< renormalised weights, skipped channels, ...

  Eigen::Index num_joints() const { return static_cast<Eigen::Index>(joint_nodes.size()); }
};

/// Reads a .gltf (buffers as data: URIs or side files) or .glb. See the header comment for what is
/// read and rejected. Throws Error naming the file and the element.
GltfRig read_gltf(const std::filesystem::path& path);

/// Time of frame f of n (n ≥ 1) evenly spread over [start, end] of the animation (n = 1: start).
double gltf_frame_time(const GltfAnimation& anim, int f, int n);

/// The local matrix of every node at time t of animation `anim` (an index into rig.animations, or −1
/// for the rest pose): the node's `matrix`, or T·R·S with the animated properties replacing the rest
/// ones. Throws Error for an animation index out of range or a non-finite t.
std::vector<Eigen::Matrix4d> node_local_matrices(const GltfRig& rig, int anim, double t);

/// The global (scene) matrix of every node: parent global · local, from the roots down.
std::vector<Eigen::Matrix4d> node_world_matrices(const GltfRig& rig, int anim, double t);

/// The scene-space matrices W_j of the joints (J, skin order).
std::vector<Eigen::Matrix4d> joint_world_matrices(const GltfRig& rig, int anim, double t);

/// The skinning matrices S_j = W_mesh⁻¹ W_j IBM_j (mesh space to mesh space).
std::vector<Eigen::Matrix4d> skinning_matrices(const GltfRig& rig, int anim, double t);

/// The skinning transforms as similarities (scaled_motor of each S_j; Error naming the joint when one
/// is not a similarity).
std::vector<ScaledMotor> skinning_motors(const GltfRig& rig, int anim, double t);

/// Rest frames of the joints in mesh space, W_mesh⁻¹ W_j at the rest pose, as similarities.
std::vector<ScaledMotor> joint_rest_frames(const GltfRig& rig);

/// The glTF reference skinning with plain matrices: row i = Σ_j w_ij S_j v_i for the surface
/// vertices (n×3, mesh space). The rest pose gives mesh.V up to the file's bind-pose accuracy.
Eigen::MatrixXd skin_positions(const GltfRig& rig, int anim, double t);

/// Writes a baked animation as glTF 2.0 (.gltf with the buffer as a data: URI, or .glb by extension):
/// one mesh node holding `rest` (UVs, if any, un-welded into glTF vertices at seams and flipped back)
/// and one morph target per frame (POSITION displacements frames[f] − rest.V), driven by a STEP
/// `weights` animation that is one-hot on target f from times[f] on. So Blender, three.js, ... play
/// the baked frames (targets named "frame 0000", ... in mesh.extras.targetNames, which Blender uses for
/// the shape keys). `node_matrix` is the node's matrix (for a rig: the mesh node's rest global matrix,
/// so the result sits in the scene as the source did; it must be affine). Sizes: frames[f] n×3, times
/// strictly increasing, as many as frames. Positions are stored as float32. Atomic; throws Error naming
/// the frame for a size mismatch or non-finite entry.
void write_gltf_morph_animation(const std::filesystem::path& path, const Mesh& rest,
                                const std::vector<Eigen::MatrixXd>& frames, const std::vector<double>& times,
                                const std::string& name = "baked",
                                const Eigen::Matrix4d& node_matrix = Eigen::Matrix4d::Identity());

/// A baked morph-target animation read back (the output of write_gltf_morph_animation, or any glTF
/// whose first mesh node has POSITION morph targets).
struct GltfMorphAnimation {
  Mesh mesh;  ///< the base surface, welded like read_gltf (UV/FUV per file vertex, v flipped)
  std::vector<Eigen::MatrixXd> frames;  ///< per target: base + displacement (n×3, welded vertices)
  std::vector<double> times;            ///< per target: its key time in the first `weights` animation
  Eigen::Matrix4d node_matrix = Eigen::Matrix4d::Identity();  ///< the mesh node's global matrix
  std::string name;                                           ///< the mesh's name
};

/// Reads the first node (lowest index) with a mesh whose primitives carry POSITION morph targets:
/// primitives merged (TRIANGLES, POSITION float VEC3, the same number of targets, each with a float
/// VEC3 POSITION), file vertices with equal base positions welded (a welded vertex takes the frame
/// positions of its first file vertex). Target f's time is the first key of the first animation channel
/// on the node's `weights` where target f's weight is the largest (a one-hot STEP animation as written
/// above gives back its times); without such a channel, times are 0, 1, 2, ... The node matrix is the
/// product of its ancestors' rest matrices and its own. Throws Error naming the file and the element.
GltfMorphAnimation read_gltf_morph_animation(const std::filesystem::path& path);

}  // namespace spinmotor
