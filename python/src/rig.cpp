// Python bindings of glTF 2.0 rigs (mesh/gltf.hpp, deform/rig_skin.hpp, scene/rig_pose.hpp): read a
// skinned character, pose it with any skinning blend at any animation time (optionally cleaned up by
// the pose-keeping cleanup), the glTF formula as the reference, and baked morph-target animations
// written and read back (the same code as `spinmotor rig pose ... --out x.glb`).
#include <memory>
#include <mutex>

#include "common.hpp"
#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/rig_skin.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"
#include "spinmotor/scene/rig_pose.hpp"

namespace spinmotor::python {

namespace {

struct PyRig {
  std::shared_ptr<const GltfRig> rig;
  std::unique_ptr<std::mutex> lock = std::make_unique<std::mutex>();
};

struct PyRigPoser {
  std::shared_ptr<const GltfRig> rig;  // outlives the poser, which refers to it
  std::unique_ptr<scene::RigPoser> poser;
  std::unique_ptr<std::mutex> lock = std::make_unique<std::mutex>();
};

scene::RigPoseOptions pose_options(int animation, const std::string& blend, const std::string& cleanup,
                                   double pin_threshold, double pin_margin, double pose_weight,
                                   const std::string& space, bool warm_start) {
  scene::RigPoseOptions o;
  o.animation = animation;
  o.blend = parse_option<SkinBlend>(blend, "blend: ");
  o.cleanup = parse_option<scene::RigCleanupMode>(cleanup, "cleanup: ");
  o.cleanup_options.pin_threshold = pin_threshold;
  o.cleanup_options.pin_margin = pin_margin;
  o.cleanup_options.pose_weight = pose_weight;
  o.space = parse_option<scene::RigSpace>(space, "space: ");
  o.cleanup_options.cleanup.warm_start = warm_start;
  return o;
}

PyRigPoser make_poser(const PyRig& r, const scene::RigPoseOptions& o) {
  PyRigPoser p;
  p.rig = r.rig;
  py::gil_scoped_release release;
  p.poser = std::make_unique<scene::RigPoser>(*p.rig, o);
  return p;
}

/// frames (k, n, 3) array or a list of (n, 3) arrays, each n×3 finite.
std::vector<Eigen::MatrixXd> to_frames(py::handle obj, Eigen::Index n) {
  std::vector<Eigen::MatrixXd> out;
  py::array a = py::array::ensure(obj);
  if (a && a.ndim() == 3) {
    for (py::ssize_t f = 0; f < a.shape(0); ++f)
      out.push_back(to_matrix(a[py::int_(f)], ("frames[" + std::to_string(f) + "]").c_str(), n, 3));
    return out;
  }
  PyErr_Clear();
  if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj))
    throw Error("frames: expected a (k, n, 3) array or a list of (n, 3) arrays");
  const auto seq = py::reinterpret_borrow<py::sequence>(obj);
  for (std::size_t f = 0; f < seq.size(); ++f)
    out.push_back(to_matrix(seq[f], ("frames[" + std::to_string(f) + "]").c_str(), n, 3));
  return out;
}

py::array_t<double> stack(const std::vector<Eigen::MatrixXd>& frames) {
  const py::ssize_t k = static_cast<py::ssize_t>(frames.size()), n = k ? frames[0].rows() : 0;
  py::array_t<double> a({k, n, static_cast<py::ssize_t>(3)});
  auto u = a.mutable_unchecked<3>();
  for (py::ssize_t f = 0; f < k; ++f)
    for (py::ssize_t i = 0; i < n; ++i)
      for (py::ssize_t c = 0; c < 3; ++c) u(f, i, c) = frames[f](i, c);
  return a;
}

Eigen::Matrix4d to_matrix4(py::handle obj, const char* name) {
  if (obj.is_none()) return Eigen::Matrix4d::Identity();
  return to_matrix(obj, name, 4, 4);
}

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
      .def_property_readonly(
          "V", [](const PyRig& r) { return to_numpy(r.rig->mesh.V); },
          "V -> (n, 3): the welded surface's rest positions (mesh space).")
      .def_property_readonly(
          "F", [](const PyRig& r) { return to_numpy(r.rig->mesh.F); }, "F -> (m, 3): the welded triangles.")
      .def_property_readonly(
          "UV",
          [](const PyRig& r) -> py::object {
            return r.rig->mesh.has_uv() ? py::object(to_numpy(r.rig->mesh.UV)) : py::none();
          },
          "UV -> (t, 2) texture coordinates per file vertex (v flipped to OBJ's origin), or None.")
      .def_property_readonly(
          "FUV",
          [](const PyRig& r) -> py::object {
            return r.rig->mesh.has_uv() ? py::object(to_numpy(r.rig->mesh.FUV)) : py::none();
          },
          "FUV -> (m, 3) texture coordinate index per corner, or None.")
      .def_property_readonly(
          "joint_names", [](const PyRig& r) { return r.rig->joint_names; },
          "joint_names -> list of str: the skin's joints in order.")
      .def_property_readonly(
          "joint_parents", [](const PyRig& r) { return r.rig->joint_parents; },
          "joint_parents -> list of int: each joint's nearest ancestor joint, -1 for a root.")
      .def_property_readonly(
          "weights", [](const PyRig& r) { return to_numpy(Eigen::MatrixXd(r.rig->weights)); },
          "weights -> (n, J) dense skin weights (rows renormalised to sum 1).")
      .def_property_readonly(
          "renormalised_rows", [](const PyRig& r) { return r.rig->renormalised_rows; },
          "renormalised_rows -> int: file vertices whose weights did not sum to 1.")
      .def_property_readonly(
          "warnings", [](const PyRig& r) { return r.rig->warnings; },
          "warnings -> list of str: what the reader noticed (renormalised rows, weld mismatches, ...).")
      .def_property_readonly(
          "animations",
          [](const PyRig& r) {
            py::list l;
            for (const GltfAnimation& a : r.rig->animations) l.append(py::make_tuple(a.name, a.start, a.end));
            return l;
          },
          "animations -> list of (name, start, end): the animations and their key time ranges in seconds.")
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
            return to_numpy_owned(std::move(V));
          },
          py::arg("t"), py::arg("animation") = 0, py::arg("blend") = "lbs", R"doc(
pose(t, animation=0, blend="lbs") -> V (n, 3, column-major, no copy): the skinned surface at time t (seconds, clamped to the
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
            scene::RigCleanupOptions o;
            o.pin_threshold = threshold;
            o.pin_margin = margin;
            o.pose_weight = pose_weight;
            o.cleanup.keep = parse_option<CleanupKeep>(keep, "keep: ");
            o.cleanup.max_iterations = max_iterations;
            PyCleanup c;
            py::gil_scoped_release release;
            const RigSkin skin = rig_skin(*r.rig);
            scene::RigCleanup rc = scene::RigCleanup::bind(r.rig->mesh, skin.weights, skin.bones, o);
            c.cleanup = std::make_unique<PinnedCleanup>(std::move(rc.cleanup));
            return c;
          },
          py::arg("threshold") = scene::RigCleanupOptions{}.pin_threshold,
          py::arg("margin") = scene::RigCleanupOptions{}.pin_margin,
          py::arg("pose_weight") = scene::RigCleanupOptions{}.pose_weight,
          py::arg("keep") = std::string(option_name(PinnedCleanupOptions{}.keep)),
          py::arg("max_iterations") = PinnedCleanupOptions{}.max_iterations, R"doc(
bind_cleanup(threshold=0.999, margin=-1, pose_weight=10, keep="auto", max_iterations=100) -> PinnedCleanup:
the pose-keeping cleanup of this rig with the rig defaults (scene/rig_cleanup.hpp, the same as `spinmotor
rig pose --cleanup pinned`): pins = vertices of one joint (weight >= threshold) farther than `margin`
(< 0: per bone a quarter of its widest blend band) from every blended vertex; the soft parts held near the
pose by the weights' attraction of strength pose_weight. Use .cleanup(rig.pose(t)) per frame.
Errors: spinmotor.Error when no vertex qualifies as a pin, or for bad parameters.
Errors: spinmotor.Error for an animation out of range or a non-finite t.
)doc")
      .def(
          "poser",
          [](const PyRig& r, int animation, const std::string& blend, const std::string& cleanup,
             double pin_threshold, double pin_margin, double pose_weight, const std::string& space,
             bool warm_start) {
            return make_poser(r, pose_options(animation, blend, cleanup, pin_threshold, pin_margin,
                                              pose_weight, space, warm_start));
          },
          py::arg("animation") = 0, py::arg("blend") = "lbs", py::arg("cleanup") = "none",
          py::arg("pin_threshold") = scene::RigCleanupOptions{}.pin_threshold,
          py::arg("pin_margin") = scene::RigCleanupOptions{}.pin_margin,
          py::arg("pose_weight") = scene::RigCleanupOptions{}.pose_weight, py::arg("space") = "mesh",
          py::arg("warm_start") = false, R"doc(
poser(animation=0, blend="lbs", cleanup="none", pin_threshold=0.999, pin_margin=-1, pose_weight=10,
      space="mesh", warm_start=False)
  -> RigPoser: the skin (and, with cleanup="pinned", the pose-keeping cleanup) bound once
  (scene/rig_pose.hpp, as `spinmotor rig pose`), posed per time with RigPoser.pose(t).

Inputs:  animation: index into animations, -1 the rest pose; blend: lbs, dlb, log or pivot-log;
         cleanup: none or pinned (the vertices of one joint with weight >= pin_threshold, farther
         than pin_margin from any blended vertex, stay put; pin_margin < 0: per bone, a quarter of
         the widest blend band of its joints; pose_weight: the attraction holding the soft parts near the
         skinned pose, scene/rig_cleanup.hpp); space: mesh (the file's POSITION frame) or scene (the
         mesh node's global matrix applied); warm_start: cleanup="pinned" for times posed in order,
         each cleanup starts from the previous one's correction (faster; depends on the call order).
Output:  a RigPoser.
Errors:  spinmotor.Error for an unknown name (listing the valid ones), an animation out of range, a
         pin_threshold outside [0.5, 1], no pin found, a skeleton or mesh the deformers refuse.
)doc")
      .def(
          "bake",
          [](const PyRig& r, const std::filesystem::path& path, py::object frames, py::object times,
             int animation, const std::string& blend, const std::string& cleanup, double pin_threshold,
             double pin_margin, double pose_weight, const std::string& space, py::object name,
             bool warm_start) {
            if (frames.is_none() == times.is_none())
              throw Error("bake: give exactly one of frames (a count) and times (a list of seconds)");
            const scene::RigPoseOptions o = pose_options(animation, blend, cleanup, pin_threshold, pin_margin,
                                                         pose_weight, space, warm_start);
            std::vector<double> t;
            if (!times.is_none()) {
              const Eigen::VectorXd tv = to_vector(times, "times");
              t.assign(tv.data(), tv.data() + tv.size());
            } else {
              int k = 0;
              try {
                k = frames.cast<int>();
              } catch (const py::cast_error&) {
                throw Error("frames: expected an int (the frame count)");
              }
              t = scene::rig_frame_times(*r.rig, animation, k);
            }
            const std::string nm = name.is_none() ? path.stem().string() : py::str(name).cast<std::string>();
            PyRigPoser p = make_poser(r, o);
            std::vector<Eigen::MatrixXd> written;
            {
              py::gil_scoped_release release;
              written = scene::bake_rig_gltf(path, *p.poser, t, nm);
            }
            py::dict d;
            d["frames"] = stack(written);
            d["times"] = t;
            return d;
          },
          py::arg("path"), py::arg("frames") = py::none(), py::arg("times") = py::none(),
          py::arg("animation") = 0, py::arg("blend") = "lbs", py::arg("cleanup") = "none",
          py::arg("pin_threshold") = scene::RigCleanupOptions{}.pin_threshold,
          py::arg("pin_margin") = scene::RigCleanupOptions{}.pin_margin,
          py::arg("pose_weight") = scene::RigCleanupOptions{}.pose_weight, py::arg("space") = "mesh",
          py::arg("name") = py::none(), py::arg("warm_start") = true, R"doc(
bake(path, frames=None, times=None, animation=0, blend="lbs", cleanup="none", pin_threshold=0.999,
     pin_margin=-1, pose_weight=10, space="mesh", name=None, warm_start=True)
  -> dict(frames (k, n, 3), times (k,))

Poses the rig (as poser() with the same options) and writes the frames as a glTF 2.0 morph-target
animation (.gltf or .glb; positions as float32; a STEP weights animation plays them; Blender shows shape
keys): what `spinmotor rig pose FILE --frames N --out path.glb` writes. With space="scene" the node
carries the mesh node's rest global matrix. Read it back with read_gltf_morph_animation(path).
Inputs:  path (.gltf or .glb); exactly one of frames (count, spread evenly over the animation) and
         times (strictly increasing seconds); the poser options; name: the mesh and animation name
         (default: the file's stem); warm_start: the frames' cleanups start from the previous
         frame's correction (as `rig pose --frames`; False: each from its skinned pose alone).
Output:  dict with frames (k, n, 3, mesh space, before float32 rounding) and times.
Errors:  spinmotor.Error as poser(), for a bad path extension, non-increasing times; nothing is
         written then (the file is replaced atomically).
)doc");

  py::class_<PyRigPoser>(m, "RigPoser", R"doc(
A glTF rig bound for posing (scene/rig_pose.hpp): made by Rig.poser(...). pose(t) -> V (n, 3).
Properties: pins (the pinned vertices with cleanup="pinned", else empty), pin_margins (per bone).
)doc")
      .def(
          "pose",
          [](PyRigPoser& p, double t) {
            Eigen::MatrixXd V;
            {
              py::gil_scoped_release release;
              std::lock_guard<std::mutex> guard(*p.lock);
              V = p.poser->pose(t);
            }
            return to_numpy_owned(std::move(V));
          },
          py::arg("t"), R"doc(
pose(t) -> V (n, 3, column-major, no copy): the skinned surface at time t (seconds, clamped to the animation's range),
cleaned up if the poser was made with cleanup="pinned", in the poser's space. No bind per call.
Errors: spinmotor.Error for a non-finite t or a non-rigid joint transform.
)doc")
      .def_property_readonly(
          "pins",
          [](const PyRigPoser& p) {
            const Eigen::VectorXi& v = p.poser->pins();
            return std::vector<int>(v.data(), v.data() + v.size());
          },
          "pins -> list of int: the vertices the cleanup keeps in place (sorted; empty without cleanup).")
      .def_property_readonly(
          "pin_margins", [](const PyRigPoser& p) { return to_numpy(p.poser->pin_margins()); },
          "pin_margins -> (J,) array: the margin used per bone (empty without cleanup).");
  m.def(
      "read_gltf",
      [](const std::filesystem::path& path) {
        PyRig r;
        py::gil_scoped_release release;
        r.rig = std::make_shared<const GltfRig>(spinmotor::read_gltf(path));
        return r;
      },
      py::arg("path"), R"doc(
read_gltf(path) -> Rig: a .gltf (data: URIs or side .bin) or .glb skinned character.
Input: path. Output: a Rig (the welded surface, joints, weights, animations).
Errors: spinmotor.Error naming the file and the element; a file without a skinned mesh (e.g. a baked
animation: read it with read_gltf_morph_animation) is an error.
)doc");

  m.def(
      "write_gltf_morph_animation",
      [](const std::filesystem::path& path, py::object V, py::object F, py::object frames, py::object times,
         const std::string& name, py::object node_matrix, py::object UV, py::object FUV) {
        Mesh rest = to_mesh(V, F);
        if (UV.is_none() != FUV.is_none()) throw Error("UV and FUV: give both or neither");
        if (!UV.is_none()) {
          rest.UV = to_matrix(UV, "UV", -1, 2);
          rest.FUV = to_faces(FUV, "FUV", rest.UV.rows());
          if (rest.FUV.rows() != rest.F.rows())
            throw Error("FUV: has " + std::to_string(rest.FUV.rows()) + " rows, F " +
                        std::to_string(rest.F.rows()));
        }
        const std::vector<Eigen::MatrixXd> fr = to_frames(frames, rest.V.rows());
        const Eigen::VectorXd tv = to_vector(times, "times");
        const std::vector<double> t(tv.data(), tv.data() + tv.size());
        const Eigen::Matrix4d node = to_matrix4(node_matrix, "node_matrix");
        py::gil_scoped_release release;
        write_gltf_morph_animation(path, rest, fr, t, name, node);
      },
      py::arg("path"), py::arg("V"), py::arg("F"), py::arg("frames"), py::arg("times"),
      py::arg("name") = "baked", py::arg("node_matrix") = py::none(), py::arg("UV") = py::none(),
      py::arg("FUV") = py::none(), R"doc(
write_gltf_morph_animation(path, V, F, frames, times, name="baked", node_matrix=None, UV=None, FUV=None)
  -> None: any deformation sequence (a deformer's poses, snaps, rig frames) as a glTF 2.0 morph-target
  animation (mesh/gltf.hpp): one node holding the rest mesh (V, F; UVs per corner if given) and one
  POSITION target per frame, played by a STEP weights animation (Blender: shape keys).

Inputs:  path (.gltf or .glb); V (n, 3), F (m, 3) the rest mesh; frames (k, n, 3) array or list of
         (n, 3); times (k,) strictly increasing seconds; name; node_matrix (4, 4) affine (default
         identity); UV (t, 2) and FUV (m, 3) texture coordinates (both or neither).
Output:  None; the file is written atomically (positions stored as float32).
Errors:  spinmotor.Error for a bad shape, non-finite value, non-increasing times, a non-affine node
         matrix, a bad extension; nothing is written then.
)doc");

  m.def(
      "read_gltf_morph_animation",
      [](const std::filesystem::path& path) {
        GltfMorphAnimation a;
        {
          py::gil_scoped_release release;
          a = read_gltf_morph_animation(path);
        }
        py::dict d;
        d["V"] = to_numpy(a.mesh.V);
        d["F"] = to_numpy(a.mesh.F);
        d["UV"] = a.mesh.has_uv() ? py::object(to_numpy(a.mesh.UV)) : py::none();
        d["FUV"] = a.mesh.has_uv() ? py::object(to_numpy(a.mesh.FUV)) : py::none();
        d["frames"] = stack(a.frames);
        d["times"] = a.times;
        d["node_matrix"] = to_numpy(Eigen::MatrixXd(a.node_matrix));
        d["name"] = a.name;
        return d;
      },
      py::arg("path"), R"doc(
read_gltf_morph_animation(path) -> dict: a baked animation read back (Rig.bake,
write_gltf_morph_animation, `spinmotor rig pose ... --out x.glb`, or any glTF whose first mesh node has
POSITION morph targets).

Input:   path (.gltf or .glb).
Output:  dict with V (n, 3) and F (m, 3): the base surface, equal positions welded (the vertex order
         of the mesh that was written); UV, FUV (or None); frames (k, n, 3): base + each target;
         times (k,): each target's key time in the weights animation; node_matrix (4, 4): the node's
         global matrix; name.
Errors:  spinmotor.Error naming the file and the element (no morph targets, a bad accessor, ...).
)doc");
}

}  // namespace spinmotor::python
