#pragma once
// Deformer types of scene files, keyed by the `deformer.type` string.
//
// A scene deformer wraps a library deformer (deform/deformer.hpp contract): its bind function reads
// the scene's `deformer` block (and handles, `ik`, ...), does all precomputation and returns an object
// whose pose() is the per-frame work. Adding a type (ffd, cage, arap, skin) is:
//   1. a definition "deformer_<type>" for its keys in scene.schema.json (listed in definitions/deformer),
//   2. a file scene/src/deformer_<type>.cpp defining
//        std::unique_ptr<SceneDeformer> bind_<type>(const Scene& scene);
//      (throw scene.error("/deformer/<key>", "...") for a bad value the schema cannot catch),
//   3. one line in the table of scene/src/deformer_registry.cpp (and its declaration above it).
// Sources in scene/src/ are globbed (re-run cmake after adding one).
#include <Eigen/Core>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "spinmotor/scene/scene.hpp"

namespace spinmotor::scene {

class SceneDeformer {
public:
  virtual ~SceneDeformer() = default;
  /// The names a pose may give motors for (handles, keys, control points). A pose entry with any other
  /// name is an error naming its JSON path.
  virtual std::vector<std::string> controls() const = 0;
  /// Per-frame work: V_out (n×3) from the frame's motors.
  virtual void pose(const Pose& pose, Eigen::MatrixXd& V_out) = 0;
  /// Per-frame figures merged into the metrics JSON, at least "max_handle_error" (max distance of a
  /// handle vertex from where its own motor takes it; null when the deformer has no such notion).
  virtual nlohmann::json report(const Pose& pose, const Eigen::MatrixXd& V_out) const = 0;
  /// Figures of bind() merged into the metrics JSON (e.g. the IK solve and fit). Default: none.
  virtual nlohmann::json bind_report() const { return nlohmann::json::object(); }
  /// The rest point a control moves: the point its motor carries, where an interactive tool draws
  /// its gizmo (a lattice point, a cage vertex, a bone head, a spline key's place between the end
  /// handles, the IK target). Nothing when the control is a handle (its centroid is the natural
  /// anchor and the caller has the vertices) or unknown. Default: nothing.
  virtual std::optional<Eigen::Vector3d> control_anchor(const std::string& /*control*/) const {
    return std::nullopt;
  }
};

using BindFunction = std::unique_ptr<SceneDeformer> (*)(const Scene& scene);

struct DeformerType {
  const char* name;  ///< the `deformer.type` value
  BindFunction bind;
};

/// All deformer types of this build.
std::span<const DeformerType> deformer_types();

/// Binds the scene's deformer: Error at /deformer/type if the type is not available in this build.
std::unique_ptr<SceneDeformer> bind_deformer(const Scene& scene);

/// Max distance of the vertices of `handles[j]` from motors[j] applied to their rest positions
/// (a helper for report()).
double max_handle_error(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V, std::span<const Handle> handles,
                        std::span<const ga::Mot> motors);

}  // namespace spinmotor::scene
