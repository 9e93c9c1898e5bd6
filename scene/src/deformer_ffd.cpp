// Scene deformer "ffd": FfdDeformer (CGA paper §V), one motor per lattice control, named "ffd[i,j,k]".
//   {"type": "ffd", "lattice": [l, m, n], "basis": "bezier" | "bspline", "degree": d (bspline, default 3),
//    "mode": "motor" | "position", "blend": "log" | "dlb" (motor mode), "box": {"min": [...], "max": [...]}}
// Defaults: FfdDeformer::Options (bezier, motor, log, box = bounding box + 5%). Metrics gain "ffd": controls,
// vertices outside the box.
#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/ffd.hpp"
#include "spinmotor/scene/deformer_registry.hpp"

namespace spinmotor::scene {

std::unique_ptr<SceneDeformer> bind_ffd(const Scene& s) {
  const nlohmann::json& b = s.deformer;
  FfdDeformer::Options o;
  for (int a = 0; a < 3; ++a) o.lattice[a] = b["lattice"][a].get<int>();
  o.basis = deformer_option(s, "basis", o.basis);
  o.degree = b.value("degree", o.degree);
  o.mode = deformer_option(s, "mode", o.mode);
  o.blend = deformer_option(s, "blend", o.blend);
  if (b.contains("box")) {
    const auto lo = b["box"]["min"].get<std::vector<double>>(),
               hi = b["box"]["max"].get<std::vector<double>>();
    const Eigen::Vector3d mn(lo[0], lo[1], lo[2]), mx(hi[0], hi[1], hi[2]);
    if (!(mx.array() > mn.array()).all()) throw s.error("/deformer/box", "max must exceed min on every axis");
    o.box = Eigen::AlignedBox3d(mn, mx);
  }
  try {
    auto report = [](const AnyDeformer& any, std::span<const ga::Mot>,
                     const Eigen::MatrixXd&) -> nlohmann::json {
      const FfdDeformer& f = *any.get<FfdDeformer>();
      return {{"max_handle_error", nullptr},
              {"ffd", {{"controls", f.controls().size()}, {"outside_box", f.outside()}}}};
    };
    return std::make_unique<SceneDeformer>(s, FfdDeformer::bind(s.mesh, Rig{}, o), report);
  } catch (const Error& e) {
    throw Error(s.name() + ": /deformer: " + e.what(), e.kind());
  }
}

}  // namespace spinmotor::scene
