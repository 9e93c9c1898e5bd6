// Scene deformer "cage": CageDeformer (CGA paper §VI), one motor per cage vertex, named "cage[j]".
//   {"type": "cage", "cage": "cage.obj" | {"box": {"margin": m}}, "coordinates": "harmonic" | "mean-value", "grid": g,
//    "mode": "motor" | "position", "blend": "log" | "pivot-log" | "dlb"}
// Defaults: harmonic, grid 64, motor, log. The cage path is relative to the scene file. A cage that is not
// closed and consistently oriented, or a mesh vertex outside it, is an error naming it (exit 2).
// Metrics gain "cage": vertices, coordinates, the interpolation bound of harmonic coordinates.
#include <unordered_map>

#include "spinmotor/deform/cage_deformer.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/scene/deformer_registry.hpp"

namespace spinmotor::scene {

namespace {

class CageScene final : public SceneDeformer {
public:
  CageScene(const Scene& s, CageDeformer d) : scene_(s), d_(std::move(d)) {
    for (Eigen::Index j = 0; j < d_.controls(); ++j) {
      index_["cage[" + std::to_string(j) + "]"] = names_.size();
      names_.push_back("cage[" + std::to_string(j) + "]");
    }
    motors_.assign(names_.size(), ga::Mot(1, 0, 0, 0, 0, 0, 0, 0));
  }
  std::vector<std::string> controls() const override { return names_; }
  std::optional<Eigen::Vector3d> control_anchor(const std::string& name) const override {
    const auto it = index_.find(name);
    if (it == index_.end()) return std::nullopt;
    return d_.cage_points().row(static_cast<Eigen::Index>(it->second)).transpose();
  }
  void pose(const Pose& pose, Eigen::MatrixXd& V_out) override {
    std::fill(motors_.begin(), motors_.end(), ga::Mot(1, 0, 0, 0, 0, 0, 0, 0));
    for (const auto& [name, m] : pose.motors) motors_[index_.at(name)] = m;
    try {
      d_.pose(motors_, V_out);
    } catch (const Error& e) {
      throw Error(scene_.name() + ": " + e.what(), e.kind());
    }
  }
  nlohmann::json report(const Pose&, const Eigen::MatrixXd&) const override {
    const bool hc = d_.options().coordinates == CageDeformer::Coordinates::Harmonic;
    nlohmann::json c = {{"vertices", d_.controls()}, {"coordinates", hc ? "harmonic" : "mean-value"}};
    if (hc) c["grid"] = d_.options().grid, c["interpolation_bound"] = d_.interpolation_bound();
    return {{"max_handle_error", nullptr}, {"cage", c}};
  }

private:
  const Scene& scene_;
  CageDeformer d_;
  std::vector<std::string> names_;
  std::unordered_map<std::string, std::size_t> index_;
  std::vector<ga::Mot> motors_;
};

/// `"cage": {"box": {"margin": m}}`: the axis-aligned bounding box of V grown by m times its
/// diagonal on every side, as a closed outward-oriented triangle cage (8 vertices, 12 faces).
Mesh box_cage(const Eigen::MatrixXd& V, double margin) {
  const Eigen::RowVector3d lo0 = V.colwise().minCoeff(), hi0 = V.colwise().maxCoeff();
  const double pad = margin * (hi0 - lo0).norm();
  const Eigen::RowVector3d lo = lo0.array() - pad, hi = hi0.array() + pad;
  Mesh c;
  c.V.resize(8, 3);
  for (int i = 0; i < 8; ++i)  // corner i: bit 0 x, bit 1 y, bit 2 z (0 = min, 1 = max)
    c.V.row(i) << ((i & 1) ? hi : lo).x(), ((i & 2) ? hi : lo).y(), ((i & 4) ? hi : lo).z();
  c.F.resize(12, 3);
  c.F << 0, 2, 1, 1, 2, 3,  // z = min, normal −z
      4, 5, 6, 5, 7, 6,     // z = max, +z
      0, 1, 4, 1, 5, 4,     // y = min, −y
      2, 6, 3, 3, 6, 7,     // y = max, +y
      0, 4, 2, 2, 4, 6,     // x = min, −x
      1, 3, 5, 3, 7, 5;     // x = max, +x
  return c;
}

}  // namespace

std::unique_ptr<SceneDeformer> bind_cage(const Scene& s) {
  const nlohmann::json& b = s.deformer;
  CageDeformer::Options o;
  o.coordinates = b.value("coordinates", "harmonic") == "mean-value" ? CageDeformer::Coordinates::MeanValue
                                                                      : CageDeformer::Coordinates::Harmonic;
  o.grid = b.value("grid", 64);
  o.mode = b.value("mode", "motor") == "position" ? CageDeformer::Mode::Position : CageDeformer::Mode::Motor;
  const std::string blend = b.value("blend", "log");
  o.blend = blend == "pivot-log" ? ga::Blend::PivotLog : blend == "dlb" ? ga::Blend::Linear : ga::Blend::Log;
  Mesh cage;
  std::string cage_name = "bounding-box cage";
  if (b["cage"].is_object()) {
    cage = box_cage(s.mesh.V, b["cage"]["box"].value("margin", 0.05));
  } else {
    const std::filesystem::path path = s.dir / b["cage"].get<std::string>();
    cage_name = path.string();
    try {
      cage = read_mesh(path);
    } catch (const Error& e) {
      throw s.error("/deformer/cage", e.what());
    }
  }
  try {
    return std::make_unique<CageScene>(s, CageDeformer::bind(s.mesh, cage, o));
  } catch (const Error& e) {
    throw Error(s.name() + ": /deformer/cage: " + cage_name + ": " + e.what(), e.kind());
  }
}

}  // namespace spinmotor::scene
