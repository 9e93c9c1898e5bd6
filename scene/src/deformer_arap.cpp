// Scene deformer "arap": ArapDeformer (CGA paper §VII; Sorkine & Alexa 2007), handles are hard constraints
// moved rigidly by their motors.
//   {"type": "arap", "energy": "spokes" | "spokes-and-rims", "iterations": n, "tolerance": t,
//    "initial": "rest" | "harmonic" | "previous", "clamp_negative_weights": bool}
// Defaults: ArapDeformer::Options. "previous" starts each frame of an animation from the previous
// frame's result (rest on the first). Metrics JSON gains "arap": the energy of every iteration (E_0 =
// initial guess, non-increasing), the iterations, whether the tolerance was reached, and the time
// split; bind adds "arap_bind".
#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/arap.hpp"
#include "spinmotor/scene/deformer_registry.hpp"

namespace spinmotor::scene {

SceneDeformer::Report handle_report(const Scene& s);  // deformer_surface_harmonic.cpp

std::unique_ptr<SceneDeformer> bind_arap(const Scene& s) {
  const nlohmann::json& b = s.deformer;
  if (s.handles.empty())
    throw s.error("/handles", "the arap deformer needs at least one handle (a fixed or moved vertex set)");
  ArapDeformer::Options o;
  o.energy = deformer_option(s, "energy", o.energy);
  o.initial = deformer_option(s, "initial", o.initial);
  o.iterations = b.value("iterations", o.iterations);
  o.tolerance = b.value("tolerance", o.tolerance);
  o.clamp_negative_weights = b.value("clamp_negative_weights", o.clamp_negative_weights);
  ArapDeformer d = [&] {
    try {
      return ArapDeformer::bind(s.mesh, Rig{.handles = s.handles}, o);
    } catch (const Error& e) {
      throw Error(s.name() + ": " + e.what(), e.kind());  // names the face, handle or connected component
    }
  }();
  const ArapBindReport& br = d.bind_report();
  nlohmann::json bind_report = {{"arap_bind",
                                 {{"weights_ms", br.weights_ms},
                                  {"cells_ms", br.cells_ms},
                                  {"factor_ms", br.factor_ms},
                                  {"harmonic_ms", br.harmonic_ms},
                                  {"ordering", br.ordering},
                                  {"supernodal", br.supernodal},
                                  {"factor_nonzeros", br.factor_nonzeros}}}};
  auto report = [handles = handle_report(s)](const AnyDeformer& any, std::span<const ga::Mot> m,
                                             const Eigen::MatrixXd& V) {
    nlohmann::json j = handles(any, m, V);
    const ArapDeformer& a = *any.get<ArapDeformer>();
    const ArapReport& r = a.report();
    j["arap"] = {{"energy_type", option_name(a.options().energy)},
                 {"initial", option_name(a.options().initial)},
                 {"energy", r.energy},
                 {"iterations", r.iterations},
                 {"converged", r.converged},
                 {"tolerance", a.options().tolerance},
                 {"local_ms", r.local_ms},
                 {"global_ms", r.global_ms},
                 {"rhs_ms", r.rhs_ms},
                 {"solve_ms", r.solve_ms},
                 {"fallback_fits", r.fallback_fits}};
    return j;
  };
  return std::make_unique<SceneDeformer>(s, std::move(d), report, bind_report);
}

}  // namespace spinmotor::scene
