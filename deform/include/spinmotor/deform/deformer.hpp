#pragma once
// The deformer shape: one contract that every deformer of the project satisfies (surface harmonic,
// spline with keys, spline driven by IK, FFD, cage, ARAP, skin), written down as the concept
// `Deformer` below and type-erased as `AnyDeformer` (any_deformer.hpp), which the scene loader, the
// viewer and the Python module hold. Read this once; every deformer header only says what differs.
//
//   auto d = SomeDeformer::bind(rest_mesh, rig, options);   // all precomputation, once
//   Eigen::MatrixXd V;                                      // caller-owned output buffer
//   for (each frame) d.pose(motors, V);                     // per-frame work, one motor per control
//
// bind(const Mesh& rest, const Rig& rig, const Options& options) -> Deformer
//   Does everything that does not depend on the pose: validation of the mesh and the rig (handles:
//   check_handles below; skeleton: check_skeleton), weights (harmonic fields, basis functions), matrix
//   factorizations, and the rest-pose binding of key motors (CGA paper §III.A: when the rest pose has
//   key motors R_j^0 that are not the identity, each vertex is stored as p'_i = ~M_i^0 p_i M_i^0,
//   M_i^0 the rest motor field, so that posing with the rest motors reproduces the rest mesh). Each
//   deformer reads the parts of the Rig it documents and throws when one it needs is missing. Throws
//   spinmotor::Error naming the bad element (handle name, vertex, bone, connected component). The
//   returned object owns copies of everything it needs; the mesh and rig may be destroyed afterwards.
//   Options are plain structs whose member initialisers are the defaults (the one place they live);
//   their enum values have one name table each (option_names.hpp).
//
// controls() -> const std::vector<Control>&
//   What a pose gives motors for, in pose order: the name of each control and the rest point its
//   motor carries (where an interactive tool draws its gizmo).
//
// pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out)
//   One unit motor per control, relative to the rest pose (all identities reproduce the rest mesh).
//   Writes the n×3 deformed positions into V_out, which is resized only if its size is wrong (so from
//   the second frame on pose() allocates nothing). Parallel over vertices (OpenMP, from
//   parallel::kMotorBlend vertices on, core/parallel.hpp). Non-const because a deformer may keep
//   per-frame scratch (prepared motor logarithms, ARAP's warm start, the last IK solve): one pose() at
//   a time per object. Throws Error on a wrong motor count or a non-finite motor.
//
// Motor conventions are those of spinmotor::ga: a motor M moves a point by M p ~M, blends are
// exp(Σ w_j log M_j) (Blend::Log) unless stated. Texture coordinates are never touched: the deformed
// mesh is the rest mesh with V replaced.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <concepts>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "spinmotor/core/option_names.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

/// A named set of vertices that one motor (or one boundary condition) acts on.
struct Handle {
  std::string name;          ///< used in error messages ("handle 'tip'")
  Eigen::VectorXi vertices;  ///< distinct vertex indices in [0, n)
};

/// Checks that every handle is non-empty, has indices in [0, n) without repeats, and that no vertex
/// belongs to two handles. Throws Error naming the handle (and the other handle and the vertex for a
/// shared vertex). `who` prefixes the message (e.g. "SurfaceHarmonicDeformer").
void check_handles(std::span<const Handle> handles, Eigen::Index n, const char* who);

/// What the controls of a lattice or cage deformer carry: points (the classic deformer, positions
/// blended linearly) or motors (blended by ga::Blend, CGA paper §V–§VI).
enum class ControlMode { Position, Motor };
inline constexpr OptionNames<ControlMode, 2> kControlModeNames{
    "mode", {{{ControlMode::Position, "position"}, {ControlMode::Motor, "motor"}}}};
constexpr const auto& option_names(ControlMode) { return kControlModeNames; }

/// A bone of a skeleton (skin deformer, rigs): a parent, a rest segment and a rest frame.
struct Bone {
  std::string name;
  int parent = -1;                ///< index of the parent bone, −1 for a root
  Eigen::Vector3d head{0, 0, 0};  ///< rest segment (bone_harmonic_weights, the control anchor)
  Eigen::Vector3d tail{0, 0, 1};
  ga::Mot rest{1, 0, 0, 0, 0, 0, 0, 0};  ///< rest frame F_j^0 (unit motor)
};

/// Throws Error naming the bone for an empty or repeated name, a parent out of range or equal to
/// itself, a cycle of parents, head == tail, or a rest frame that is not a finite unit motor.
void check_skeleton(std::span<const Bone> bones);

/// A joint chain solved by FABRIK toward a target (spline IK, CGA paper §III.C).
struct IkChain {
  Eigen::MatrixXd chain{};               ///< k×3 rest joint positions, k ≥ 2, root first
  Eigen::Vector3d target{0, 0, 0};       ///< rest target; the control "ik.target" moves it
  double tolerance = 1e-4;               ///< FABRIK: end-joint distance to the target
  int iterations = 50;                   ///< FABRIK: at most this many forward + backward passes
  std::optional<ga::Rot> orientation{};  ///< optional end-bone orientation relative to rest
};

/// What a deformer binds to besides the rest mesh and its options. Each deformer reads the parts it
/// documents: handles (surface harmonic and ARAP: one control each; spline and spline IK: {from, to}),
/// cage (cage deformer), skeleton + weights (skin), ik (spline IK). The FFD lattice is an option.
struct Rig {
  std::vector<Handle> handles{};
  std::optional<Mesh> cage{};
  std::vector<Bone> skeleton{};
  Eigen::SparseMatrix<double> weights{};  ///< n×B skin weights (rows: vertices), used with skeleton
  std::optional<IkChain> ik{};
};

/// One control of a deformer: the name a pose gives its motor and the rest point the motor carries
/// (a handle's centroid, a lattice point, a cage vertex, a bone head, a spline key's place between the
/// end handles, the IK target).
struct Control {
  std::string name{};
  Eigen::Vector3d anchor{0, 0, 0};
  bool operator==(const Control&) const = default;
};

/// The deformer shape (see the top of this header).
template <class D>
concept Deformer = std::move_constructible<D> &&
    requires(D& d, const D& cd, const Mesh& rest, const Rig& rig, const typename D::Options& options,
             std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out) {
  { D::bind(rest, rig, options) } -> std::same_as<D>;
  { cd.controls() } -> std::same_as<const std::vector<Control>&>;
  { cd.vertices() } -> std::convertible_to<Eigen::Index>;
  { d.pose(motors, V_out) } -> std::same_as<void>;
};

/// Controls named after handles, anchored at their centroids in V.
std::vector<Control> handle_controls(const Eigen::MatrixXd& V, std::span<const Handle> handles);

/// Throws Error "<who>: expected <k> motors (one per control), got <m>" unless the counts agree, and
/// "<who>: motor j (control '<name>') is not a finite unit motor" for a bad one.
void check_motors(std::span<const ga::Mot> motors, std::span<const Control> controls, const char* who);

/// Mean of the rows of V (n×3) listed by the handle (its gizmo anchor, an IK tip); zero for an empty handle.
inline Eigen::Vector3d handle_centroid(const Eigen::MatrixXd& V, const Handle& h) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (Eigen::Index k = 0; k < h.vertices.size(); ++k) c += V.row(h.vertices[k]).transpose();
  return h.vertices.size() > 0 ? Eigen::Vector3d(c / static_cast<double>(h.vertices.size())) : c;
}

}  // namespace spinmotor
