// Python bindings of glTF 2.0 rigs (mesh/gltf.hpp, deform/rig_skin.hpp): read a skinned character,
// pose it with any skinning blend at any animation time, and the glTF formula as the reference.
#include <memory>
#include <mutex>

#include "common.hpp"
#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/rig_skin.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"

namespace spinmotor::python {

namespace {

struct PyRig {
  std::shared_ptr<const GltfRig> rig;
  std::unique_ptr<std::mutex> lock = std::make_unique<std::mutex>();
};

int animation_index(const GltfRig& rig, int animation) {
  if (animation < -1 || animation >= static_cast<int>(rig.animations.size()))
    throw Error("animation " + std::to_string(animation) + " out of range (the rig has " +
                std::to_string(rig.animations.size()) + "; -1 is the rest pose)");
  return animation;
}

}  // namespace

void bind_rig(py::module_& m) {
  py::class_<PyRig>(m, "Rig", R"doc(
A glTF 2.0 skinned character (mesh/gltf.hpp): the welded surface (vertices with identical positions
merged, texture coordinates per corner), the joints, the skin weights and the animations.

read_gltf(path) -> Rig. Properties: V, F, UV, FUV (the welded surface), joint_names, joint_parents,
weights (n, J dense), animations (list of (name, start, end) in seconds), renormalised_rows, warnings.
Errors: spinmotor.Error naming the file and the element (accessor, node, primitive, sampler).
)doc")
      .def_property_readonly("V", [](const PyRig& r) { return to_numpy(r.rig->mesh.V); })
      .def_property_readonly("F", [](const PyRig& r) { return to_numpy(r.rig->mesh.F); })
      .def_property_readonly("UV",
                             [](const PyRig& r) -> py::object {
                               return r.rig->mesh.has_uv() ? py::object(to_numpy(r.rig->mesh.UV))
                                                           : py::none();
                             })
      .def_property_readonly("FUV",
                             [](const PyRig& r) -> py::object {
                               return r.rig->mesh.has_uv() ? py::object(to_numpy(r.rig->mesh.FUV))
                                                           : py::none();
                             })
      .def_property_readonly("joint_names", [](const PyRig& r) { return r.rig->joint_names; })
      .def_property_readonly("joint_parents", [](const PyRig& r) { return r.rig->joint_parents; })
      .def_property_readonly("weights",
                             [](const PyRig& r) { return to_numpy(Eigen::MatrixXd(r.rig->weights)); })
      .def_property_readonly("renormalised_rows", [](const PyRig& r) { return r.rig->renormalised_rows; })
      .def_property_readonly("warnings", [](const PyRig& r) { return r.rig->warnings; })
      .def_property_readonly("animations",
                             [](const PyRig& r) {
                               py::list l;
                               for (const GltfAnimation& a : r.rig->animations)
                                 l.append(py::make_tuple(a.name, a.start, a.end));
                               return l;
                             })
      .def(
          "pose",
          [](PyRig& r, double t, int animation, const std::string& blend) {
            const GltfRig& rig = *r.rig;
            const int a = animation_index(rig, animation);
            const SkinBlend b = parse_option<SkinBlend>(blend, "blend: ");
            Eigen::MatrixXd V;
            {
              py::gil_scoped_release release;
              std::lock_guard<std::mutex> guard(*r.lock);
              SkinDeformer d = bind_rig(rig, b);
              d.pose(rig_pose_motors(rig, a, t), V);
            }
            return to_numpy(V);
          },
          py::arg("t"), py::arg("animation") = 0, py::arg("blend") = "lbs", R"doc(
pose(t, animation=0, blend="lbs") -> V (n, 3): the skinned surface at time t (seconds, clamped to the
animation's range) with blend lbs, dlb, log or pivot-log (SkinDeformer); animation -1 is the rest pose.
Errors: spinmotor.Error for an animation out of range, an unknown blend, a non-rigid joint transform.
)doc")
      .def(
          "skin_positions",
          [](PyRig& r, double t, int animation) {
            const GltfRig& rig = *r.rig;
            const int a = animation_index(rig, animation);
            Eigen::MatrixXd V;
            {
              py::gil_scoped_release release;
              V = spinmotor::skin_positions(rig, a, t);
            }
            return to_numpy(V);
          },
          py::arg("t"), py::arg("animation") = 0, R"doc(
skin_positions(t, animation=0) -> V (n, 3): the glTF skinning formula with plain 4×4 matrices and every
influence (the reference the blends are compared with).
)doc")
      .def(
          "bind_cleanup",
          [](PyRig& r, double threshold, double margin, double pose_weight, const std::string& keep,
             int max_iterations) {
            RigCleanupOptions o;
            o.pin_threshold = threshold;
            o.pin_margin = margin;
            o.pose_weight = pose_weight;
            o.cleanup.keep = parse_option<CleanupKeep>(keep, "keep: ");
            o.cleanup.max_iterations = max_iterations;
            PyCleanup c;
            py::gil_scoped_release release;
            const RigSkin skin = rig_skin(*r.rig);
            RigCleanup rc = RigCleanup::bind(r.rig->mesh, skin.weights, skin.bones, o);
            c.cleanup = std::make_unique<PinnedCleanup>(std::move(rc.cleanup));
            return c;
          },
          py::arg("threshold") = RigCleanupOptions{}.pin_threshold,
          py::arg("margin") = RigCleanupOptions{}.pin_margin,
          py::arg("pose_weight") = RigCleanupOptions{}.pose_weight,
          py::arg("keep") = std::string(option_name(PinnedCleanupOptions{}.keep)),
          py::arg("max_iterations") = PinnedCleanupOptions{}.max_iterations, R"doc(
bind_cleanup(threshold=0.999, margin=-1, pose_weight=10, keep="auto", max_iterations=100) -> PinnedCleanup:
the pose-keeping cleanup of this rig with the rig defaults (scene/rig_cleanup.hpp, the same as `spinmotor
rig pose --cleanup pinned`): pins = vertices of one joint (weight >= threshold) farther than `margin`
(< 0: per bone a quarter of its widest blend band) from every blended vertex; the soft parts held near the
pose by the weights' attraction of strength pose_weight. Use .cleanup(rig.pose(t)) per frame.
Errors: spinmotor.Error when no vertex qualifies as a pin, or for bad parameters.
)doc");
  m.def(
      "read_gltf",
      [](const std::string& path) {
        PyRig r;
        py::gil_scoped_release release;
        r.rig = std::make_shared<const GltfRig>(spinmotor::read_gltf(path));
        return r;
      },
      py::arg("path"),
      "read_gltf(path) -> Rig: a .gltf (data: URIs or side .bin) or .glb skinned character.");
}

}  // namespace spinmotor::python
