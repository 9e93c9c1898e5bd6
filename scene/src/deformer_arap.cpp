// Scene deformer "arap": ArapDeformer (CGA paper §VII; Sorkine & Alexa 2007), handles are hard constraints
// moved rigidly by their motors.
//   {"type": "arap", "energy": "spokes" | "spokes-and-rims", "iterations": n, "tolerance": t,
//    "initial": "rest" | "harmonic" | "previous", "clamp_negative_weights": bool}
// Defaults: spokes-and-rims, 100 iterations, tolerance 1e-6 (relative energy change), rest, no clamping.
// "previous" starts each frame of an animation from the previous frame's result (rest on the first).
// Metrics JSON gains "arap": the energy of every iteration (E_0 = initial guess, non-increasing), the
// iterations, whether the tolerance was reached, and the time split; bind adds "arap_bind".
#include "spinmotor/deform/arap.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/scene/deformer_registry.hpp"

namespace spinmotor::scene {

namespace {

class ArapScene final : public SceneDeformer {
public:
  ArapScene(const Scene& s, ArapDeformer d) : scene_(s), d_(std::move(d)) { motors_.resize(s.handles.size()); }

  std::vector<std::string> controls() const override {
    std::vector<std::string> names;
    for (const Handle& h : scene_.handles) names.push_back(h.name);
    return names;
  }

  void pose(const Pose& pose, Eigen::MatrixXd& V_out) override {
    for (std::size_t j = 0; j < motors_.size(); ++j) motors_[j] = pose.motor(scene_.handles[j].name);
    try {
      d_.pose(motors_, V_out);
    } catch (const Error& e) {
      throw Error(scene_.name() + ": " + e.what(), e.kind());
    }
  }

  nlohmann::json report(const Pose& pose, const Eigen::MatrixXd& V_out) const override {
    std::vector<ga::Mot> m;
    for (const Handle& h : scene_.handles) m.push_back(pose.motor(h.name));
    const ArapReport& r = d_.report();
    return {{"max_handle_error", max_handle_error(scene_.mesh.V, V_out, scene_.handles, m)},
            {"arap",
             {{"energy_type", to_string(d_.options().energy)},
              {"initial", to_string(d_.options().initial)},
              {"energy", r.energy},
              {"iterations", r.iterations},
              {"converged", r.converged},
              {"tolerance", d_.options().tolerance},
              {"local_ms", r.local_ms},
              {"global_ms", r.global_ms},
              {"rhs_ms", r.rhs_ms},
              {"solve_ms", r.solve_ms},
              {"jacobi_rotations", r.jacobi_rotations}}}};
  }

  nlohmann::json bind_report() const override {
    const ArapBindReport& b = d_.bind_report();
    return {{"arap_bind",
             {{"weights_ms", b.weights_ms},
              {"cells_ms", b.cells_ms},
              {"factor_ms", b.factor_ms},
              {"harmonic_ms", b.harmonic_ms},
              {"ordering", b.ordering},
              {"supernodal", b.supernodal},
              {"factor_nonzeros", b.factor_nonzeros}}}};
  }

private:
  const Scene& scene_;
  ArapDeformer d_;
  std::vector<ga::Mot> motors_;
};

}  // namespace

std::unique_ptr<SceneDeformer> bind_arap(const Scene& s) {
  const nlohmann::json& b = s.deformer;
  if (s.handles.empty())
    throw s.error("/handles", "the arap deformer needs at least one handle (a fixed or moved vertex set)");
  ArapDeformer::Options o;
  o.energy = b.value("energy", "spokes-and-rims") == "spokes" ? ArapEnergy::Spokes : ArapEnergy::SpokesAndRims;
  o.iterations = b.value("iterations", o.iterations);
  o.tolerance = b.value("tolerance", o.tolerance);
  o.clamp_negative_weights = b.value("clamp_negative_weights", o.clamp_negative_weights);
  const std::string initial = b.value("initial", "rest");
  o.initial = initial == "harmonic" ? ArapInitial::Harmonic
              : initial == "previous" ? ArapInitial::Previous
                                      : ArapInitial::Rest;
  try {
    return std::make_unique<ArapScene>(s, ArapDeformer::bind(s.mesh, s.handles, o));
  } catch (const Error& e) {
    throw Error(s.name() + ": " + e.what(), e.kind());  // names the face, handle or connected component
  }
}

}  // namespace spinmotor::scene
