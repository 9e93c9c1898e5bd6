// Scene deformer "surface-harmonic": SurfaceHarmonicDeformer (CGA paper §IV), one motor per handle.
//   {"type": "surface-harmonic", "weights": "mean-value" | "cotan", "blend": "log" | "pivot-log" | "dlb"}
#include "spinmotor/deform/surface_harmonic.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/scene/deformer_registry.hpp"

namespace spinmotor::scene {

namespace {

class SurfaceHarmonicScene final : public SceneDeformer {
public:
  SurfaceHarmonicScene(const Scene& s, SurfaceHarmonicDeformer d) : scene_(s), d_(std::move(d)) {
    motors_.resize(s.handles.size());
  }
  std::vector<std::string> controls() const override {
    std::vector<std::string> names;
    for (const Handle& h : scene_.handles) names.push_back(h.name);
    return names;
  }
  void pose(const Pose& pose, Eigen::MatrixXd& V_out) override {
    for (std::size_t j = 0; j < motors_.size(); ++j) motors_[j] = pose.motor(scene_.handles[j].name);
    d_.pose(motors_, V_out);
  }
  nlohmann::json report(const Pose& pose, const Eigen::MatrixXd& V_out) const override {
    std::vector<ga::Mot> m;
    for (const Handle& h : scene_.handles) m.push_back(pose.motor(h.name));
    return {{"max_handle_error", max_handle_error(scene_.mesh.V, V_out, scene_.handles, m)}};
  }

private:
  const Scene& scene_;
  SurfaceHarmonicDeformer d_;
  std::vector<ga::Mot> motors_;
};

}  // namespace

std::unique_ptr<SceneDeformer> bind_surface_harmonic(const Scene& s) {
  const nlohmann::json& b = s.deformer;
  if (s.handles.empty()) throw s.error("/handles", "the surface-harmonic deformer needs at least one handle");
  SurfaceHarmonicDeformer::Options o;
  o.weights = b.value("weights", "mean-value") == "cotan" ? HarmonicWeights::Cotangent : HarmonicWeights::MeanValue;
  const std::string blend = b.value("blend", "log");
  o.blend = blend == "pivot-log" ? ga::Blend::PivotLog : blend == "dlb" ? ga::Blend::Linear : ga::Blend::Log;
  try {
    return std::make_unique<SurfaceHarmonicScene>(s, SurfaceHarmonicDeformer::bind(s.mesh, s.handles, o));
  } catch (const Error& e) {
    throw Error(s.name() + ": " + e.what(), e.kind());  // names the handle or the connected component
  }
}

}  // namespace spinmotor::scene
