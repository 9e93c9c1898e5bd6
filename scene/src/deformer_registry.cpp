#include "spinmotor/scene/deformer_registry.hpp"

#include "spinmotor/core/error.hpp"

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

double max_handle_error(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V, std::span<const Handle> handles,
                        std::span<const ga::Mot> motors) {
  double e = 0.0;
  for (std::size_t j = 0; j < handles.size(); ++j)
    for (Eigen::Index k = 0; k < handles[j].vertices.size(); ++k) {
      const int v = handles[j].vertices[k];
      e = std::max(e, (V.row(v).transpose() - ga::transform(motors[j], V_rest.row(v).transpose())).norm());
    }
  return e;
}

}  // namespace spinmotor::scene
