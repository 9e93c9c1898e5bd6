// `spinmotor snap REST EDITED --out OUT [--tradeoff t] [--problem standard|generalized]
// [--align similarity|translation|none] [--smooth-rho N] [--json]`: the nearest spin transformation of an
// edit (Crane et al. 2011 §7.2, spin/conformal_snap.hpp). EDITED may come from any tool as long as it keeps
// the rest mesh's vertex order and faces. The output keeps EDITED's texture coordinates (or REST's if
// EDITED has none).
//
// --mode shape (issue 9's second snap mode, an experiment): instead of §7.2, extrude from the rest mesh
// toward the edit's per-face half-density h* and areas A* (Le Folgoc et al. 2019 §6, spin/
// curvature_spin_flow.hpp) in --steps steps, then place the result on the edit by the best similarity.
// On the 90°-bent sausage it keeps 67% of the bend at Q_mean 1.013 (the §7.2 snap: 46%, Q_mean 1.008);
// closed meshes only.
//
// --mode pinned (--pin FILE [--keep auto|volume|area|none]; the default mode when --pin is given): the
// pose-keeping conformal cleanup (spin/pinned_cleanup.hpp, snap_pinned.cpp): the pinned vertices stay
// exactly where EDITED has them, the rest is made conformal at the rest volume (area if open).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "command.hpp"
#include "snap_pinned.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/area_distortion.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/curvature_spin_flow.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace {

using namespace spinmotor;

struct SnapArgs {
  std::string rest, edited, out, problem = "standard", align = "similarity", mode = "free", pin,
                                 keep = "auto";
  double tradeoff = 1.0, area_constraint = 0.0, pose_weight = PinnedCleanupOptions{}.pose_weight;
  int smooth = 0, steps = 4;
  bool json = false, quiet = false;
};

// Declares the positionals, options and flags of `snap` on `sub`, bound to `a`. Returns the --mode
// option (given or not decides the default mode).
CLI::Option* add_snap_options(CLI::App& sub, SnapArgs& a) {
  sub.add_option("REST", a.rest, "Rest mesh (connected oriented manifold)")->required();
  sub.add_option("EDITED", a.edited, "Edited mesh: same vertices (same order) and faces as REST")->required();
  sub.add_option("--out", a.out, "Output mesh (the snapped positions)")->required();
  sub.add_option("--tradeoff", a.tradeoff, "0 follows the edit, 1 is conformal (Crane et al. Fig. 21)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  sub.add_option("--problem", a.problem,
                 "Eigenproblem: standard (eq. 7) or generalized (eq. 6, closed meshes)")
      ->check(CLI::IsMember({"standard", "generalized"}))  // unweighted: SpinTransform only
      ->capture_default_str();
  sub.add_option("--align", a.align, "Placement onto the edit: similarity (Umeyama), translation, none")
      ->check(CLI::IsMember(option_values<SnapAlignment>()))
      ->capture_default_str();
  sub.add_option("--smooth-rho", a.smooth,
                 "Passes of face-neighbour averaging of rho before the solve (for creased edits, e.g. "
                 "linear-blend-skinned elbows, whose rho has spikes)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  CLI::Option* mode_opt =
      sub.add_option("--mode", a.mode,
                     "free (or spin): nearest spin transformation (§7.2); shape: extrude toward the edit's "
                     "curvature "
                     "(Le Folgoc et al. 2019; keeps more of a large bend, closed meshes); pinned: conformal "
                     "cleanup keeping the --pin vertices in place (the default when --pin is given)")
          ->check(CLI::IsMember(option_values<SnapMode>()))
          ->capture_default_str();
  sub.add_option("--pin", a.pin,
                 "--mode pinned: file of 0-based vertex indices kept exactly where EDITED has them "
                 "(one per line, '#' comments)");
  sub.add_option("--keep", a.keep,
                 "--mode pinned: measure kept at its rest value (auto: volume if closed, else area)")
      ->check(CLI::IsMember(option_values<CleanupKeep>()))
      ->capture_default_str();
  sub.add_option("--pose-weight", a.pose_weight,
                 "--mode pinned: γ ≥ 0 of the attraction holding the free vertices near EDITED (0 = the pins "
                 "only; spin/pinned_cleanup.hpp)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sub.add_option("--steps", a.steps, "--mode shape: extrusion steps")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  sub.add_option("--area-constraint", a.area_constraint,
                 "--mode shape: area soft constraint epsilon (0 = off)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sub.add_flag("--json", a.json, "Print sizes, quality and timings as JSON");
  sub.add_flag("-q,--quiet", a.quiet, "Print nothing unless --json");
  return mode_opt;
}

// Throws unless `edited` has the vertex count, the face count and the faces of `rest` (files named from
// `a`; the first differing face is named).
void check_same_connectivity(const Mesh& rest, const Mesh& edited, const SnapArgs& a) {
  if (rest.V.rows() != edited.V.rows() || rest.F.rows() != edited.F.rows()) {
    std::ostringstream m;
    m << "snap: " << a.edited << " has " << edited.V.rows() << " vertices and " << edited.F.rows()
      << " faces, " << a.rest << " has " << rest.V.rows() << " vertices and " << rest.F.rows()
      << " faces (the edit must keep the vertex order and the faces)";
    throw Error(m.str());
  }
  for (Eigen::Index f = 0; f < rest.F.rows(); ++f)
    if (rest.F.row(f) != edited.F.row(f)) {
      std::ostringstream m;
      m << "snap: face " << f << " of " << a.edited << " is (" << edited.F(f, 0) << ", " << edited.F(f, 1)
        << ", " << edited.F(f, 2) << "), in " << a.rest << " (" << rest.F(f, 0) << ", " << rest.F(f, 1)
        << ", " << rest.F(f, 2) << ") (the edit must keep the faces)";
      throw Error(m.str());
    }
}

// --mode shape: extrudes `rest` toward `edited`'s curvature in a.steps steps, places the result on
// `edited` by the best similarity, writes it to a.out and reports quality and time (JSON or text).
void snap_shape(const Mesh& rest, const Mesh& edited, const SnapArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  CurvatureSpinOptions co;
  co.alpha = 0.05;  // the extrusion default (curvature_spin_flow.hpp)
  co.area_epsilon = a.area_constraint;
  const CurvatureFlow flow = curvature_extrusion(rest.V, rest.F, edited.V, a.steps, co);
  const Similarity T = umeyama_fit(flow.V, edited.V);
  Mesh out = edited.has_uv() ? edited : rest;
  out.V = T.apply(flow.V);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const QuasiConformalSummary q0 = quasi_conformal_summary(rest.V, rest.F, edited.V);
  const QuasiConformalSummary q1 = quasi_conformal_summary(rest.V, rest.F, out.V);
  const VertexDistances dist = vertex_distances(edited.V, out.V, Alignment::None);
  write_mesh(a.out, out);
  if (a.json) {
    std::cout << nlohmann::json{{"mode", "shape"},
                                {"vertices", rest.V.rows()},
                                {"faces", rest.F.rows()},
                                {"steps", a.steps},
                                {"area_constraint", a.area_constraint},
                                {"q_mean_before", q0.q_mean},
                                {"q_max_before", q0.q_max},
                                {"q_mean_after", q1.q_mean},
                                {"q_max_after", q1.q_max},
                                {"rms_edit_to_snap", dist.rms},
                                {"max_edit_to_snap", dist.max},
                                {"closure", flow.closure},
                                {"total_ms", ms}}
                     .dump(2)
              << '\n';
  } else if (!a.quiet) {
    std::printf("snap (shape mode, %d extrusion steps): %lld vertices, %lld faces\n", a.steps,
                static_cast<long long>(rest.V.rows()), static_cast<long long>(rest.F.rows()));
    std::printf("  Q_mean before %.6f, after %.6f (Q_max %.4g -> %.4g)\n", q0.q_mean, q1.q_mean, q0.q_max,
                q1.q_max);
    std::printf("  RMS distance edit-snap %.4g of the bounding-box diagonal (max %.4g); %.0f ms\n", dist.rms,
                dist.max, ms);
    std::printf("  wrote %s\n", a.out.c_str());
  }
}

// --mode free: the nearest spin transformation of `edited` (§7.2) with a's tradeoff, smoothing, problem
// and alignment, written to a.out; reports quality and timings (JSON or text).
void snap_free(const Mesh& rest, const Mesh& edited, const SnapArgs& a) {
  ConformalSnapOptions o;
  o.tradeoff = a.tradeoff;
  o.rho_smoothing = a.smooth;
  o.problem = parse_option<SpinEigenProblem>(a.problem, "snap: --problem: ");
  o.alignment = parse_option<SnapAlignment>(a.align, "snap: --align: ");
  ConformalSnap cs(rest, o);
  const ConformalSnapResult r = cs.snap(edited.V);
  const QuasiConformalSummary q0 = quasi_conformal_summary(rest.V, rest.F, edited.V);
  const QuasiConformalSummary q1 = quasi_conformal_summary(rest.V, rest.F, r.V);
  const AreaDistortionSummary ad = area_distortion_summary(rest.V, rest.F, r.V);
  const VertexDistances dist = vertex_distances(edited.V, r.V, Alignment::None);
  Mesh out = edited.has_uv() ? edited : rest;
  out.V = r.V;
  write_mesh(a.out, out);
  const SnapTimings& t = r.timings;
  if (a.json) {
    nlohmann::json j;
    j["vertices"] = rest.V.rows();
    j["faces"] = rest.F.rows();
    j["problem"] = a.problem;
    j["tradeoff"] = a.tradeoff;
    j["align"] = a.align;
    j["q_mean_before"] = q0.q_mean;
    j["q_max_before"] = std::isfinite(q0.q_max) ? nlohmann::json(q0.q_max) : nlohmann::json();
    j["q_mean_after"] = q1.q_mean;
    j["q_max_after"] = std::isfinite(q1.q_max) ? nlohmann::json(q1.q_max) : nlohmann::json();
    j["area_distortion_after"] = ad.mean_abs;
    j["rms_edit_to_snap"] = dist.rms;  // relative to the edit's bounding-box diagonal
    j["max_edit_to_snap"] = dist.max;
    j["collapsed_faces_in_edit"] = r.collapsed_faces;
    j["eigenvalue"] = r.eigenvalue;
    j["eigen_iterations"] = r.iterations;
    j["bind_ms"] = cs.bind_ms() + t.bind;
    j["similarity_fit_ms"] = t.similarity_fit;
    j["eigen_ms"] = t.eigen;
    j["poisson_ms"] = t.poisson;
    j["total_ms"] = cs.bind_ms() + t.total();
    std::cout << j.dump(2) << '\n';
  } else if (!a.quiet) {
    std::printf("snap: %lld vertices, %lld faces, %s problem, tradeoff %g, %s alignment\n",
                static_cast<long long>(rest.V.rows()), static_cast<long long>(rest.F.rows()),
                a.problem.c_str(), a.tradeoff, a.align.c_str());
    std::printf("  Q_mean before %.6f, after %.6f (Q_max %.4g -> %.4g)\n", q0.q_mean, q1.q_mean, q0.q_max,
                q1.q_max);
    std::printf("  RMS distance edit-snap %.4g of the bounding-box diagonal (max %.4g)\n", dist.rms,
                dist.max);
    std::printf("  times (ms): bind %.1f, similarity fit %.1f, eigen %.1f, poisson %.1f\n",
                cs.bind_ms() + t.bind, t.similarity_fit, t.eigen, t.poisson);
    std::printf("  wrote %s\n", a.out.c_str());
  }
}

// The command: reads REST and EDITED, checks they share their connectivity and runs the mode (pinned
// when --pin is given and --mode is not, `mode_given`; else a.mode). Throws on --pin outside pinned mode.
void run_snap(const SnapArgs& a, bool mode_given) {
  const Mesh rest = read_mesh(a.rest);
  const Mesh edited = read_mesh(a.edited);
  check_same_connectivity(rest, edited, a);
  const SnapMode mode = !a.pin.empty() && !mode_given ? SnapMode::Pinned : parse_option<SnapMode>(a.mode);
  if (mode == SnapMode::Pinned) {
    cli::snap_pinned(rest, edited, {a.rest, a.pin, a.out, a.keep, a.pose_weight, a.json, a.quiet});
    return;
  }
  if (!a.pin.empty()) throw Error("snap: --pin is used by --mode pinned only (not --mode " + a.mode + ")");
  if (mode == SnapMode::Shape)
    snap_shape(rest, edited, a);
  else
    snap_free(rest, edited, a);
}

const cli::RegisterCommand register_snap{
    "snap",
    "Snap an edited mesh onto its nearest spin transformation (conformal deformation) of the rest mesh",
    [](CLI::App& sub) {
      auto a = std::make_shared<SnapArgs>();
      CLI::Option* mode_opt = add_snap_options(sub, *a);
      sub.footer(
          "Examples:\n"
          "  spinmotor snap rest.obj posed.obj --out snapped.obj                 # nearest spin "
          "transformation\n"
          "  spinmotor snap rest.obj posed.obj --out half.obj --tradeoff 0.5     # halfway between edit and "
          "conformal\n"
          "  spinmotor snap arm.obj arm-lbs.obj --out arm-clean.obj --smooth-rho 20 --json   # creased "
          "skinning edits\n"
          "  spinmotor snap arm.obj arm-lbs.obj --pin rigid.txt --out arm-clean.obj      # keep the pose: "
          "pinned mode");
      sub.callback([a, mode_opt] { run_snap(*a, mode_opt->count() != 0); });
    }};

}  // namespace
