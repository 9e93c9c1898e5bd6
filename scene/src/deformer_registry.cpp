#include "spinmotor/scene/deformer_registry.hpp"

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/rig_pins.hpp"

namespace spinmotor::scene {

// One bind function per deformer type, each in its own scene/src/deformer_<type>.cpp.
std::unique_ptr<SceneDeformer> bind_surface_harmonic(const Scene& scene);
std::unique_ptr<SceneDeformer> bind_spline(const Scene& scene);
std::unique_ptr<SceneDeformer> bind_arap(const Scene& scene);
std::unique_ptr<SceneDeformer> bind_ffd(const Scene& scene);
std::unique_ptr<SceneDeformer> bind_cage(const Scene& scene);
std::unique_ptr<SceneDeformer> bind_skin(const Scene& scene);

namespace {
const DeformerType kTypes[] = {
    {"surface-harmonic", &bind_surface_harmonic},
    {"spline", &bind_spline},
    {"arap", &bind_arap},
    {"ffd", &bind_ffd},
    {"cage", &bind_cage},
    {"skin", &bind_skin},
};
}  // namespace

std::span<const DeformerType> deformer_types() { return kTypes; }

std::unique_ptr<SceneDeformer> bind_deformer(const Scene& scene) {
  std::string available;
  for (const DeformerType& t : deformer_types()) {
    if (scene.deformer_type == t.name) return t.bind(scene);
    available += (available.empty() ? "" : ", ") + std::string(t.name);
  }
  throw scene.error("/deformer/type", "deformer type '" + scene.deformer_type +
                                          "' is not available in this build (available: " + available + ")");
}

SceneDeformer::SceneDeformer(const Scene& scene, AnyDeformer deformer, Report report,
                             nlohmann::json bind_report, Motors motors)
    : scene_(scene),
      d_(std::move(deformer)),
      report_(std::move(report)),
      bind_report_(bind_report.is_null() ? nlohmann::json::object() : std::move(bind_report)),
      motors_of_(std::move(motors)) {
  motors_.assign(d_.controls().size(), ga::Mot(1, 0, 0, 0, 0, 0, 0, 0));
}

std::vector<std::string> SceneDeformer::control_names() const {
  std::vector<std::string> names;
  for (const Control& c : controls()) names.push_back(c.name);
  return names;
}

std::optional<Eigen::Vector3d> SceneDeformer::control_anchor(const std::string& control) const {
  for (const Control& c : controls())
    if (c.name == control) return c.anchor;
  return std::nullopt;
}

void SceneDeformer::motors(const Pose& pose, std::vector<ga::Mot>& out) const {
  out.resize(controls().size());
  if (motors_of_) {
    motors_of_(pose, out);
  } else {
    const auto& c = controls();
    for (std::size_t j = 0; j < c.size(); ++j) out[j] = pose.motor(c[j].name);
  }
}

void SceneDeformer::pose(const Pose& pose, Eigen::MatrixXd& V_out) {
  try {
    motors(pose, motors_);
    d_.pose(motors_, V_out);
  } catch (const Error& e) {
    const std::string msg = e.what();
    if (msg.rfind(scene_.name() + ":", 0) == 0) throw;
    throw Error(scene_.name() + ": " + msg, e.kind());
  }
}

nlohmann::json SceneDeformer::report(const Pose& pose, const Eigen::MatrixXd& V_out) const {
  nlohmann::json r = nlohmann::json::object();
  if (report_) {
    std::vector<ga::Mot> m;
    motors(pose, m);
    r = report_(d_, m, V_out);
  }
  if (!r.contains("max_handle_error")) r["max_handle_error"] = nullptr;
  return r;
}

nlohmann::json SceneDeformer::bind_report() const { return bind_report_; }

std::vector<int> skin_pins(const Mesh& rest, const Rig& skin, double threshold, double margin) {
  const Eigen::MatrixXd W(skin.weights);
  const Eigen::VectorXd margins = margin >= 0 ? Eigen::VectorXd::Constant(W.cols(), margin)
                                              : default_pin_margins(rest.V, W, skin.skeleton, threshold);
  const Eigen::VectorXi pins = pins_from_weights(rest.V, W, threshold, margins);
  if (pins.size() == 0)
    throw Error("no vertex has a bone weight ≥ " + std::to_string(threshold) +
                " far enough from a blended vertex (lower pin_threshold or pin_margin)");
  return {pins.data(), pins.data() + pins.size()};
}

double max_handle_error(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V,
                        std::span<const Handle> handles, std::span<const ga::Mot> motors) {
  double e = 0.0;
  for (std::size_t j = 0; j < handles.size(); ++j)
    for (Eigen::Index k = 0; k < handles[j].vertices.size(); ++k) {
      const int v = handles[j].vertices[k];
      e = std::max(e, (V.row(v).transpose() - ga::transform(motors[j], V_rest.row(v).transpose())).norm());
    }
  return e;
}

}  // namespace spinmotor::scene
