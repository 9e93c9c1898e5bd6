// Python bindings of the spin module: ConformalSnap, SpinTransform, Willmore flow, curvature fairing
// and extrusion, the Dirac spectrum. Binds and solves release the GIL; progress callbacks take it back
// for the call (an exception raised in a callback ends the flow and propagates).
#include <algorithm>
#include <memory>
#include <mutex>

#include "common.hpp"
#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/rig_pins.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/curvature_spin_flow.hpp"
#include "spinmotor/spin/dirac_spectrum.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"
#include "spinmotor/spin/spin_transform.hpp"
#include "spinmotor/spin/willmore_flow.hpp"

namespace spinmotor::python {

namespace {

struct PySnap {
  std::unique_ptr<ConformalSnap> snap;
  // mode "pinned": the cleanup bound for the last (pins, keep) asked, rebound when they change
  std::unique_ptr<PinnedCleanup> pinned;
  Eigen::VectorXi pinned_pins;  // sorted, unique
  CleanupKeep pinned_keep = CleanupKeep::Auto;
  std::unique_ptr<std::mutex> lock = std::make_unique<std::mutex>();
};
struct PySpin {
  std::unique_ptr<SpinTransform> st;
  std::unique_ptr<std::mutex> lock = std::make_unique<std::mutex>();
};

/// A Python callable (or None) as a callback (step, steps), called with the GIL held.
std::function<void(int, int)> to_progress(const py::object& progress) {
  if (progress.is_none()) return {};
  if (!PyCallable_Check(progress.ptr())) throw Error("progress: expected a callable (step, total) or None");
  return [&progress](int step, int steps) {  // `progress` outlives the solve (caller's frame)
    py::gil_scoped_acquire gil;
    progress(step, steps);
  };
}

py::dict snap_dict(const ConformalSnapResult& r) {
  py::dict d;
  d["V"] = to_numpy(r.V);
  d["rho"] = to_numpy(r.rho);
  d["mu"] = to_numpy(r.mu);
  d["lambda"] = to_numpy(r.lambda);
  d["eigenvalue"] = r.eigenvalue;
  d["iterations"] = r.iterations;
  d["residual"] = r.residual;
  d["collapsed_faces"] = static_cast<long long>(r.collapsed_faces);
  d["alignment_scale"] = r.alignment.scale;
  py::dict t;
  t["similarity_fit"] = r.timings.similarity_fit;
  t["bind"] = r.timings.bind;
  t["eigen"] = r.timings.eigen;
  t["poisson"] = r.timings.poisson;
  t["total"] = r.timings.total();
  d["timings_ms"] = t;
  return d;
}

py::dict flow_dict(const CurvatureFlow& r) {
  py::dict d;
  d["V"] = to_numpy(r.V);
  d["willmore"] = r.willmore;
  d["closure"] = r.closure;
  return d;
}

/// A keyword given as a Python object (None = not given) as a number / string; Error naming it otherwise.
template <class T>
T as(const py::object& o, const char* name, const char* expected) {
  try {
    return o.cast<T>();
  } catch (const py::cast_error&) {
    throw Error(std::string(name) + ": expected " + expected + ", got " +
                std::string(py::str(o.get_type().attr("__name__"))));
  }
}

/// ConformalSnap's mode "pinned", full=True (the keys of PinnedCleanup.cleanup(full=True)).
py::dict cleanup_dict(const PinnedCleanupResult& r, const Eigen::MatrixXd& V) {
  py::dict d;
  d["V"] = to_numpy(V);
  d["iterations"] = r.iterations;
  d["converged"] = r.converged;
  d["all_pinned"] = r.all_pinned;
  d["keep"] = std::string(option_name(r.kept));
  d["measure_ratio"] = r.measure_ratio();
  d["edit_measure_ratio"] = r.rest_measure != 0 ? r.edit_measure / r.rest_measure : 1.0;
  d["pin_error"] = r.pin_error;
  d["energy"] = r.energy;
  d["total_ms"] = r.total_ms;
  return d;
}

CurvatureSpinOptions curvature_options(double alpha, double beta, double area_epsilon, bool exactness) {
  return CurvatureSpinOptions{
      .alpha = alpha, .beta = beta, .area_epsilon = area_epsilon, .exactness = exactness};
}

}  // namespace

void bind_spin(py::module_& m) {
  // ---- PinnedCleanup (the pose-keeping cleanup) ----------------------------------------------------
  {
    const PinnedCleanupOptions def;
    py::class_<PyCleanup>(m, "PinnedCleanup", R"doc(
The pose-keeping conformal cleanup (spin/pinned_cleanup.hpp): the pinned vertices stay exactly where the
edit put them; the others are placed as conformally as possible (low quasi-conformal error Q against the
rest mesh) at the rest volume (closed meshes) or area (open ones).

PinnedCleanup(V, F, pins, keep="auto", max_iterations=100, tolerance=1e-4, pose_weight=0.0,
              attraction=None, warm_start=False)
  V (n, 3), F (m, 3): the rest mesh; pins: vertex indices (order and repeats do not matter). keep: auto
  (volume if closed, else area), volume, area or none. pose_weight: gamma >= 0 of the pose attraction
  that holds the free vertices near the edit (0: the pins only); attraction: n weights in [0, 1] per
  vertex (None: all 1), e.g. pin_attraction_from_weights(W). warm_start: for animations cleaned in
  time order, start each call from the previous call's correction (reset() forgets it). All
  factorization happens here, once.
  For a glTF rig, Rig.bind_cleanup() binds one with the rig defaults.
Errors: spinmotor.Error for empty or out-of-range pins, a connected component without a pin (named),
keep="volume" on an open mesh, a degenerate rest face, a negative pose_weight, attraction weights of
the wrong count or outside [0, 1]; numerical Error if the factorization fails.
)doc")
        .def(py::init([](py::object V, py::object F, py::object pins, const std::string& keep,
                         int max_iterations, double tolerance, double pose_weight, py::object attraction,
                         bool warm_start) {
               const Mesh rest = to_mesh(V, F);
               const Eigen::VectorXi p = to_int_vector(pins, "pins");
               const Eigen::VectorXd a = attraction.is_none()
                                             ? Eigen::VectorXd()
                                             : to_vector(attraction, "attraction", rest.V.rows());
               PinnedCleanupOptions o;
               o.keep = parse_option<CleanupKeep>(keep, "keep: ");
               o.max_iterations = max_iterations;
               o.tolerance = tolerance;
               o.pose_weight = pose_weight;
               o.warm_start = warm_start;
               PyCleanup c;
               py::gil_scoped_release release;
               c.cleanup = std::make_unique<PinnedCleanup>(PinnedCleanup::bind(rest, p, o, a));
               return c;
             }),
             py::arg("V"), py::arg("F"), py::arg("pins"),
             py::arg("keep") = std::string(option_name(def.keep)),
             py::arg("max_iterations") = def.max_iterations, py::arg("tolerance") = def.tolerance,
             py::arg("pose_weight") = def.pose_weight, py::arg("attraction") = py::none(),
             py::arg("warm_start") = def.warm_start)
        .def(
            "reset",
            [](PyCleanup& c) {
              std::lock_guard<std::mutex> guard(*c.lock);
              c.cleanup->reset();
            },
            "reset() -> None: forget the previous frame (warm_start): the next cleanup starts afresh.")
        .def(
            "cleanup",
            [](PyCleanup& c, py::object V_edit, bool full) -> py::object {
              const Eigen::MatrixXd E = to_points(V_edit, "V_edit");
              Eigen::MatrixXd V;
              PinnedCleanupResult r;
              {
                py::gil_scoped_release release;
                std::lock_guard<std::mutex> guard(*c.lock);
                r = c.cleanup->cleanup(E, V);
              }
              if (!full) return to_numpy(V);
              return cleanup_dict(r, V);
            },
            py::arg("V_edit"), py::arg("full") = false, R"doc(
cleanup(V_edit, full=False) -> V (n, 3), or with full=True a dict: V, iterations, converged, all_pinned,
keep, measure_ratio (kept volume or area / rest), edit_measure_ratio, pin_error, energy (per iteration),
total_ms. V_edit (n, 3): the edit, same connectivity as the rest mesh. No factorization per call.
)doc")
        .def_property_readonly(
            "pins",
            [](const PyCleanup& c) {
              const Eigen::VectorXi& p = c.cleanup->pins();
              return std::vector<int>(p.data(), p.data() + p.size());
            },
            "pins -> list of int: the pinned vertices, sorted, without repeats.")
        .def_property_readonly(
            "bind_ms", [](const PyCleanup& c) { return c.cleanup->bind_ms(); },
            "bind_ms -> float: the time of the bind (constructor) in milliseconds.");
    m.def(
        "pins_from_weights",
        [](py::object V, py::object W, double threshold, double margin) {
          const Eigen::MatrixXd P = to_points(V, "V");
          const Eigen::MatrixXd Wm = to_matrix(W, "W", P.rows(), -1);
          const Eigen::VectorXi p = pins_from_weights(P, Wm, threshold, margin);
          return std::vector<int>(p.data(), p.data() + p.size());
        },
        py::arg("V"), py::arg("W"), py::arg("threshold") = kRigidWeight, py::arg("margin") = 0.0, R"doc(
pins_from_weights(V, W, threshold=0.999, margin=0.0) -> pins: the vertices whose dominant skin weight
(W: n×B) is at least `threshold` and that lie farther than `margin` from every vertex below it (the
bones' rigid parts, each joint left room). Errors: spinmotor.Error naming the bad row or parameter.
)doc");
    m.def(
        "pin_attraction_from_weights",
        [](py::object W, double threshold, double low) {
          return to_numpy(pin_attraction_from_weights(to_matrix(W, "W", -1, -1), threshold, low));
        },
        py::arg("W"), py::arg("threshold") = kRigidWeight, py::arg("low") = kAttractionLow, R"doc(
pin_attraction_from_weights(W, threshold=0.999, low=0.5) -> a (n,): the per-vertex weights of the
cleanup's pose attraction from skin weights W (n×B): smoothstep of the dominant weight between `low`
(0: the middle of a joint, left free) and `threshold` (1: rigid parts). Errors: spinmotor.Error naming
the bad row or parameter.
)doc");
  }

  // ---- ConformalSnap -------------------------------------------------------------------------------
  {
    const ConformalSnapOptions def{};
    const PinnedCleanupOptions cleanup_def{};
    py::class_<PySnap>(m, "ConformalSnap", R"doc(
The conformal snap of an edit (spin/conformal_snap.hpp, `spinmotor snap`) in its three modes: free, the
spin transformation of the rest mesh nearest to the edit (optimal rho, Crane et al. 2011 section 7.2),
blended with the edit by `tradeoff` and aligned to it; shape, the extrusion toward the edit's curvature
(Le Folgoc et al. 2019); pinned, the pose-keeping cleanup (pins stay where the edit put them).

ConformalSnap(V, F, boundary_tangents=True, rho_smoothing=0, tolerance=1e-10, iterations=50,
              problem="standard", alignment="similarity")
  V (n, 3), F (m, 3): the rest mesh, a connected oriented manifold without degenerate faces or
  unreferenced vertices. The free mode's bind (ordering, symbolic analysis, Laplacian factor) happens
  here, once. boundary_tangents: open meshes prescribe the edit's boundary tangents; rho_smoothing:
  passes of rho averaging (for creased edits); tolerance / iterations: the inverse iteration; problem:
  standard (eq. 7) or generalized (eq. 6, closed meshes); alignment: placement onto the edit,
  similarity, translation or none (option_values("problem"), option_values("align")).
Errors: spinmotor.Error naming the first offending element or the bad option value (listing the valid
ones); numerical Error if a factorization fails.
)doc")
        .def(py::init([](py::object V, py::object F, bool boundary_tangents, int rho_smoothing,
                         double tolerance, int iterations, const std::string& problem,
                         const std::string& alignment) {
               const Mesh rest = to_mesh(V, F);
               ConformalSnapOptions o;
               o.boundary_tangents = boundary_tangents;
               o.rho_smoothing = rho_smoothing;
               o.tolerance = tolerance;
               o.iterations = iterations;
               o.problem = parse_option<SpinEigenProblem>(problem, "problem: ");
               o.alignment = parse_option<SnapAlignment>(alignment, "alignment: ");
               PySnap p;
               py::gil_scoped_release release;
               p.snap = std::make_unique<ConformalSnap>(rest, o);
               return p;
             }),
             py::arg("V"), py::arg("F"), py::arg("boundary_tangents") = def.boundary_tangents,
             py::arg("rho_smoothing") = def.rho_smoothing, py::arg("tolerance") = def.tolerance,
             py::arg("iterations") = def.iterations,
             py::arg("problem") = std::string(option_name(def.problem)),
             py::arg("alignment") = std::string(option_name(def.alignment)))
        .def(
            "snap",
            [def, cleanup_def](PySnap& p, py::object V_edit, py::object tradeoff, bool full,
                               py::object mode_obj, py::object pins_obj, py::object keep_obj,
                               py::object steps_obj, py::object area_obj) -> py::object {
              const Mesh& rest = p.snap->rest();
              const Eigen::MatrixXd E = to_points(V_edit, "V_edit");
              if (E.rows() != rest.V.rows())
                throw Error("V_edit: has " + std::to_string(E.rows()) + " vertices, the rest mesh " +
                            std::to_string(rest.V.rows()));
              // The mode: as `spinmotor snap`, pinned when pins are given without a mode, else free.
              const SnapMode mode =
                  !mode_obj.is_none()
                      ? parse_option<SnapMode>(as<std::string>(mode_obj, "mode", "a str"), "mode: ")
                      : (pins_obj.is_none() ? SnapMode::Free : SnapMode::Pinned);
              const std::string mname(option_name(mode));
              auto only = [&](const py::object& o, const char* what, SnapMode owner) {
                if (!o.is_none() && mode != owner)
                  throw Error(std::string(what) + ": belongs to mode \"" + std::string(option_name(owner)) +
                              "\", not \"" + mname + "\"");
              };
              only(tradeoff, "tradeoff", SnapMode::Free);
              only(pins_obj, "pins", SnapMode::Pinned);
              only(keep_obj, "keep", SnapMode::Pinned);
              only(steps_obj, "steps", SnapMode::Shape);
              only(area_obj, "area_constraint", SnapMode::Shape);
              if (mode == SnapMode::Free) {
                const double t =
                    tradeoff.is_none() ? def.tradeoff : as<double>(tradeoff, "tradeoff", "a number");
                ConformalSnapResult r;
                {
                  py::gil_scoped_release release;
                  std::lock_guard<std::mutex> guard(*p.lock);
                  p.snap->set_tradeoff(t);
                  r = p.snap->snap(E);
                }
                if (full) return snap_dict(r);
                return to_numpy(r.V);
              }
              if (mode == SnapMode::Shape) {
                const int steps = steps_obj.is_none() ? 4 : as<int>(steps_obj, "steps", "an int");
                CurvatureSpinOptions co = kExtrusionOptions;
                co.area_epsilon =
                    area_obj.is_none() ? 0.0 : as<double>(area_obj, "area_constraint", "a number");
                require(rest, {.manifold = true, .oriented = true, .closed = true}, "snap mode shape");
                CurvatureFlow flow;
                Eigen::MatrixXd V;
                {
                  py::gil_scoped_release release;
                  flow = curvature_extrusion(rest.V, rest.F, E, steps, co);
                  V = umeyama_fit(flow.V, E).apply(flow.V);
                }
                if (!full) return to_numpy(V);
                py::dict d = flow_dict(flow);
                d["V"] = to_numpy(V);
                return d;
              }
              // Pinned: bind (or reuse) the cleanup for these pins and keep.
              if (pins_obj.is_none())
                throw Error("pins: mode \"pinned\" needs the vertices to keep in place");
              Eigen::VectorXi pins = to_int_vector(pins_obj, "pins");
              const CleanupKeep keep =
                  keep_obj.is_none()
                      ? cleanup_def.keep
                      : parse_option<CleanupKeep>(as<std::string>(keep_obj, "keep", "a str"), "keep: ");
              std::vector<int> sorted(pins.data(), pins.data() + pins.size());
              std::sort(sorted.begin(), sorted.end());
              sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
              const Eigen::VectorXi key =
                  Eigen::Map<const Eigen::VectorXi>(sorted.data(), static_cast<Eigen::Index>(sorted.size()));
              Eigen::MatrixXd V;
              PinnedCleanupResult r;
              {
                py::gil_scoped_release release;
                std::lock_guard<std::mutex> guard(*p.lock);
                if (!p.pinned || p.pinned_keep != keep || p.pinned_pins.size() != key.size() ||
                    p.pinned_pins != key) {
                  PinnedCleanupOptions o;
                  o.keep = keep;
                  p.pinned.reset();
                  p.pinned = std::make_unique<PinnedCleanup>(PinnedCleanup::bind(rest, pins, o));
                  p.pinned_pins = key;
                  p.pinned_keep = keep;
                }
                r = p.pinned->cleanup(E, V);
              }
              if (!full) return to_numpy(V);
              return cleanup_dict(r, V);
            },
            py::arg("V_edit"), py::arg("tradeoff") = py::none(), py::arg("full") = false,
            py::arg("mode") = py::none(), py::arg("pins") = py::none(), py::arg("keep") = py::none(),
            py::arg("steps") = py::none(), py::arg("area_constraint") = py::none(), R"doc(
snap(V_edit, tradeoff=None, full=False, mode=None, pins=None, keep=None, steps=None,
     area_constraint=None) -> V (n, 3), or a dict when full=True. What `spinmotor snap` computes.

Inputs:  V_edit (n, 3) finite, same vertex order as the rest mesh.
         mode: "free" (default without pins; "spin" is its former name), "shape" or "pinned" (default
         when pins are given); option_values("snap-mode").
         free:   tradeoff t in [0, 1] (default 1): 0 follows the edit, 1 is conformal (Fig. 21).
         shape:  steps (default 4) extrusion steps from the rest mesh toward the edit's curvature,
                 area_constraint (default 0 = off); closed meshes; the result is placed on the edit by
                 the best similarity.
         pinned: pins: vertex indices kept exactly where V_edit has them; keep: "auto" (default),
                 "volume", "area" or "none". The cleanup is bound on the first call with these pins
                 and keep and reused while they stay the same.
Output:  (n, 3) snapped positions. full=True: free: dict with V, rho (m,), mu (n, 4), lambda (n, 4),
         eigenvalue, iterations, residual, collapsed_faces, alignment_scale, timings_ms; shape: V,
         willmore, closure; pinned: as PinnedCleanup.cleanup(full=True).
Errors:  spinmotor.Error for a wrong size, a non-finite coordinate, an unknown mode or keep (listing
         the valid names), an option of another mode, tradeoff outside [0, 1], bad pins (see
         PinnedCleanup), an open mesh in mode shape; numerical Error if a solve fails. The GIL is
         released.
)doc");
  }

  // ---- private timing hooks (bench/python_overhead.py): the C++ calls alone, outputs reused ---------
  py::reinterpret_borrow<py::class_<PyCleanup>>(m.attr("PinnedCleanup"))
      .def(
          "_time_cleanup",
          [](PyCleanup& c, py::object V_edit, int repeats) {
            const Eigen::MatrixXd E = to_points(V_edit, "V_edit");
            Eigen::MatrixXd V;
            py::gil_scoped_release release;
            std::lock_guard<std::mutex> guard(*c.lock);
            return time_calls(repeats, [&] { (void)c.cleanup->cleanup(E, V); });
          },
          py::arg("V_edit"), py::arg("repeats") = 3);
  py::reinterpret_borrow<py::class_<PySnap>>(m.attr("ConformalSnap"))
      .def(
          "_time_snap",
          [](PySnap& p, py::object V_edit, int repeats) {
            const Eigen::MatrixXd E = to_points(V_edit, "V_edit");
            py::gil_scoped_release release;
            std::lock_guard<std::mutex> guard(*p.lock);
            p.snap->set_tradeoff(ConformalSnapOptions{}.tradeoff);
            return time_calls(repeats, [&] { (void)p.snap->snap(E); });
          },
          py::arg("V_edit"), py::arg("repeats") = 3);

  // ---- SpinTransform -------------------------------------------------------------------------------
  {
    const SpinTransformOptions def{};
    py::class_<PySpin>(m, "SpinTransform", R"doc(
Spin transformation (Crane, Pinkall, Schroeder 2011): bind once, solve per curvature change rho.

SpinTransform(V, F, tolerance=1e-10, iterations=50, krylov=True, problem="standard", scale="area",
              ordering="metis")
  V (n, 3), F (m, 3): a connected oriented manifold, no degenerate faces or unreferenced vertices.
  tolerance, iterations: the inverse iteration's residual and cap; krylov: Rayleigh-Ritz on the
  iterates; problem: standard (eq. 7), generalized (eq. 6) or unweighted; scale: output normalisation,
  area (the input's area), unit (max |v| = 1) or none; ordering: fill-reducing ordering, natural, amd
  or metis (the names of `spinmotor spin`, option_values("problem" / "scale" / "ordering")).
Errors: spinmotor.Error naming the first offender or the bad option value (listing the valid ones).
)doc")
        .def(py::init([](py::object V, py::object F, double tolerance, int iterations, bool krylov,
                         const std::string& problem, const std::string& scale, const std::string& ordering) {
               const Mesh mesh = to_mesh(V, F);
               SpinTransformOptions o;
               o.tolerance = tolerance;
               o.iterations = iterations;
               o.krylov = krylov;
               o.problem = parse_option<SpinEigenProblem>(problem, "problem: ");
               o.scale = parse_option<SpinScale>(scale, "scale: ");
               // Only the vertex orderings (kVertexOrderings), and the message lists only those.
               o.ordering = parse_ordering(ordering, kVertexOrderings, "ordering");
               PySpin p;
               py::gil_scoped_release release;
               p.st = std::make_unique<SpinTransform>(mesh, o);
               return p;
             }),
             py::arg("V"), py::arg("F"), py::arg("tolerance") = def.tolerance,
             py::arg("iterations") = def.iterations, py::arg("krylov") = def.krylov,
             py::arg("problem") = std::string(option_name(def.problem)),
             py::arg("scale") = std::string(option_name(def.scale)),
             py::arg("ordering") = std::string(option_name(def.ordering)))
        .def(
            "solve",
            [](PySpin& p, py::object rho, bool full) -> py::object {
              const Eigen::VectorXd r = to_vector(rho, "rho");
              SpinTransformResult out;
              {
                py::gil_scoped_release release;
                std::lock_guard<std::mutex> guard(*p.lock);
                out = p.st->solve(r);
              }
              if (!full) return to_numpy(out.V);
              py::dict d;
              d["V"] = to_numpy(out.V);
              d["lambda"] = to_numpy(out.lambda);
              d["eigenvalue"] = out.eigenvalue;
              d["iterations"] = out.iterations;
              d["residual"] = out.residual;
              return d;
            },
            py::arg("rho"), py::arg("full") = false, R"doc(
solve(rho, full=False) -> V (or a dict when full=True)

Inputs:  rho: (m,) finite curvature change per face (rho = 0 reproduces the mesh up to similarity).
Output:  (n, 3) positions (scaled to the input's area); full=True: dict with V, lambda (n, 4),
         eigenvalue, iterations, residual.
Errors:  spinmotor.Error for a wrong size or a non-finite entry; numerical Error if a factorization
         fails or the result is not finite. The GIL is released.
)doc");
  }

  // ---- flows ---------------------------------------------------------------------------------------
  {
    const WillmoreFlowOptions def{};
    m.def(
        "willmore_flow",
        [](py::object V, py::object F, double tau, int steps, bool keep_positions, py::object progress) {
          const Mesh mesh = to_mesh(V, F);
          WillmoreFlowOptions o;
          o.tau = tau;
          o.steps = steps;
          o.keep_positions = keep_positions;
          const auto cb = to_progress(progress);
          if (cb) o.progress = [&cb](const WillmoreFlowProgress& p) { cb(p.step, p.steps); };
          WillmoreFlowResult r;
          {
            py::gil_scoped_release release;
            r = willmore_flow(mesh, o);
          }
          py::dict d;
          d["V"] = to_numpy(r.V);
          d["willmore"] = to_numpy(r.willmore);
          d["step_ms"] = to_numpy(r.step_ms);
          py::list pos;
          for (const auto& P : r.positions) pos.append(to_numpy(P));
          d["positions"] = pos;
          return d;
        },
        py::arg("V"), py::arg("F"), py::arg("tau") = def.tau, py::arg("steps") = def.steps,
        py::arg("keep_positions") = def.keep_positions, py::arg("progress") = py::none(), R"doc(
Willmore flow by spin transformations (rho = -tau H at every step).

Inputs:  V (n, 3), F (m, 3) (as SpinTransform); tau > 0; steps >= 1; keep_positions: also return each
         step's positions; progress: optional callable(step, total) called after each step.
Output:  dict with V (n, 3), willmore (steps + 1 values: before, then after each step), step_ms,
         positions (list of (n, 3), input first, when keep_positions).
Errors:  spinmotor.Error for a bad mesh or option; numerical Error if a solve fails; an exception
         raised by progress ends the flow and propagates. The GIL is released between callbacks.
)doc");
  }
  {
    const CurvatureSpinOptions def{};
    m.def(
        "fair",
        [](py::object V, py::object F, int steps, double tau, double alpha, double beta, double area_epsilon,
           bool exactness, py::object progress) {
          const Mesh mesh = to_mesh(V, F);
          const auto o = curvature_options(alpha, beta, area_epsilon, exactness);
          const auto cb = to_progress(progress);
          CurvatureFlow r;
          {
            py::gil_scoped_release release;
            require(mesh, {.manifold = true, .oriented = true, .closed = true}, "fair");
            r = curvature_fairing(mesh.V, mesh.F, steps, tau, o, cb);
          }
          return flow_dict(r);
        },
        py::arg("V"), py::arg("F"), py::arg("steps"), py::arg("tau"), py::arg("alpha") = def.alpha,
        py::arg("beta") = def.beta, py::arg("area_epsilon") = def.area_epsilon,
        py::arg("exactness") = def.exactness, py::arg("progress") = py::none(), R"doc(
Curvature fairing toward a round sphere (Le Folgoc section 6; spin/curvature_spin_flow.hpp).

Inputs:  V (n, 3), F (m, 3): a closed, oriented, manifold mesh; steps >= 0; tau in (0, 1] (each step
         prescribes (1 - tau) h); alpha > 0, beta >= 0: regulariser weights; area_epsilon: area soft
         constraint (0 = off); exactness: genus > 0 exactness constraints; progress: optional
         callable(step, total) after each step.
Output:  dict with V (n, 3, the input's total area and centroid), willmore (steps + 1 values),
         closure (per step).
Errors:  spinmotor.Error for a bad mesh or option; an exception raised by progress propagates.
)doc");
    m.def(
        "extrude",
        [](py::object V_sphere, py::object F, py::object V_target, int steps, double alpha, double beta,
           double area_epsilon, bool exactness, py::object progress) {
          const Mesh sphere = to_mesh(V_sphere, F, true, "V_sphere", "F");
          const Eigen::MatrixXd T = to_points(V_target, "V_target");
          if (T.rows() != sphere.V.rows())
            throw Error("V_target: has " + std::to_string(T.rows()) + " vertices, V_sphere " +
                        std::to_string(sphere.V.rows()) + " (same connectivity required)");
          const auto o = curvature_options(alpha, beta, area_epsilon, exactness);
          const auto cb = to_progress(progress);
          CurvatureFlow r;
          {
            py::gil_scoped_release release;
            require(Mesh{T, sphere.F, {}, {}}, {.manifold = true, .oriented = true, .closed = true},
                    "extrude");
            r = curvature_extrusion(sphere.V, sphere.F, T, steps, o, cb);
          }
          return flow_dict(r);
        },
        py::arg("V_sphere"), py::arg("F"), py::arg("V_target"), py::arg("steps"),
        py::arg("alpha") = kExtrusionOptions.alpha, py::arg("beta") = kExtrusionOptions.beta,
        py::arg("area_epsilon") = kExtrusionOptions.area_epsilon,
        py::arg("exactness") = kExtrusionOptions.exactness, py::arg("progress") = py::none(), R"doc(
Curvature extrusion (Le Folgoc section 6, Ye section 5.2): from V_sphere (same F) toward the curvature
half-density and face areas of V_target, in `steps` ramped steps (e.g. back from fair()'s result).

Inputs:  V_sphere, V_target (n, 3); F (m, 3) closed, oriented, manifold; steps >= 1; alpha (default
         0.05, weaker than fairing's), beta, area_epsilon, exactness as fair(); progress as fair().
Output:  dict with V (n, 3, the target's total area and centroid), willmore, closure.
Errors:  spinmotor.Error for mismatched sizes, a bad mesh or option.
)doc");
  }

  // ---- Dirac spectrum ------------------------------------------------------------------------------
  {
    const DiracSpectrumOptions def{};
    m.def(
        "dirac_spectrum",
        [](py::object V, py::object F, py::object rho, int count, bool eigenvectors) {
          const Mesh mesh = to_mesh(V, F);
          Eigen::VectorXd r;
          if (!rho.is_none()) r = to_vector(rho, "rho", mesh.F.rows());
          DiracSpectrumOptions o;
          o.count = count;
          o.eigenvectors = eigenvectors;
          DiracSpectrum s;
          {
            py::gil_scoped_release release;
            s = dirac_spectrum(mesh.V, mesh.F, r, o);
          }
          py::dict d;
          d["eigenvalues"] = to_numpy(s.eigenvalues);
          if (eigenvectors) d["eigenvectors"] = to_numpy(s.eigenvectors);
          d["constant_kernel"] = s.constant_kernel;
          d["iterations"] = s.iterations;
          return d;
        },
        py::arg("V"), py::arg("F"), py::arg("rho") = py::none(), py::arg("count") = def.count,
        py::arg("eigenvectors") = def.eigenvectors, R"doc(
The eigenvalues of the spin transformation's Dirac problem nearest 0 (spin/dirac_spectrum.hpp).

Inputs:  V (n, 3), F (m, 3): closed, connected, oriented manifold; rho: optional (m,) curvature change
         (default 0); count: number of eigenvalues; eigenvectors: also return them.
Output:  dict with eigenvalues (count,) by increasing |gamma|, eigenvectors (4n, count) when asked,
         constant_kernel (4 when rho = 0: the constants, excluded), iterations.
Errors:  spinmotor.Error for a bad mesh or option; numerical Error if the iteration fails.
)doc");
  }
}

}  // namespace spinmotor::python
