// Scene deformer "cage": CageDeformer (CGA paper §VI), one motor per cage vertex, named "cage[j]".
//   {"type": "cage", "cage": "cage.obj" | {"box": {"margin": m}}, "coordinates": "harmonic" | "mean-value",
//   "grid": g,
//    "mode": "motor" | "position", "blend": "log" | "pivot-log" | "dlb"}
// Defaults: CageDeformer::Options (harmonic, grid 64, motor, log). The cage path is relative to the scene
// file. A cage that is not closed and consistently oriented, or a mesh vertex outside it, is an error naming
// it (exit 2). Metrics gain "cage": vertices, coordinates, the interpolation bound of harmonic coordinates.
#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/cage_deformer.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/scene/deformer_registry.hpp"

namespace spinmotor::scene {

namespace {

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
  o.coordinates = deformer_option(s, "coordinates", o.coordinates);
  o.grid = b.value("grid", o.grid);
  o.mode = deformer_option(s, "mode", o.mode);
  o.blend = deformer_option(s, "blend", o.blend);
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
    auto report = [](const AnyDeformer& any, std::span<const ga::Mot>,
                     const Eigen::MatrixXd&) -> nlohmann::json {
      const CageDeformer& d = *any.get<CageDeformer>();
      const bool hc = d.options().coordinates == CageDeformer::Coordinates::Harmonic;
      nlohmann::json c = {{"vertices", d.controls().size()},
                          {"coordinates", option_name(d.options().coordinates)}};
      if (hc) c["grid"] = d.options().grid, c["interpolation_bound"] = d.interpolation_bound();
      return {{"max_handle_error", nullptr}, {"cage", c}};
    };
    Rig rig;
    rig.cage = std::move(cage);
    return std::make_unique<SceneDeformer>(s, CageDeformer::bind(s.mesh, rig, o), report);
  } catch (const Error& e) {
    throw Error(s.name() + ": /deformer/cage: " + cage_name + ": " + e.what(), e.kind());
  }
}

}  // namespace spinmotor::scene
