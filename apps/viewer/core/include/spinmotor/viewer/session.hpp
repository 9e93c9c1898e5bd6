#pragma once
// The viewer's document: a scene file (docs/scene.md), a glTF rig or a bare mesh, its bound deformer, the
// current pose with undo/redo, and saving. Window-free (the headless screenshot mode and the tests drive
// it).
//
// A glTF character (.gltf/.glb, or a scene with a `rig` block) is a skin scene whose working pose has a
// time: set_time() poses the animation (the pose's motors are then edits on top of it, docs/scene.md
// `rig`), set_animation() picks another one; the time is playback state, kept by undo/redo.
//
//   Session s = Session::open("scene.json");    // load, validate, bind the deformer once
//   s.set_motor("tip", m);  s.commit_pose();    // an edit (one undo step per commit)
//   const Eigen::MatrixXd& V = s.posed();       // the deformer's pose() for the current pose
//   s.save_scene("edited.json");                // same JSON, the pose replaced by the current one
#include <Eigen/Core>
#include <algorithm>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "spinmotor/scene/deformer_registry.hpp"
#include "spinmotor/scene/scene.hpp"
#include "spinmotor/viewer/undo_stack.hpp"

namespace spinmotor::viewer {

/// A motor as scene JSON: {"quaternion": [w, x, y, z], "translate": [tx, ty, tz]} (rotation about the
/// origin, then translation; docs/scene.md `pose`).
nlohmann::json motor_to_json(const ga::Mot& m);

/// A bone of a skin deformer where the working pose puts it (Session::posed_bones).
struct PosedBone {
  std::string name;
  int parent = -1;
  Eigen::Vector3d head, tail;
};

/// References returned by scene(), rest(), controls() and posed() stay valid until the next call of
/// add_handle, remove_handle, set_deformer or set_animation, which rebuild the scene (ASan caught a test
/// holding one).
class Session {
 public:
  /// A ".json" path is a scene (validated, deformer bound); ".gltf"/".glb" a rig scene
  /// {"rig": {"gltf": FILE}, "deformer": {"type": "skin"}} at the start of its first animation (the rest
  /// pose when it has none); anything else a mesh shown without deformer. Throws Error naming the file
  /// and what is wrong.
  static Session open(const std::filesystem::path& path);
  Session(Session&&) noexcept;
  Session& operator=(Session&&) noexcept;
  ~Session();

  const scene::Scene& scene() const { return *scene_; }
  /// Every handle's vertices (sorted): the pins of the pose-keeping cleanup ("keep the pose").
  std::vector<int> handle_vertices() const {
    std::vector<int> v;
    for (const Handle& h : scene_->handles)
      v.insert(v.end(), h.vertices.data(), h.vertices.data() + h.vertices.size());
    std::sort(v.begin(), v.end());
    return v;
  }
  const Mesh& rest() const { return scene_->mesh; }
  bool has_deformer() const { return deformer_ != nullptr; }
  double bind_ms() const { return bind_ms_; }
  /// The names the pose may move (handles, keys, control points); empty without deformer.
  const std::vector<std::string>& controls() const { return controls_; }
  /// Rest vertices of the handle called `name` (empty if it is not a handle, e.g. an FFD control).
  std::vector<int> handle_vertices(const std::string& name) const;
  /// The rest point control `name` moves, where its gizmo sits: the deformer's anchor (lattice point,
  /// cage vertex, bone head, spline key, IK target; SceneDeformer::control_anchor) or else the
  /// centroid of the handle's rest vertices. Nothing for a name that is neither.
  std::optional<Eigen::Vector3d> control_anchor(const std::string& name) const;
  /// control_anchor moved by the control's motor in the working pose.
  std::optional<Eigen::Vector3d> posed_anchor(const std::string& name) const;

  /// The scene's `deformer` block (null without deformer) and `ik` block (null when there is none).
  nlohmann::json deformer_block() const;
  nlohmann::json ik_block() const;
  /// Replaces the deformer block, and the `ik` block (null removes it), validates the document and
  /// rebinds: the viewer's deformer panel. Pose entries of controls the new deformer does not have
  /// are dropped; the undo history restarts. Throws Error (naming the JSON path) for a bad block; the
  /// session is then unchanged.
  void set_deformer(const nlohmann::json& deformer, const nlohmann::json& ik = nullptr);

  /// Adds a handle {"name", "select": {"vertices": [...]}} to the scene document, re-validates it and
  /// rebinds the deformer (a bare mesh gets a surface-harmonic deformer). The pose is kept; the undo
  /// history restarts (its poses may name handles that no longer exist). Throws Error (naming the JSON
  /// path) for an empty or taken name, no vertices, or vertices another handle owns; the session is
  /// then unchanged.
  void add_handle(const std::string& name, const std::vector<int>& vertices);
  /// Removes a handle and its pose entry, then rebinds as add_handle. Error if there is no such handle.
  void remove_handle(const std::string& name);
  /// Renames a handle everywhere the document names it (the handle, its pose entry, the spline
  /// deformer's `from`/`to`), then rebinds as add_handle. Error for an unknown handle or an empty or
  /// taken new name; the session is then unchanged.
  void rename_handle(const std::string& name, const std::string& new_name);

  // ---- rigs (scenes with a `rig` block) ----
  bool has_rig() const { return scene_->rig.has_value(); }
  /// The animation the time poses (−1: the file has none, or no rig).
  int animation() const { return has_rig() ? scene_->rig->animation : -1; }
  std::vector<std::string> animation_names() const;
  /// First and last key time of the current animation ({0, 0} without one).
  std::pair<double, double> animation_range() const;
  /// The working pose's time (nothing: the rest pose).
  std::optional<double> time() const { return pose_.time; }
  /// Poses the animation at t (nothing: the rest pose). Error without a rig or animation, or t not finite.
  void set_time(std::optional<double> t);
  /// Switches the animation (rebinds as set_deformer; the time and the pose edits are kept).
  void set_animation(int index);

  /// The skin's bones where the working pose puts them: K_j = F_j ~F_j^0 applied to the rest head and tail
  /// (a rig: the animation at the time with the edits on top). Empty unless the deformer is a skin.
  std::vector<PosedBone> posed_bones();
  /// The pins of the pose-keeping cleanup ("keep the pose") of a scene with handles: every handle's
  /// vertices (empty without handles).
  std::vector<int> cleanup_pins();
  /// For a skin scene without handles, the skin the rig cleanup binds to (scene/rig_cleanup.hpp: pins and
  /// attraction from its weights, the rig defaults); null otherwise.
  std::shared_ptr<const spinmotor::Rig> cleanup_skin() const;
  /// The motor a gizmo drag of `name` starts from: its pose entry, or for a skin bone without one the
  /// motion it inherits from its nearest posed ancestor (what pose() applies to it).
  ga::Mot drag_start_motor(const std::string& name) const;

  const scene::Pose& pose() const { return pose_; }
  ga::Mot motor(const std::string& name) const { return pose_.motor(name); }
  /// Sets one motor of the working pose (during a drag: no undo step yet). Error for an unknown control.
  void set_motor(const std::string& name, const ga::Mot& m);
  /// Records the working pose as one undo step (call when a drag ends).
  void commit_pose();
  bool undo();  ///< back to the previous committed pose
  bool redo();
  bool can_undo() const { return history_.can_undo(); }
  bool can_redo() const { return history_.can_redo(); }

  /// The deformer's positions for the working pose (recomputed when it changed; rest without deformer).
  const Eigen::MatrixXd& posed();
  double pose_ms() const { return pose_ms_; }  ///< time of the last pose()

  /// The scene document with `pose` set to the working pose (and `frames` removed).
  nlohmann::json scene_document() const;
  /// Writes scene_document() atomically. Relative paths inside stay relative to the original scene's
  /// directory, so the file should go next to it (or the mesh path be absolute).
  void save_scene(const std::filesystem::path& path) const;

 private:
  Session() = default;
  void rebind(nlohmann::json doc);
  // On the heap: a bound scene deformer may keep a reference to its Scene, which must not move.
  std::unique_ptr<scene::Scene> scene_ = std::make_unique<scene::Scene>();
  std::unique_ptr<scene::SceneDeformer> deformer_;
  std::vector<std::string> controls_;
  scene::Pose pose_;
  UndoStack<scene::Pose> history_{scene::Pose{}};
  Eigen::MatrixXd V_;
  bool dirty_ = true;
  double bind_ms_ = 0, pose_ms_ = 0;
};

}  // namespace spinmotor::viewer
