#pragma once
// Scene files (docs/scene.md): loading, JSON Schema validation and the parsed scene.
//
// load_scene(file) reads the JSON, validates it against the shipped schema (scene.schema.json,
// embedded in the binary: scene_schema()), then builds what every deformer needs: the rest mesh (from
// a file relative to the scene file, a generator, or the surface of a glTF `rig`), the handles (vertex sets
// from their `select`), the poses (one per frame, motors by control name), the `ik`, `snap` and `output`
// blocks. The `deformer` block is kept as JSON: each deformer type reads its own keys when it binds
// (deformer_registry.hpp).
//
// Every problem throws spinmotor::Error (BadInput) whose message starts with the scene file and the
// JSON Pointer of the bad value, e.g.
//   scene.json: /handles/1/select/box/min: expected at least 3 items, got 2
//   scene.json: /handles/1: handle 'tip' shares vertex 17 with handle 'base' (/handles/0)
//   scene.json: /pose/tip/matrix: not a rigid motion (...)
// Nothing is written by loading.
#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/deformer.hpp"
#include "spinmotor/deform/gltf_skin.hpp"
#include "spinmotor/deform/rig_pins.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace spinmotor::scene {

/// The text of scene.schema.json (embedded at build time).
const char* scene_schema_text();
/// The parsed schema.
const nlohmann::json& scene_schema();

/// One frame's motors by control name (handle, key or control point); missing names are identities.
struct Pose {
  std::map<std::string, ga::Mot> motors;
  std::string
      path;  ///< JSON Pointer of the pose object ("/pose", "/frames/2"); entries are path + "/" + name
  /// Scenes with a `rig`: the animation time of this frame in seconds (nothing: the rest pose). The
  /// motors are then edits on top of the animation (docs/scene.md `rig`).
  std::optional<double> time;
  /// The motor of `name`, or the identity.
  ga::Mot motor(const std::string& name) const;
  /// JSON Pointer of the entry `name`.
  std::string entry_path(const std::string& name) const;
};

struct IkSpec {
  Eigen::MatrixXd chain;  ///< k×3 rest joint positions
  Eigen::Vector3d target;
  double tolerance = 1e-4;
  int iterations = 50;
  std::optional<ga::Rot> orientation;  ///< end-bone orientation relative to rest
};

struct SnapSpec {
  bool enabled = false;
  /// "mode": free (§7.2), shape (extrusion toward the edit's curvature, Le Folgoc 2019) or pinned (the
  /// pose-keeping cleanup); default free, pinned when "pins" is given.
  SnapMode mode = SnapMode::Free;
  std::vector<int> pin_handles;          ///< pinned mode: indices of the handles whose vertices are pinned
  CleanupKeep keep = CleanupKeep::Auto;  ///< pinned mode: the measure kept
  int iterations = PinnedCleanupOptions{}.max_iterations;  ///< pinned mode: at most this many steps
  /// pinned mode: γ of the pose attraction; unset: 0 with handle pins, the rig default
  /// (scene/rig_cleanup.hpp) with "pins": "weights", where the attraction follows the weights.
  std::optional<double> pose_weight;
  /// pinned mode, "pins": "weights": the rigid parts of the skin deformer's weights (rig_pins.hpp)
  /// instead of handles, with pin_threshold and pin_margin (< 0: default_pin_margins).
  bool pin_weights = false;
  double pin_threshold = kRigidWeight;
  double pin_margin = -1;
  double tradeoff = 1.0;       ///< spin mode: similarities (0) … integrable spin transformation (1)
  int smooth_rho = 0;          ///< spin mode: Laplacian smoothing passes of the fitted ρ
  int steps = 4;               ///< shape mode: extrusion steps
  double area_constraint = 0;  ///< shape mode: area soft-constraint ε (0 = off)
};

/// The `rig` block: a glTF character (mesh/gltf.hpp) whose surface is the scene's mesh, posed by the skin
/// deformer from its animation.
struct RigSpec {
  std::filesystem::path file;           ///< the glTF file (resolved against the scene's directory)
  std::shared_ptr<const GltfRig> gltf;  ///< as read_gltf returned it (shared by copies of the scene)
  std::shared_ptr<const RigSkin> skin;  ///< its rest surface (the scene's mesh), bones and bind matrices
  int animation = -1;         ///< the animation index the frames sample, −1 when the file has none
  std::vector<double> times;  ///< one per frame (empty: the rest pose)
};

struct OutputSpec {
  std::optional<std::filesystem::path> mesh, metrics, colors;  ///< as written in the file (relative or not)
};

struct Scene {
  std::filesystem::path file;  ///< the scene file ("" when parsed from memory)
  std::filesystem::path dir;   ///< base directory of relative paths
  nlohmann::json doc;          ///< the validated document
  Mesh mesh;                   ///< rest mesh
  std::string mesh_source;     ///< file path or generator name
  std::vector<Handle> handles;
  std::string deformer_type;
  nlohmann::json deformer;   ///< the /deformer block
  std::vector<Pose> frames;  ///< one for `pose` (or none given), several for `frames` (or `rig.frames`)
  bool animated = false;     ///< `frames` (or `rig.frames`) was given: outputs get frame numbers
  int first_frame = 0;       ///< the number of frames[0] in output names and metrics (`rig.frames` [A, B]: A)
  std::optional<RigSpec> rig;
  std::optional<IkSpec> ik;
  SnapSpec snap;
  OutputSpec output;

  /// "scene.json" (the file name) for messages.
  std::string name() const;
  /// Error "<name>: <pointer>: <message>".
  Error error(const std::string& pointer, const std::string& message) const;
  /// The handle called `name`, or throw error(pointer, "no handle named ...").
  const Handle& handle(const std::string& name, const std::string& pointer) const;
  /// Index of the handle called `name`, or −1.
  int handle_index(const std::string& name) const;
};

/// Reads, validates and builds a scene file. Throws Error as described above.
Scene load_scene(const std::filesystem::path& file);

/// Same from an in-memory document; relative paths are relative to `dir`, messages name `name`.
Scene parse_scene(const nlohmann::json& doc, const std::filesystem::path& dir,
                  const std::string& name = "scene");

/// A motor from its JSON form (docs/scene.md `pose`): rotate/translate, matrix (rigid, row-major 4×4) or
/// quaternion (normalized) + translate. Throws Error naming `pointer` (and the sub-key) when the
/// matrix is not rigid or an axis/quaternion is zero.
ga::Mot parse_motor(const nlohmann::json& j, const std::string& pointer,
                    const std::string& scene_name = "scene");

}  // namespace spinmotor::scene
