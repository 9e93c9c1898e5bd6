// Python bindings of the rig cleanup (scene/rig_cleanup.hpp): the one door to the pose-keeping cleanup of a
// skinned character, for rigs read here (Rig.bind_cleanup) and for skins held elsewhere (the Blender
// add-on: rest positions, faces, weights and bones from Blender's own data).
#include "spinmotor/scene/rig_cleanup.hpp"

#include <memory>
#include <mutex>

#include "common.hpp"
#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/gltf_skin.hpp"

namespace spinmotor::python {

namespace {

struct PyRigCleanup {
  std::unique_ptr<scene::RigCleanup> cleanup;
  std::unique_ptr<std::mutex> lock = std::make_unique<std::mutex>();
};

/// bones: a list of (name, parent, head, tail) with parent an index (−1 or None for a root).
std::vector<Bone> to_bones(py::handle obj, Eigen::Index count) {
  std::vector<Bone> bones;
  if (obj.is_none()) {
    for (Eigen::Index j = 0; j < count; ++j) bones.push_back({.name = "bone " + std::to_string(j)});
    return bones;
  }
  if (!py::isinstance<py::sequence>(obj)) throw Error("bones: expected a list of (name, parent, head, tail)");
  const auto seq = py::reinterpret_borrow<py::sequence>(obj);
  for (std::size_t j = 0; j < seq.size(); ++j) {
    const std::string who = "bones[" + std::to_string(j) + "]";
    if (!py::isinstance<py::sequence>(seq[j]) || py::len(seq[j]) != 4)
      throw Error(who + ": expected (name, parent, head, tail)");
    const auto b = py::reinterpret_borrow<py::sequence>(seq[j]);
    Bone bone;
    bone.name = py::str(b[0]).cast<std::string>();
    bone.parent = b[1].is_none() ? -1 : b[1].cast<int>();
    bone.head = to_vector(b[2], (who + " head").c_str(), 3);
    bone.tail = to_vector(b[3], (who + " tail").c_str(), 3);
    bones.push_back(std::move(bone));
  }
  check_skeleton(bones);
  return bones;
}

py::list pieces_list(const scene::RigCleanup& c) {
  py::list l;
  for (const scene::RigCleanupPiece& p : c.pieces()) {
    py::dict d;
    d["first_vertex"] = p.vertices.front();
    d["vertices"] = p.vertices.size();
    d["faces"] = p.faces;
    d["degenerate_faces"] = p.degenerate;
    d["pins"] = p.pins;
    d["status"] = std::string(option_name(p.status));
    d["keep"] = p.status == scene::RigPieceStatus::Cleaned
                    ? py::object(py::str(std::string(option_name(p.keep))))
                    : py::none();
    l.append(d);
  }
  return l;
}

py::dict result_dict(const scene::RigCleanupResult& r, const Eigen::MatrixXd& V) {
  py::dict d;
  d["V"] = to_numpy(V);
  d["iterations"] = r.iterations;
  d["converged"] = r.converged;
  d["volume_ratio"] = r.volume_ratio;
  d["edit_volume_ratio"] = r.edit_volume_ratio;
  d["pin_error"] = r.pin_error;
  d["total_ms"] = r.total_ms;
  py::list pieces;
  for (const PinnedCleanupResult& p : r.pieces) {
    py::dict pd;
    pd["iterations"] = p.iterations;
    pd["converged"] = p.converged;
    pd["measure_ratio"] = p.measure_ratio();
    pd["keep"] = std::string(option_name(p.kept));
    pieces.append(pd);
  }
  d["pieces"] = pieces;
  return d;
}

scene::RigCleanupOptions cleanup_options(double threshold, double margin, double pose_weight,
                                         const std::string& keep, int max_iterations, double tolerance,
                                         bool warm_start) {
  scene::RigCleanupOptions o;
  o.pin_threshold = threshold;
  o.pin_margin = margin;
  o.cleanup.pose_weight = pose_weight;
  o.cleanup.keep = parse_option<CleanupKeep>(keep, "keep: ");
  o.cleanup.max_iterations = max_iterations;
  o.cleanup.tolerance = tolerance;
  o.cleanup.warm_start = warm_start;
  return o;
}

}  // namespace

py::object make_rig_cleanup(const Mesh& rest, const Eigen::SparseMatrix<double>& W,
                            const std::vector<Bone>& bones, const scene::RigCleanupOptions& o,
                            const scene::RigCleanup::VertexLabel& label) {
  PyRigCleanup c;
  {
    py::gil_scoped_release release;
    c.cleanup = std::make_unique<scene::RigCleanup>(scene::RigCleanup::bind(rest, W, bones, o, label));
  }
  return py::cast(std::move(c));
}

void bind_rig_cleanup(py::module_& m) {
  const scene::RigCleanupOptions def;
  // The library's rig defaults (scene::RigCleanupOptions), for callers that cannot import the module
  // when they declare their own defaults (the Blender add-on's properties: its tests compare).
  py::dict defaults;
  defaults["threshold"] = def.pin_threshold;
  defaults["margin"] = def.pin_margin;
  defaults["pose_weight"] = def.cleanup.pose_weight;
  defaults["attraction_low"] = def.attraction_low;
  defaults["keep"] = std::string(option_name(def.cleanup.keep));
  defaults["max_iterations"] = def.cleanup.max_iterations;
  defaults["tolerance"] = def.cleanup.tolerance;
  defaults["warm_start"] = def.cleanup.warm_start;
  m.attr("RIG_CLEANUP_DEFAULTS") = defaults;
  py::class_<PyRigCleanup>(m, "RigCleanup", R"doc(
The pose-keeping cleanup of a skinned character with the rig defaults (scene/rig_cleanup.hpp): the one
door shared by `spinmotor rig pose --cleanup pinned`, scene files, the viewer and the Blender add-on.
Pins and the pose attraction come from the skin weights; every connected piece of the surface is handled
on its own (cleaned, or kept as skinned when one bone moves it rigidly, every vertex is pinned, or nothing
anchors it), so open, non-manifold and multi-piece meshes never abort.

RigCleanup(V, F, W, bones=None, threshold=0.999, margin=-1, pose_weight=10, keep="auto",
           max_iterations=100, tolerance=1e-4, warm_start=False)
  V (n, 3), F (m, 3): the rest surface; W (n, B): skin weights (rows need not sum to 1); bones: B tuples
  (name, parent, head, tail) for the default per-bone margins (margin < 0; with bones=None give a
  margin >= 0). warm_start: for frames cleaned in time order. Rig.bind_cleanup() binds one for a rig.
Errors: spinmotor.Error for bad weights or options, a bone count that does not match W, or a rest piece
the cleanup refuses (named by its first vertex).
)doc")
      .def(py::init([](py::object V, py::object F, py::object W, py::object bones, double threshold,
                       double margin, double pose_weight, const std::string& keep, int max_iterations,
                       double tolerance, bool warm_start) {
             const Mesh rest = to_mesh(V, F);
             const Eigen::MatrixXd Wm = to_matrix(W, "W", rest.V.rows(), -1);
             const std::vector<Bone> b = to_bones(bones, Wm.cols());
             if (bones.is_none() && margin < 0)
               throw Error("RigCleanup: the per-bone default margin (margin < 0) needs the bones");
             const scene::RigCleanupOptions o =
                 cleanup_options(threshold, margin, pose_weight, keep, max_iterations, tolerance, warm_start);
             PyRigCleanup c;
             py::gil_scoped_release release;
             c.cleanup = std::make_unique<scene::RigCleanup>(scene::RigCleanup::bind(rest, Wm, b, o));
             return c;
           }),
           py::arg("V"), py::arg("F"), py::arg("W"), py::arg("bones") = py::none(),
           py::arg("threshold") = def.pin_threshold, py::arg("margin") = def.pin_margin,
           py::arg("pose_weight") = def.cleanup.pose_weight,
           py::arg("keep") = std::string(option_name(def.cleanup.keep)),
           py::arg("max_iterations") = def.cleanup.max_iterations,
           py::arg("tolerance") = def.cleanup.tolerance, py::arg("warm_start") = def.cleanup.warm_start)
      .def(
          "cleanup",
          [](PyRigCleanup& c, py::object V_edit, bool full) -> py::object {
            const Eigen::MatrixXd E = to_points(V_edit, "V_edit");
            Eigen::MatrixXd V;
            scene::RigCleanupResult r;
            {
              py::gil_scoped_release release;
              std::lock_guard<std::mutex> guard(*c.lock);
              r = (*c.cleanup)(E, V);
            }
            if (!full) return to_numpy(V);
            return result_dict(r, V);
          },
          py::arg("V_edit"), py::arg("full") = false, R"doc(
cleanup(V_edit, full=False) -> V (n, 3), or with full=True a dict: V, iterations (the most of any piece),
converged, volume_ratio and edit_volume_ratio (over the pieces that keep their volume), pin_error,
total_ms, pieces (per piece: iterations, converged, measure_ratio, keep). No factorization per call.
)doc")
      .def(
          "reset",
          [](PyRigCleanup& c) {
            std::lock_guard<std::mutex> guard(*c.lock);
            c.cleanup->reset();
          },
          "reset() -> None: forget the previous frame (warm_start).")
      .def_property_readonly(
          "pins",
          [](const PyRigCleanup& c) {
            const Eigen::VectorXi& p = c.cleanup->pins();
            return std::vector<int>(p.data(), p.data() + p.size());
          },
          "pins -> list of int: the pinned vertices, increasing.")
      .def_property_readonly(
          "attraction", [](const PyRigCleanup& c) { return to_numpy(c.cleanup->attraction()); },
          "attraction -> (n,): the per-vertex attraction weights a_i.")
      .def_property_readonly(
          "margins", [](const PyRigCleanup& c) { return to_numpy(c.cleanup->margins()); },
          "margins -> (B,): the pin margin used per bone.")
      .def_property_readonly(
          "pieces", [](const PyRigCleanup& c) { return pieces_list(*c.cleanup); },
          "pieces -> list of dict: per connected piece its first_vertex, vertices, faces, degenerate_faces, "
          "pins, "
          "status (cleaned, rigid, pinned, unanchored) and keep.")
      .def_property_readonly(
          "cleaned_vertices", [](const PyRigCleanup& c) { return c.cleanup->cleaned_vertices(); },
          "cleaned_vertices -> int: vertices of the pieces the cleanup solves for.")
      .def_property_readonly(
          "bind_ms", [](const PyRigCleanup& c) { return c.cleanup->bind_ms(); },
          "bind_ms -> float: the time of the bind in milliseconds.");
}

}  // namespace spinmotor::python
