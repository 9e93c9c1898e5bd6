// Python bindings of the deform module: one base class spinmotor.Deformer holding an AnyDeformer
// (controls, vertices, pose), and one subclass per deformer whose constructor is the C++ bind() of
// the concrete type. Keyword defaults are read from each Options struct (never repeated here) and
// enum-valued options go through the option tables (parse_option).
#include <mutex>

#include "common.hpp"
#include "spinmotor/deform/any_deformer.hpp"
#include "spinmotor/deform/arap.hpp"
#include "spinmotor/deform/cage_deformer.hpp"
#include "spinmotor/deform/delta_mush.hpp"
#include "spinmotor/deform/direct_delta_mush.hpp"
#include "spinmotor/deform/ffd.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/deform/spline_deformer.hpp"
#include "spinmotor/deform/spline_ik.hpp"
#include "spinmotor/deform/surface_harmonic.hpp"

namespace spinmotor::python {

namespace {

/// A bound deformer. pose() releases the GIL; the mutex keeps one pose at a time per object
/// (deformer.hpp: pose is non-const and keeps per-frame scratch).
struct PyDeformer {
  AnyDeformer d;
  std::string type;
  std::unique_ptr<std::mutex> lock = std::make_unique<std::mutex>();
};
struct PySurfaceHarmonic : PyDeformer {};
struct PyArap : PyDeformer {};
struct PyFfd : PyDeformer {};
struct PyCage : PyDeformer {};
struct PySkin : PyDeformer {};
struct PySpline : PyDeformer {};
struct PySplineIk : PyDeformer {};
struct PyDeltaMush : PyDeformer {};
struct PyDirectDeltaMush : PyDeformer {};

/// Binds D with the GIL released (all inputs were converted before).
template <class Py, class D>
Py bind_released(const Mesh& rest, const Rig& rig, const typename D::Options& o, const char* type) {
  Py p;
  p.type = type;
  {
    py::gil_scoped_release release;
    p.d = D::bind(rest, rig, o);
  }
  return p;
}

/// handles: list of (name, indices) pairs or a dict {name: indices}.
std::vector<Handle> to_handles(py::handle obj) {
  std::vector<Handle> out;
  auto add = [&](py::handle name, py::handle idx, std::size_t k) {
    if (!py::isinstance<py::str>(name))
      throw Error("handles[" + std::to_string(k) + "]: the name must be a str");
    Handle h;
    h.name = name.cast<std::string>();
    h.vertices = to_int_vector(idx, ("handle '" + h.name + "' indices").c_str());
    out.push_back(std::move(h));
  };
  if (py::isinstance<py::dict>(obj)) {
    std::size_t k = 0;
    for (auto item : py::reinterpret_borrow<py::dict>(obj)) add(item.first, item.second, k++);
    return out;
  }
  if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj))
    throw Error("handles: expected a list of (name, indices) pairs or a dict {name: indices}");
  const auto seq = py::reinterpret_borrow<py::sequence>(obj);
  for (std::size_t k = 0; k < seq.size(); ++k) {
    py::object item = seq[k];
    if (!py::isinstance<py::sequence>(item) || py::isinstance<py::str>(item) || py::len(item) != 2)
      throw Error("handles[" + std::to_string(k) + "]: expected a (name, indices) pair");
    add(item[py::int_(0)], item[py::int_(1)], k);
  }
  return out;
}

/// skeleton: list of dicts {name, parent=-1, head, tail, rest=Motor()} (or tuples in that order).
std::vector<Bone> to_skeleton(py::handle obj) {
  if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj))
    throw Error("skeleton: expected a list of bones (dicts with name, parent, head, tail[, rest])");
  std::vector<Bone> out;
  const auto seq = py::reinterpret_borrow<py::sequence>(obj);
  for (std::size_t k = 0; k < seq.size(); ++k) {
    py::object item = seq[k];
    const std::string where = "skeleton[" + std::to_string(k) + "]";
    py::object name, parent, head, tail, rest;
    if (py::isinstance<py::dict>(item)) {
      const auto d = py::reinterpret_borrow<py::dict>(item);
      for (auto kv : d) {
        const std::string key = py::str(kv.first);
        if (key != "name" && key != "parent" && key != "head" && key != "tail" && key != "rest")
          throw Error(where + ": unknown key '" + key + "' (one of: name, parent, head, tail, rest)");
      }
      if (!d.contains("name") || !d.contains("head") || !d.contains("tail"))
        throw Error(where + ": needs name, head and tail");
      name = d["name"];
      head = d["head"];
      tail = d["tail"];
      parent = d.contains("parent") ? py::object(d["parent"]) : py::object(py::int_(-1));
      rest = d.contains("rest") ? py::object(d["rest"]) : py::object(py::none());
    } else if (py::isinstance<py::sequence>(item) && !py::isinstance<py::str>(item) &&
               (py::len(item) == 4 || py::len(item) == 5)) {
      name = item[py::int_(0)];
      parent = item[py::int_(1)];
      head = item[py::int_(2)];
      tail = item[py::int_(3)];
      rest = py::len(item) == 5 ? py::object(item[py::int_(4)]) : py::object(py::none());
    } else {
      throw Error(where +
                  ": expected a dict {name, parent, head, tail, rest} or a tuple (name, parent, head, tail)");
    }
    Bone b;
    if (!py::isinstance<py::str>(name)) throw Error(where + ": name must be a str");
    b.name = name.cast<std::string>();
    if (!py::isinstance<py::int_>(parent)) throw Error(where + ": parent must be an int (-1 for a root)");
    b.parent = parent.cast<int>();
    b.head = to_vector(head, (where + " head").c_str(), 3);
    b.tail = to_vector(tail, (where + " tail").c_str(), 3);
    if (!rest.is_none()) {
      if (!py::isinstance<ga::Mot>(rest)) throw Error(where + ": rest must be a spinmotor.Motor");
      b.rest = rest.cast<ga::Mot>();
    }
    out.push_back(std::move(b));
  }
  return out;
}

Eigen::SparseMatrix<double> to_weights(py::handle obj, Eigen::Index n, std::size_t bones) {
  const Eigen::MatrixXd W = to_matrix(obj, "weights", n, static_cast<Eigen::Index>(bones));
  return W.sparseView();
}

py::list controls_list(const AnyDeformer& d) {
  py::list l;
  for (const Control& c : d.controls()) l.append(py::make_tuple(c.name, to_numpy(Eigen::VectorXd(c.anchor))));
  return l;
}

constexpr const char* kPoseDoc = R"doc(
pose(motors) -> V

Inputs:  motors: list of unit spinmotor.Motor, one per control (in the order of .controls), relative
         to the rest pose (all identities reproduce the rest mesh).
Output:  (n, 3) float64 deformed positions: a column-major (Fortran-ordered) array that owns the
         C++ result's memory (no copy; a new array per call).
Errors:  spinmotor.Error for a wrong count ("expected k motors (one per control), got m") or a
         non-finite motor (naming the control); numerical Error when the deformer's solve fails.
The GIL is released during the pose; one pose at a time per object.
)doc";

}  // namespace

void bind_deform(py::module_& m) {
  py::class_<PyDeformer>(m, "Deformer", R"doc(
A bound deformer (the C++ Deformer concept behind AnyDeformer): every precomputation happened in the
constructor (bind); pose() is the per-frame work.

Attributes:
  controls: list of (name, anchor) pairs, anchor a (3,) rest point, in pose order
  vertices: number of mesh vertices
  type:     the C++ class name
)doc")
      .def_property_readonly(
          "controls", [](const PyDeformer& p) { return controls_list(p.d); },
          "controls -> list of (name, anchor (3,)) pairs in pose order: what pose() takes one motor for.")
      .def_property_readonly(
          "vertices", [](const PyDeformer& p) { return static_cast<long long>(p.d.vertices()); },
          "vertices -> int: the number of mesh vertices (rows of pose()'s output).")
      .def_property_readonly(
          "type", [](const PyDeformer& p) { return p.type; }, "type -> str: the C++ class name.")
      .def(
          "pose",
          [](PyDeformer& p, py::object motors) {
            const std::vector<ga::Mot> ms = to_motors(motors, "motors");
            Eigen::MatrixXd V;
            {
              py::gil_scoped_release release;
              std::lock_guard<std::mutex> guard(*p.lock);
              p.d.pose(ms, V);
            }
            return to_numpy_owned(std::move(V));  // no copy: the array takes the matrix
          },
          py::arg("motors"), kPoseDoc)
      .def(
          "_time_pose",
          [](PyDeformer& p, py::object motors, int repeats) {
            // Private (bench/python_overhead.py): the C++ call alone, as a C++ caller makes it per
            // frame (motors converted once, the output matrix reused).
            const std::vector<ga::Mot> ms = to_motors(motors, "motors");
            Eigen::MatrixXd V;
            py::gil_scoped_release release;
            std::lock_guard<std::mutex> guard(*p.lock);
            return time_calls(repeats, [&] { p.d.pose(ms, V); });
          },
          py::arg("motors"), py::arg("repeats") = 5)
      .def("__repr__", [](const PyDeformer& p) {
        return "<spinmotor." + p.type + " " + std::to_string(p.d.vertices()) + " vertices, " +
               std::to_string(p.d.controls().size()) + " controls>";
      });

  // ---- SurfaceHarmonicDeformer -------------------------------------------------------------------
  {
    using D = SurfaceHarmonicDeformer;
    const D::Options def{};
    py::class_<PySurfaceHarmonic, PyDeformer>(m, "SurfaceHarmonicDeformer", R"doc(
Surface-harmonic motor blending (CGA paper III.B): harmonic coordinates of the handles on the surface,
motors blended per vertex.

SurfaceHarmonicDeformer(V, F, handles, weights="mean-value", blend="log")
  V (n, 3), F (m, 3); handles: list of (name, indices) or dict {name: indices}, disjoint, >= 1;
  weights: "mean-value" | "cotan"; blend: "log" | "pivot-log" | "dlb".
  One control per handle (anchored at its centroid); handle vertices follow their motor exactly.
Errors: spinmotor.Error for bad arrays, bad handles (naming the handle and vertex), a component
  without a handle, a degenerate face, an unknown option name (listing the choices).
)doc")
        .def(py::init([](py::object V, py::object F, py::object handles, const std::string& weights,
                         const std::string& blend) {
               const Mesh rest = to_mesh(V, F);
               Rig rig;
               rig.handles = to_handles(handles);
               D::Options o;
               o.weights = parse_option<HarmonicWeights>(weights, "weights: ");
               o.blend = parse_option<ga::Blend>(blend, "blend: ");
               return bind_released<PySurfaceHarmonic, D>(rest, rig, o, "SurfaceHarmonicDeformer");
             }),
             py::arg("V"), py::arg("F"), py::arg("handles"),
             py::arg("weights") = std::string(option_name(def.weights)),
             py::arg("blend") = std::string(option_name(def.blend)));
  }

  // ---- ArapDeformer ------------------------------------------------------------------------------
  {
    using D = ArapDeformer;
    const D::Options def{};
    py::class_<PyArap, PyDeformer>(m, "ArapDeformer", R"doc(
As-rigid-as-possible deformation (Sorkine & Alexa 2007): handle vertices are placed by their motors,
the free vertices solved by local/global iterations on a factorization made at bind time.

ArapDeformer(V, F, handles, energy="spokes-and-rims", clamp_negative_weights=False, iterations=100,
             tolerance=1e-6, initial="harmonic")
  energy: "spokes" | "spokes-and-rims"; initial: "rest" | "harmonic" | "previous".
Errors: as SurfaceHarmonicDeformer; numerical Error if the factorization fails.
)doc")
        .def(py::init([](py::object V, py::object F, py::object handles, const std::string& energy,
                         bool clamp_negative_weights, int iterations, double tolerance,
                         const std::string& initial) {
               const Mesh rest = to_mesh(V, F);
               Rig rig;
               rig.handles = to_handles(handles);
               D::Options o;
               o.energy = parse_option<ArapEnergy>(energy, "energy: ");
               o.clamp_negative_weights = clamp_negative_weights;
               o.iterations = iterations;
               o.tolerance = tolerance;
               o.initial = parse_option<ArapInitial>(initial, "initial: ");
               return bind_released<PyArap, D>(rest, rig, o, "ArapDeformer");
             }),
             py::arg("V"), py::arg("F"), py::arg("handles"),
             py::arg("energy") = std::string(option_name(def.energy)),
             py::arg("clamp_negative_weights") = def.clamp_negative_weights,
             py::arg("iterations") = def.iterations, py::arg("tolerance") = def.tolerance,
             py::arg("initial") = std::string(option_name(def.initial)));
  }

  // ---- FfdDeformer -------------------------------------------------------------------------------
  {
    using D = FfdDeformer;
    const D::Options def{};
    py::class_<PyFfd, PyDeformer>(m, "FfdDeformer", R"doc(
Free-form deformation: a lattice of controls around the mesh (the rig is not read; F is optional).

FfdDeformer(V, F=None, lattice=(4, 4, 4), basis="bezier", degree=3, mode="motor", blend="log",
            box=None, margin=0.05)
  basis: "bezier" | "bspline"; mode: "motor" | "position"; blend (motor mode): "log" | "dlb";
  box: ((xmin, ymin, zmin), (xmax, ymax, zmax)) or None for the bounding box grown by margin.
  Controls "ffd[a,b,c]" at the lattice points.
Errors: spinmotor.Error for bad arrays, a lattice below the basis' order, an unknown name (listing the
valid ones), an empty box.
)doc")
        .def(py::init([](py::object V, py::object F, std::array<int, 3> lattice, const std::string& basis,
                         int degree, const std::string& mode, const std::string& blend, py::object box,
                         double margin) {
               Mesh rest;
               rest.V = to_points(V, "V");
               if (!F.is_none()) rest.F = to_faces(F, "F", rest.V.rows());
               D::Options o;
               o.lattice = lattice;
               o.basis = parse_option<D::Basis>(basis, "basis: ");
               o.degree = degree;
               o.mode = parse_option<ControlMode>(mode, "mode: ");
               o.blend = parse_option<ga::Blend>(blend, "blend: ");
               if (!box.is_none()) {
                 const Eigen::MatrixXd B = to_matrix(box, "box", 2, 3);
                 o.box = Eigen::AlignedBox3d(B.row(0).transpose(), B.row(1).transpose());
               }
               o.margin = margin;
               return bind_released<PyFfd, D>(rest, Rig{}, o, "FfdDeformer");
             }),
             py::arg("V"), py::arg("F") = py::none(), py::arg("lattice") = def.lattice,
             py::arg("basis") = std::string(option_name(def.basis)), py::arg("degree") = def.degree,
             py::arg("mode") = std::string(option_name(def.mode)),
             py::arg("blend") = std::string(option_name(def.blend)), py::arg("box") = py::none(),
             py::arg("margin") = def.margin);
  }

  // ---- CageDeformer ------------------------------------------------------------------------------
  {
    using D = CageDeformer;
    const D::Options def{};
    py::class_<PyCage, PyDeformer>(m, "CageDeformer", R"doc(
Cage deformation: the mesh inside a closed, outward-oriented cage mesh; one control per cage vertex
("cage[j]").

CageDeformer(V, F, cage=(CV, CF), coordinates="harmonic", grid=64, mode="motor", blend="log")
  coordinates: "harmonic" | "mean-value"; mode: "motor" | "position"; blend: "log" | "pivot-log" | "dlb".
Errors: spinmotor.Error for a bad cage (open, misoriented) or a mesh vertex outside the cage.
)doc")
        .def(py::init([](py::object V, py::object F, py::object cage, const std::string& coordinates,
                         int grid, const std::string& mode, const std::string& blend) {
               const Mesh rest = to_mesh(V, F);
               if (!py::isinstance<py::sequence>(cage) || py::len(cage) != 2)
                 throw Error("cage: expected a (CV, CF) pair or a spinmotor.Mesh");
               Rig rig;
               rig.cage = to_mesh(cage[py::int_(0)], cage[py::int_(1)], true, "cage V", "cage F");
               D::Options o;
               o.coordinates = parse_option<D::Coordinates>(coordinates, "coordinates: ");
               o.grid = grid;
               o.mode = parse_option<ControlMode>(mode, "mode: ");
               o.blend = parse_option<ga::Blend>(blend, "blend: ");
               return bind_released<PyCage, D>(rest, rig, o, "CageDeformer");
             }),
             py::arg("V"), py::arg("F"), py::arg("cage"),
             py::arg("coordinates") = std::string(option_name(def.coordinates)), py::arg("grid") = def.grid,
             py::arg("mode") = std::string(option_name(def.mode)),
             py::arg("blend") = std::string(option_name(def.blend)));
  }

  // ---- skeleton deformers: SkinDeformer, DeltaMushDeformer, DirectDeltaMushDeformer ---------------
  constexpr const char* kSkeletonDoc =
      "  skeleton: list of bones, each a dict {name, parent=-1, head, tail, rest=Motor()} or a tuple\n"
      "            (name, parent, head, tail[, rest]); weights: (n, B) dense non-negative array, columns in\n"
      "            bone order, every row with a positive entry (<= 4 largest kept, renormalised).\n"
      "  One control per bone (anchored at its head); pose() takes the posed world frames F_j.\n"
      "Errors: spinmotor.Error for a bad skeleton (naming the bone), weights of the wrong shape, negative,\n"
      "non-finite or with an all-zero row (naming the row), an unknown blend (listing the valid ones).\n";
  {
    using D = SkinDeformer;
    const D::Options def{};
    py::class_<PySkin, PyDeformer>(
        m, "SkinDeformer",
        (std::string("Skinning with motors.\n\nSkinDeformer(V, F, skeleton, weights, blend=\"") +
         std::string(option_name(def.blend)) +
         "\")\n  blend: \"lbs\" | \"dlb\" | \"log\" | \"pivot-log\".\n" + kSkeletonDoc)
            .c_str())
        .def(py::init([](py::object V, py::object F, py::object skeleton, py::object weights,
                         const std::string& blend) {
               const Mesh rest = to_mesh(V, F);
               Rig rig;
               rig.skeleton = to_skeleton(skeleton);
               rig.weights = to_weights(weights, rest.V.rows(), rig.skeleton.size());
               D::Options o;
               o.blend = parse_option<SkinBlend>(blend, "blend: ");
               return bind_released<PySkin, D>(rest, rig, o, "SkinDeformer");
             }),
             py::arg("V"), py::arg("F"), py::arg("skeleton"), py::arg("weights"),
             py::arg("blend") = std::string(option_name(def.blend)));
  }
  {
    using D = DeltaMushDeformer;
    const D::Options def{};
    py::class_<PyDeltaMush, PyDeformer>(
        m, "DeltaMushDeformer",
        (std::string(
             "Delta Mush (Mancewicz et al. 2014) over a skin.\n\nDeltaMushDeformer(V, F, skeleton, weights, "
             "iterations=10, step=0.5, blend=\"lbs\")\n") +
         kSkeletonDoc)
            .c_str())
        .def(py::init([](py::object V, py::object F, py::object skeleton, py::object weights, int iterations,
                         double step, const std::string& blend) {
               const Mesh rest = to_mesh(V, F);
               Rig rig;
               rig.skeleton = to_skeleton(skeleton);
               rig.weights = to_weights(weights, rest.V.rows(), rig.skeleton.size());
               D::Options o;
               o.iterations = iterations;
               o.step = step;
               o.blend = parse_option<SkinBlend>(blend, "blend: ");
               return bind_released<PyDeltaMush, D>(rest, rig, o, "DeltaMushDeformer");
             }),
             py::arg("V"), py::arg("F"), py::arg("skeleton"), py::arg("weights"),
             py::arg("iterations") = def.iterations, py::arg("step") = def.step,
             py::arg("blend") = std::string(option_name(def.blend)));
  }
  {
    using D = DirectDeltaMushDeformer;
    const D::Options def{};
    py::class_<PyDirectDeltaMush, PyDeformer>(
        m, "DirectDeltaMushDeformer",
        (std::string(
             "Direct Delta Mush (Le & Lewis 2019).\n\nDirectDeltaMushDeformer(V, F, skeleton, weights, "
             "iterations=10, tau=1.0, prune=1e-7)\n") +
         kSkeletonDoc)
            .c_str())
        .def(py::init([](py::object V, py::object F, py::object skeleton, py::object weights, int iterations,
                         double tau, double prune) {
               const Mesh rest = to_mesh(V, F);
               Rig rig;
               rig.skeleton = to_skeleton(skeleton);
               rig.weights = to_weights(weights, rest.V.rows(), rig.skeleton.size());
               D::Options o;
               o.iterations = iterations;
               o.tau = tau;
               o.prune = prune;
               return bind_released<PyDirectDeltaMush, D>(rest, rig, o, "DirectDeltaMushDeformer");
             }),
             py::arg("V"), py::arg("F"), py::arg("skeleton"), py::arg("weights"),
             py::arg("iterations") = def.iterations, py::arg("tau") = def.tau, py::arg("prune") = def.prune);
  }

  // ---- SplineDeformer, SplineIkDeformer ------------------------------------------------------------
  {
    using D = SplineDeformer;
    const D::Options def{};
    py::class_<PySpline, PyDeformer>(m, "SplineDeformer", R"doc(
Spline-aligned deformation (CGA paper III.C): a harmonic parameter from handle `from` (0) to `to` (1)
and key motors blended along it.

SplineDeformer(V, F, handles=[(from_name, idx), (to_name, idx)], basis="bspline", degree=3, keys=4,
               weights="mean-value", key_names=None)
  One control per key ("key0".. or key_names).
Errors: spinmotor.Error for bad arrays, bad handles (naming them), keys below the basis' order, an
unknown name (listing the valid ones); numerical Error if the harmonic solve fails.
)doc")
        .def(py::init([](py::object V, py::object F, py::object handles, const std::string& basis, int degree,
                         int keys, const std::string& weights, py::object key_names) {
               const Mesh rest = to_mesh(V, F);
               Rig rig;
               rig.handles = to_handles(handles);
               D::Options o;
               o.basis = parse_option<SplineBasis>(basis, "basis: ");
               o.degree = degree;
               o.keys = keys;
               o.weights = parse_option<HarmonicWeights>(weights, "weights: ");
               if (!key_names.is_none()) o.key_names = key_names.cast<std::vector<std::string>>();
               return bind_released<PySpline, D>(rest, rig, o, "SplineDeformer");
             }),
             py::arg("V"), py::arg("F"), py::arg("handles"),
             py::arg("basis") = std::string(option_name(def.basis)), py::arg("degree") = def.degree,
             py::arg("keys") = def.keys, py::arg("weights") = std::string(option_name(def.weights)),
             py::arg("key_names") = py::none());
  }
  {
    using D = SplineIkDeformer;
    const D::Options def{};
    const IkChain ikdef{};
    py::class_<PySplineIk, PyDeformer>(m, "SplineIkDeformer", R"doc(
Spline deformation driven by inverse kinematics (CGA paper III.C, Fig. 5): FABRIK solves the joint
chain toward the target, its B-spline fit drives the spline deformer.

SplineIkDeformer(V, F, handles=[from, to], chain, target, tolerance=1e-4, iterations=50, controls=5,
                 degree=3, weights="mean-value", warm_start=False)
  chain: (k, 3) rest joint positions (k >= 2, root first); target: (3,) rest target.
  One control "ik.target" (its motor carries the rest target to the frame's target).
Errors: spinmotor.Error as SplineDeformer, and for a chain of fewer than 2 joints or a non-finite
target.
)doc")
        .def(py::init([](py::object V, py::object F, py::object handles, py::object chain, py::object target,
                         double tolerance, int iterations, int controls, int degree,
                         const std::string& weights, bool warm_start) {
               const Mesh rest = to_mesh(V, F);
               Rig rig;
               rig.handles = to_handles(handles);
               IkChain ik;
               ik.chain = to_matrix(chain, "chain", -1, 3);
               ik.target = to_vector(target, "target", 3);
               ik.tolerance = tolerance;
               ik.iterations = iterations;
               rig.ik = ik;
               D::Options o;
               o.controls = controls;
               o.degree = degree;
               o.weights = parse_option<HarmonicWeights>(weights, "weights: ");
               o.warm_start = warm_start;
               return bind_released<PySplineIk, D>(rest, rig, o, "SplineIkDeformer");
             }),
             py::arg("V"), py::arg("F"), py::arg("handles"), py::arg("chain"), py::arg("target"),
             py::arg("tolerance") = ikdef.tolerance, py::arg("iterations") = ikdef.iterations,
             py::arg("controls") = def.controls, py::arg("degree") = def.degree,
             py::arg("weights") = std::string(option_name(def.weights)),
             py::arg("warm_start") = def.warm_start);
  }
}

}  // namespace spinmotor::python
