// Scene deformer "surface-harmonic": SurfaceHarmonicDeformer (CGA paper §IV), one motor per handle.
//   {"type": "surface-harmonic", "weights": "mean-value" | "cotan", "blend": "log" | "pivot-log" | "dlb"}
// Defaults: SurfaceHarmonicDeformer::Options.
#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/surface_harmonic.hpp"
#include "spinmotor/scene/deformer_registry.hpp"

namespace spinmotor::scene {

/// The report of deformers whose control j is handle j: the max distance of a handle's vertices from
/// where its motor takes them.
SceneDeformer::Report handle_report(const Scene& s) {
  return [&s](const AnyDeformer&, std::span<const ga::Mot> m, const Eigen::MatrixXd& V) -> nlohmann::json {
    return {{"max_handle_error", max_handle_error(s.mesh.V, V, s.handles, m)}};
  };
}

std::unique_ptr<SceneDeformer> bind_surface_harmonic(const Scene& s) {
  if (s.handles.empty()) throw s.error("/handles", "the surface-harmonic deformer needs at least one handle");
  SurfaceHarmonicDeformer::Options o;
  o.weights = deformer_option(s, "weights", o.weights);
  o.blend = deformer_option(s, "blend", o.blend);
  try {
    return std::make_unique<SceneDeformer>(
        s, SurfaceHarmonicDeformer::bind(s.mesh, Rig{.handles = s.handles}, o), handle_report(s));
  } catch (const Error& e) {
    throw Error(s.name() + ": " + e.what(), e.kind());  // names the handle or the connected component
  }
}

}  // namespace spinmotor::scene
