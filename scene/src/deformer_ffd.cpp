// Scene deformer "ffd": FfdDeformer (CGA paper §V), one motor per lattice control, named "ffd[i,j,k]".
//   {"type": "ffd", "lattice": [l, m, n], "basis": "bezier" | "bspline", "degree": d (bspline, default 3),
//    "mode": "motor" | "position", "blend": "log" | "dlb" (motor mode), "box": {"min": [...], "max": [...]}}
// Defaults: bezier, motor, log, box = bounding box + 5%. Metrics gain "ffd": controls, vertices outside the box.
#include <unordered_map>

#include "spinmotor/deform/ffd.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/scene/deformer_registry.hpp"

namespace spinmotor::scene {

namespace {

class FfdScene final : public SceneDeformer {
public:
  FfdScene(const Scene& s, FfdDeformer d) : scene_(s), d_(std::move(d)) {
    const auto& L = d_.lattice();
    for (int a = 0; a < L[0]; ++a)
      for (int b = 0; b < L[1]; ++b)
        for (int c = 0; c < L[2]; ++c) {
          const std::string name = "ffd[" + std::to_string(a) + "," + std::to_string(b) + "," + std::to_string(c) + "]";
          index_[name] = names_.size();
          names_.push_back(name);
        }
    motors_.assign(names_.size(), ga::Mot(1, 0, 0, 0, 0, 0, 0, 0));
  }
  std::vector<std::string> controls() const override { return names_; }
  std::optional<Eigen::Vector3d> control_anchor(const std::string& name) const override {
    const auto it = index_.find(name);  // names_ are in the library's control order (ffd.hpp)
    if (it == index_.end()) return std::nullopt;
    return d_.control_points().row(static_cast<Eigen::Index>(it->second)).transpose();
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
    return {{"max_handle_error", nullptr},
            {"ffd", {{"controls", d_.controls()}, {"outside_box", d_.outside()}}}};
  }

private:
  const Scene& scene_;
  FfdDeformer d_;
  std::vector<std::string> names_;
  std::unordered_map<std::string, std::size_t> index_;
  std::vector<ga::Mot> motors_;
};

}  // namespace

std::unique_ptr<SceneDeformer> bind_ffd(const Scene& s) {
  const nlohmann::json& b = s.deformer;
  FfdDeformer::Options o;
  for (int a = 0; a < 3; ++a) o.lattice[a] = b["lattice"][a].get<int>();
  o.basis = b.value("basis", "bezier") == "bspline" ? FfdDeformer::Basis::BSpline : FfdDeformer::Basis::Bezier;
  o.degree = b.value("degree", 3);
  o.mode = b.value("mode", "motor") == "position" ? FfdDeformer::Mode::Position : FfdDeformer::Mode::Motor;
  o.blend = b.value("blend", "log") == "dlb" ? ga::Blend::Linear : ga::Blend::Log;
  if (b.contains("box")) {
    const auto lo = b["box"]["min"].get<std::vector<double>>(), hi = b["box"]["max"].get<std::vector<double>>();
    const Eigen::Vector3d mn(lo[0], lo[1], lo[2]), mx(hi[0], hi[1], hi[2]);
    if (!(mx.array() > mn.array()).all()) throw s.error("/deformer/box", "max must exceed min on every axis");
    o.box = Eigen::AlignedBox3d(mn, mx);
  }
  try {
    return std::make_unique<FfdScene>(s, FfdDeformer::bind(s.mesh, o));
  } catch (const Error& e) {
    throw Error(s.name() + ": /deformer: " + e.what(), e.kind());
  }
}

}  // namespace spinmotor::scene
