// Python bindings of glTF 2.0 rigs (mesh/gltf.hpp, deform/gltf_skin.hpp, scene/rig_pose.hpp): read a
// skinned character (every skinned mesh of it, or those named), pose it with any skinning blend at any
// animation time (optionally cleaned up by the rig cleanup), the glTF formula as the reference, and baked
// animations written and read back (the same code as `spinmotor rig pose ... --out x.glb`).
#include <memory>
#include <mutex>

#include "common.hpp"
#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/gltf_correctives.hpp"
#include "spinmotor/deform/gltf_skin.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/mesh/gltf_rig_writer.hpp"
#include "spinmotor/mesh/procedural_rig.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"
#include "spinmotor/scene/rig_pose.hpp"

namespace spinmotor::python {

namespace {

struct PyRig {
  std::shared_ptr<const GltfRig> rig;
  std::shared_ptr<const RigSkin> skin;  // rest surface (scene coordinates), bones, bind matrices
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
  o.cleanup_options.cleanup.pose_weight = pose_weight;
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

std::vector<double> frame_times(const PyRig& r, int animation, py::object frames, py::object times) {
  if (frames.is_none() == times.is_none())
    throw Error("bake: give exactly one of frames (a count) and times (a list of seconds)");
  if (!times.is_none()) {
    const Eigen::VectorXd tv = to_vector(times, "times");
    return {tv.data(), tv.data() + tv.size()};
  }
  int k = 0;
  try {
    k = frames.cast<int>();
  } catch (const py::cast_error&) {
    throw Error("frames: expected an int (the frame count)");
  }
  return scene::rig_frame_times(*r.rig, animation, k);
}

py::list pieces_list(const GltfRig& rig) {
  py::list l;
  for (const GltfPiece& p : rig.pieces) {
    py::dict d;
    d["name"] = p.name;
    d["node"] = rig.nodes[p.node].name;
    d["skin"] = rig.skins[p.skin].name;
    d["first_vertex"] = p.first_vertex;
    d["vertices"] = p.vertices;
    d["first_face"] = p.first_face;
    d["faces"] = p.faces;
    d["file_vertices"] = p.file_vertices;
    d["morph_targets"] = p.target_names;
    l.append(d);
  }
  return l;
}

void bind_rig_class(py::module_& m) {
  py::class_<PyRig>(m, "Rig", R"doc(
A glTF 2.0 skinned character (mesh/gltf.hpp): every skinned mesh of the scene (or those named), welded per
mesh (texture coordinates per corner), the joints, the skin weights, the morph targets and the animations,
evaluated as the glTF specification defines skinning (deform/gltf_skin.hpp), in the file's scene
coordinates (as glTF viewers and Blender show it).

read_gltf(path, meshes=None) -> Rig. Properties: V (the rest surface in scene coordinates: the bind pose),
F, UV, FUV, pieces (one dict per mesh: name, node, skin, first_vertex, vertices, first_face, faces,
file_vertices, morph_targets), joint_names, joint_parents, weights (n, J dense), animations (list of
(name, start, end) in seconds), renormalised_rows, warnings; vertex_label(i) names a vertex in the file's
own numbering.
Errors: spinmotor.Error naming the file and the element (accessor, node, mesh, primitive, sampler).
)doc")
      .def_property_readonly(
          "V", [](const PyRig& r) { return to_numpy(r.skin->rest.V); },
          "V -> (n, 3): the rest surface (the bind pose) in scene coordinates.")
      .def_property_readonly(
          "V_file", [](const PyRig& r) { return to_numpy(r.rig->mesh.V); },
          "V_file -> (n, 3): the welded POSITION values (each mesh's own frame).")
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
          "pieces", [](const PyRig& r) { return pieces_list(*r.rig); },
          "pieces -> list of dict: the skinned meshes read, their vertex and face ranges and morph targets.")
      .def(
          "vertex_label", [](const PyRig& r, Eigen::Index v) { return r.rig->vertex_label(v); },
          py::arg("vertex"),
          "vertex_label(vertex) -> str: where a surface vertex comes from (\"mesh 'Body' primitive 2 vertex "
          "17\").")
      .def_property_readonly(
          "joint_names", [](const PyRig& r) { return r.rig->joint_names; },
          "joint_names -> list of str: the joints in order.")
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
          "animations -> list of (name, start, end): the animations and their key time ranges in seconds.");
}

void bind_rig_pose(py::module_& m) {
  py::class_<PyRig> cls = py::reinterpret_borrow<py::class_<PyRig>>(m.attr("Rig"));
  cls.def(
         "pose",
         [](PyRig& r, double t, int animation, const std::string& blend) {
           const GltfRig& rig = *r.rig;
           const int a = animation_index(rig, animation);
           const SkinBlend b = parse_option<SkinBlend>(blend, "blend: ");
           Eigen::MatrixXd V;
           {
             py::gil_scoped_release release;
             std::lock_guard<std::mutex> guard(*r.lock);
             RigSkinner skinner(rig, b);
             skinner.pose(a, t, V);
           }
           return to_numpy_owned(std::move(V));
         },
         py::arg("t"), py::arg("animation") = 0, py::arg("blend") = "lbs", R"doc(
pose(t, animation=0, blend="lbs") -> V (n, 3, column-major, no copy): the skinned surface at time t (seconds,
clamped to the animation's range) in scene coordinates, morph targets applied, with blend lbs (the glTF
formula, every influence), dlb, log or pivot-log; animation -1 is the rest pose.
Errors: spinmotor.Error for an animation out of range, an unknown blend, a mirroring joint transform.
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
skin_positions(t, animation=0) -> V (n, 3): the glTF specification's skinning with plain 4×4 matrices and
every influence, in scene coordinates (the reference the blends are compared with).
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
          py::arg("pose_weight") = scene::RigCleanupOptions{}.cleanup.pose_weight, py::arg("space") = "scene",
          py::arg("warm_start") = false, R"doc(
poser(animation=0, blend="lbs", cleanup="none", pin_threshold=0.999, pin_margin=-1, pose_weight=10,
      space="scene", warm_start=False)
  -> RigPoser: the skin (and, with cleanup="pinned", the rig cleanup) bound once (scene/rig_pose.hpp, as
  `spinmotor rig pose`), posed per time with RigPoser.pose(t).

Inputs:  animation: index into animations, -1 the rest pose; blend: lbs, dlb, log or pivot-log;
         cleanup: none or pinned (the vertices of one joint with weight >= pin_threshold, farther
         than pin_margin from any blended vertex, stay put; pin_margin < 0: per bone, a quarter of
         the widest blend band of its joints; pose_weight: the attraction holding the soft parts near the
         skinned pose; every connected piece on its own, scene/rig_cleanup.hpp); space: scene (the file's
         scene) or mesh (each mesh's POSITION frame); warm_start: cleanup="pinned" for times posed in
         order, each cleanup starts from the previous one's correction.
Output:  a RigPoser.
Errors:  spinmotor.Error for an unknown name (listing the valid ones), an animation out of range, a
         pin_threshold outside [0.5, 1], a skeleton or mesh the deformers refuse.
)doc");
}

void bind_rig_bake(py::module_& m) {
  py::class_<PyRig> cls = py::reinterpret_borrow<py::class_<PyRig>>(m.attr("Rig"));
  cls.def(
      "bake",
      [](const PyRig& r, const std::filesystem::path& path, py::object frames, py::object times,
         int animation, const std::string& blend, const std::string& cleanup, double pin_threshold,
         double pin_margin, double pose_weight, const std::string& space, py::object name, bool warm_start,
         const std::string& mode, double max_error) {
        const scene::RigPoseOptions o = pose_options(animation, blend, cleanup, pin_threshold, pin_margin,
                                                     pose_weight, space, warm_start);
        if (mode != "frames" && mode != "correctives")
          throw Error("mode: '" + mode + "' (frames or correctives)");
        const std::vector<double> t = frame_times(r, animation, frames, times);
        const std::string nm = name.is_none() ? path.stem().string() : py::str(name).cast<std::string>();
        PyRigPoser p = make_poser(r, o);
        std::vector<Eigen::MatrixXd> written;
        py::dict d;
        {
          py::gil_scoped_release release;
          if (mode == "frames") {
            written = scene::bake_rig_gltf(path, *p.poser, t, nm);
          } else {
            if (o.space != scene::RigSpace::Scene) throw Error("mode=\"correctives\" is in scene space");
            for (double tf : t) written.push_back(p.poser->pose_scene(tf));
            CorrectiveOptions co;
            co.max_error = max_error;
            const CorrectiveRig cr = corrective_rig(*r.rig, animation, t, written, co);
            write_gltf_rig(path, cr.rig);
            py::gil_scoped_acquire acquire;
            d["targets"] = cr.targets;
            d["max_error"] = cr.max_error;
            d["rms_error"] = cr.rms_error;
            d["bound_met"] = cr.bound_met;
          }
        }
        d["frames"] = stack(written);
        d["times"] = t;
        return d;
      },
      py::arg("path"), py::arg("frames") = py::none(), py::arg("times") = py::none(),
      py::arg("animation") = 0, py::arg("blend") = "lbs", py::arg("cleanup") = "none",
      py::arg("pin_threshold") = scene::RigCleanupOptions{}.pin_threshold,
      py::arg("pin_margin") = scene::RigCleanupOptions{}.pin_margin,
      py::arg("pose_weight") = scene::RigCleanupOptions{}.cleanup.pose_weight, py::arg("space") = "scene",
      py::arg("name") = py::none(), py::arg("warm_start") = true, py::arg("mode") = "frames",
      py::arg("max_error") = CorrectiveOptions{}.max_error, R"doc(
bake(path, frames=None, times=None, animation=0, blend="lbs", cleanup="none", pin_threshold=0.999,
     pin_margin=-1, pose_weight=10, space="scene", name=None, warm_start=True, mode="frames", max_error=1e-3)
  -> dict(frames (k, n, 3), times (k,)[, targets, max_error, rms_error, bound_met])

Poses the rig (as poser() with the same options) and writes a .gltf/.glb:
  mode="frames": every frame as a morph target, one node per mesh, played by a STEP weights animation
  (Blender shows shape keys): what `spinmotor rig pose FILE --frames N --out path.glb` writes;
  mode="correctives": the rig itself with a few corrective morph targets per mesh and their weights
  animation, reproducing the posed frames to max_error of the diagonal on any engine that plays skinning
  and morph targets (deform/gltf_correctives.hpp; `--bake correctives`).
Inputs:  path (.gltf or .glb); exactly one of frames (count, spread evenly over the animation) and
         times (strictly increasing seconds); the poser options; name: the mesh and animation name
         (default: the file's stem).
Output:  dict with frames (k, n, 3, in the poser's space, before float32 rounding) and times; with
         mode="correctives" also the targets per mesh and the achieved max_error / rms_error.
Errors:  spinmotor.Error as poser(), for a bad path extension, non-increasing times; nothing is
         written then (the file is replaced atomically).
)doc");
}

void bind_rig_poser(py::module_& m) {
  py::class_<PyRigPoser>(m, "RigPoser", R"doc(
A glTF rig bound for posing (scene/rig_pose.hpp): made by Rig.poser(...). pose(t) -> V (n, 3).
Properties: pins (the pinned vertices with cleanup="pinned", else empty), pin_margins (per bone),
last_cleanup (the last frame's cleanup figures), pieces (the cleanup's pieces).
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
Errors: spinmotor.Error for a non-finite t or a mirroring joint transform.
)doc")
      .def_property_readonly(
          "pins",
          [](const PyRigPoser& p) {
            if (!p.poser->cleanup()) return std::vector<int>();
            const Eigen::VectorXi& v = p.poser->cleanup()->pins();
            return std::vector<int>(v.data(), v.data() + v.size());
          },
          "pins -> list of int: the vertices the cleanup keeps in place (sorted; empty without cleanup).")
      .def_property_readonly(
          "pin_margins",
          [](const PyRigPoser& p) {
            return to_numpy(p.poser->cleanup() ? p.poser->cleanup()->margins() : Eigen::VectorXd());
          },
          "pin_margins -> (J,) array: the margin used per bone (empty without cleanup).")
      .def_property_readonly(
          "last_cleanup",
          [](const PyRigPoser& p) -> py::object {
            if (!p.poser->cleanup()) return py::none();
            const scene::RigCleanupResult& r = p.poser->last_cleanup();
            py::dict d;
            d["iterations"] = r.iterations;
            d["converged"] = r.converged;
            d["volume_ratio"] = r.volume_ratio;
            d["edit_volume_ratio"] = r.edit_volume_ratio;
            d["pin_error"] = r.pin_error;
            d["total_ms"] = r.total_ms;
            return d;
          },
          "last_cleanup -> dict or None: iterations, converged, volume_ratio, edit_volume_ratio, pin_error, "
          "total_ms of the last pose's cleanup.");
}

void bind_gltf_files(py::module_& m) {
  m.def(
      "read_gltf",
      [](const std::filesystem::path& path, py::object meshes) {
        GltfReadOptions o;
        if (!meshes.is_none()) o.meshes = meshes.cast<std::vector<std::string>>();
        PyRig r;
        py::gil_scoped_release release;
        r.rig = std::make_shared<const GltfRig>(spinmotor::read_gltf(path, o));
        r.skin = std::make_shared<const RigSkin>(rig_skin(*r.rig));
        return r;
      },
      py::arg("path"), py::arg("meshes") = py::none(), R"doc(
read_gltf(path, meshes=None) -> Rig: a .gltf (data: URIs or side .bin) or .glb skinned character.
Input: path; meshes: node or mesh names to read (None: every skinned mesh of the scene).
Output: a Rig (the welded surface of every mesh read, joints, weights, morph targets, animations).
Errors: spinmotor.Error naming the file and the element; a file without a skinned mesh (e.g. a baked
animation: read it with read_gltf_morph_animation) or a mesh name that does not exist is an error.
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
        py::list pieces;
        for (const GltfMorphPiece& p : a.pieces)
          pieces.append(py::make_tuple(p.name, p.first_vertex, p.vertices));
        d["pieces"] = pieces;
        return d;
      },
      py::arg("path"), R"doc(
read_gltf_morph_animation(path) -> dict: a baked animation read back (Rig.bake, write_gltf_morph_animation,
`spinmotor rig pose ... --out x.glb`, or any glTF whose mesh nodes carry POSITION morph targets).

Input:   path (.gltf or .glb).
Output:  dict with V (n, 3) and F (m, 3): the base surface of every morph mesh, equal positions welded per
         mesh (the vertex order that was written); UV, FUV (or None); frames (k, n, 3): base + each
         target; times (k,): each target's key time in the weights animation; node_matrix (4, 4): the
         first mesh node's global matrix; name; pieces: (name, first_vertex, vertices) per mesh.
Errors:  spinmotor.Error naming the file and the element (no morph targets, a bad accessor, ...).
)doc");
}

void bind_procedural_rigs(py::module_& m) {
  const CharacterRigOptions cdef;
  m.def(
      "write_character_rig",
      [](const std::filesystem::path& path, const std::string& layout, double armature_scale,
         bool mesh_node_offset, bool morph_targets, bool scale_animation, double walk_degrees,
         int resolution) {
        CharacterRigOptions o;
        if (layout == "scene")
          o.layout = CharacterLayout::Scene;
        else if (layout == "mixamo")
          o.layout = CharacterLayout::Mixamo;
        else if (layout == "armature")
          o.layout = CharacterLayout::Armature;
        else
          throw Error("layout: '" + layout + "' (scene, mixamo or armature)");
        o.armature_scale = armature_scale;
        o.mesh_node_offset = mesh_node_offset;
        o.morph_targets = morph_targets;
        o.scale_animation = scale_animation;
        o.walk_degrees = walk_degrees;
        o.resolution = resolution;
        py::gil_scoped_release release;
        write_gltf_rig(path, character_rig(o));
      },
      py::arg("path"), py::arg("layout") = "scene", py::arg("armature_scale") = cdef.armature_scale,
      py::arg("mesh_node_offset") = cdef.mesh_node_offset, py::arg("morph_targets") = cdef.morph_targets,
      py::arg("scale_animation") = cdef.scale_animation, py::arg("walk_degrees") = cdef.walk_degrees,
      py::arg("resolution") = cdef.resolution, R"doc(
write_character_rig(path, layout="scene", armature_scale=0.01, mesh_node_offset=False, morph_targets=True,
                    scale_animation=True, walk_degrees=35, resolution=1) -> None
  Writes the project's procedural standing character (mesh/procedural_rig.hpp: seven separate meshes on one
  skin, morph targets on the head, animations "walk" and "squash") as .gltf/.glb, in the layout production
  files come in: scene (joints and meshes at the root), mixamo (a scaled, turned armature above
  centimetre joints, POSITION in scene units), armature (POSITION in the armature's own units);
  mesh_node_offset puts a transform on every skinned node (which glTF ignores).
Errors: spinmotor.Error for a bad layout or parameter, or a bad path extension.
)doc");
  m.def(
      "write_limb_rig",
      [](const std::filesystem::path& path, double radius, double length, int rings, int sides, int joints,
         double blend, double bend_degrees, double twist_degrees) {
        LimbRigOptions o{radius, length, rings, sides, joints, blend, bend_degrees, twist_degrees};
        py::gil_scoped_release release;
        write_gltf_rig(path, limb_rig(o));
      },
      py::arg("path"), py::arg("radius") = LimbRigOptions{}.radius,
      py::arg("length") = LimbRigOptions{}.length, py::arg("rings") = LimbRigOptions{}.rings,
      py::arg("sides") = LimbRigOptions{}.sides, py::arg("joints") = LimbRigOptions{}.joints,
      py::arg("blend") = LimbRigOptions{}.blend, py::arg("bend_degrees") = LimbRigOptions{}.bend_degrees,
      py::arg("twist_degrees") = LimbRigOptions{}.twist_degrees,
      R"doc(
write_limb_rig(path, radius=0.5, length=4, rings=96, sides=48, joints=3, blend=0.5, bend_degrees=60,
               twist_degrees=90) -> None: the procedural capsule limb (mesh/procedural_rig.hpp) as .gltf/.glb.
Errors: spinmotor.Error naming a bad parameter, or for a bad path extension.
)doc");
}

}  // namespace

void bind_rig_cleanup(py::module_& m);
py::object make_rig_cleanup(const Mesh& rest, const Eigen::SparseMatrix<double>& W,
                            const std::vector<Bone>& bones, const scene::RigCleanupOptions& o,
                            const scene::RigCleanup::VertexLabel& label);

namespace {

void bind_rig_bind_cleanup(py::module_& m) {
  py::class_<PyRig> cls = py::reinterpret_borrow<py::class_<PyRig>>(m.attr("Rig"));
  const scene::RigCleanupOptions def;
  cls.def(
      "bind_cleanup",
      [](const PyRig& r, double threshold, double margin, double pose_weight, const std::string& keep,
         int max_iterations, bool warm_start) {
        scene::RigCleanupOptions o;
        o.pin_threshold = threshold;
        o.pin_margin = margin;
        o.cleanup.pose_weight = pose_weight;
        o.cleanup.keep = parse_option<CleanupKeep>(keep, "keep: ");
        o.cleanup.max_iterations = max_iterations;
        o.cleanup.warm_start = warm_start;
        const std::shared_ptr<const GltfRig> rig = r.rig;
        return make_rig_cleanup(r.skin->rest, r.skin->rig.weights, r.skin->rig.skeleton, o,
                                [rig](Eigen::Index v) { return rig->vertex_label(v); });
      },
      py::arg("threshold") = def.pin_threshold, py::arg("margin") = def.pin_margin,
      py::arg("pose_weight") = def.cleanup.pose_weight,
      py::arg("keep") = std::string(option_name(def.cleanup.keep)),
      py::arg("max_iterations") = def.cleanup.max_iterations, py::arg("warm_start") = def.cleanup.warm_start,
      R"doc(
bind_cleanup(threshold=0.999, margin=-1, pose_weight=10, keep="auto", max_iterations=100, warm_start=False)
  -> RigCleanup: the rig cleanup of this rig's rest surface (scene coordinates) with the rig defaults (the
  same as `spinmotor rig pose --cleanup pinned`). Use .cleanup(rig.pose(t)) per frame.
Errors: spinmotor.Error for bad parameters.
)doc");
}

}  // namespace

void bind_rig(py::module_& m) {
  bind_rig_class(m);
  bind_rig_pose(m);
  bind_rig_bake(m);
  bind_rig_poser(m);
  bind_gltf_files(m);
  bind_rig_cleanup(m);
  bind_rig_bind_cleanup(m);
  bind_procedural_rigs(m);
}

}  // namespace spinmotor::python
