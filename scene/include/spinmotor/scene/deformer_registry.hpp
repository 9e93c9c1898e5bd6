#pragma once
// Deformer types of scene files, keyed by the `deformer.type` string.
//
// A scene deformer is a library deformer behind the one deformer shape (deform/deformer.hpp: bind,
// controls, pose), held as an AnyDeformer, plus what the scene reports about it. Each type's bind
// function reads the scene's `deformer` block (option values through their name tables, defaults from
// the library's Options), builds the Rig (handles, cage, skeleton, ik) and binds. Adding a type is:
//   1. a definition "deformer_<type>" for its keys in scene.schema.json (listed in definitions/deformer),
//   2. a file scene/src/deformer_<type>.cpp defining
//        std::unique_ptr<SceneDeformer> bind_<type>(const Scene& scene);
//      (throw scene.error("/deformer/<key>", "...") for a bad value the schema cannot catch),
//   3. one line in the table of scene/src/deformer_registry.cpp (and its declaration above it).
// Sources in scene/src/ are globbed (re-run cmake after adding one).
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/any_deformer.hpp"
#include "spinmotor/scene/scene.hpp"

namespace spinmotor::scene {

/// A bound deformer of a scene: the library deformer and the scene's view of it.
class SceneDeformer {
 public:
  /// Per-frame figures merged into the metrics JSON (e.g. "arap", "ik"); gets the frame's motors.
  using Report =
      std::function<nlohmann::json(const AnyDeformer&, std::span<const ga::Mot>, const Eigen::MatrixXd&)>;
  /// The motors of a pose, in control order. Default: by control name, identity when absent.
  using Motors = std::function<void(const Pose&, std::vector<ga::Mot>&)>;

  SceneDeformer(const Scene& scene, AnyDeformer deformer, Report report = {}, nlohmann::json bind_report = {},
                Motors motors = {});

  const AnyDeformer& deformer() const { return d_; }
  AnyDeformer& deformer() { return d_; }
  /// The controls (name + rest anchor) in pose order.
  const std::vector<Control>& controls() const { return d_.controls(); }
  /// The names a pose may give motors for. A pose entry with any other name is an error naming its
  /// JSON path (run.cpp).
  std::vector<std::string> control_names() const;
  /// The rest point a control moves (where an interactive tool draws its gizmo), or nothing for an
  /// unknown name.
  std::optional<Eigen::Vector3d> control_anchor(const std::string& control) const;
  /// Per-frame work: V_out (n×3) from the frame's motors. Errors are prefixed with the scene's name.
  void pose(const Pose& pose, Eigen::MatrixXd& V_out);
  /// The motors pose() gives the deformer for `pose`, in control order (e.g. a skin's bone motions
  /// after inheritance, and for a rig the animation at pose.time with the edits on top).
  void motors(const Pose& pose, std::vector<ga::Mot>& out) const;
  /// The skin's bones and weights (skin deformers only, else null).
  /// A skin deformer's rig (deformer.hpp: skeleton and weights, as it was bound with): the pins of the
  /// pose-keeping cleanup come from its weights (snap "pins": "weights"; the viewer's rig cleanup), and
  /// the viewer draws its bones. Null for other deformers.
  const Rig* skin() const { return skin_.get(); }
  /// The same, shared (a worker thread that binds the rig cleanup keeps it).
  std::shared_ptr<const Rig> shared_skin() const { return skin_; }
  void set_skin(std::shared_ptr<const Rig> skin) { skin_ = std::move(skin); }
  /// Per-frame figures merged into the metrics JSON, at least "max_handle_error" (max distance of a
  /// handle vertex from where its own motor takes it; null when the deformer has no such notion).
  nlohmann::json report(const Pose& pose, const Eigen::MatrixXd& V_out) const;
  /// Figures of bind() merged into the metrics JSON (e.g. the IK solve and fit, ARAP's factorization).
  nlohmann::json bind_report() const;

 private:
  const Scene& scene_;
  AnyDeformer d_;
  Report report_;
  nlohmann::json bind_report_;
  Motors motors_of_;
  std::vector<ga::Mot> motors_;
  std::shared_ptr<const Rig> skin_;
};

/// The pins of the pose-keeping cleanup of a skinned pose (deform/rig_pins.hpp): the vertices whose
/// largest weight is ≥ threshold and that lie farther than `margin` from every blended vertex
/// (margin < 0: per bone, default_pin_margins). Increasing. Throws Error when there is none.
std::vector<int> skin_pins(const Mesh& rest, const Rig& skin, double threshold, double margin);

/// The value of the option `key` of the scene's deformer block, parsed by its name table, or
/// `fallback` (the library Options' default) when the key is absent. An unknown name throws the
/// scene's error at /deformer/<key>.
template <class E>
E deformer_option(const Scene& s, const char* key, E fallback) {
  if (!s.deformer.contains(key)) return fallback;
  try {
    return parse_option<E>(s.deformer[key].get<std::string>());
  } catch (const Error& e) {
    throw s.error(std::string("/deformer/") + key, e.what());
  }
}

using BindFunction = std::unique_ptr<SceneDeformer> (*)(const Scene& scene);

struct DeformerType {
  const char* name;  ///< the `deformer.type` value
  BindFunction bind;
};

/// All deformer types of this build.
std::span<const DeformerType> deformer_types();

/// Binds the scene's deformer: Error at /deformer/type if the type is not available in this build.
std::unique_ptr<SceneDeformer> bind_deformer(const Scene& scene);

/// Max distance of the vertices of `handles[j]` from motors[j] applied to their rest positions.
double max_handle_error(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V,
                        std::span<const Handle> handles, std::span<const ga::Mot> motors);

}  // namespace spinmotor::scene
