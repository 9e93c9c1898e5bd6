// `spinmotor flow MESH (--willmore TAU [--steps N] | --minimal) --out OUT [--json] [--quiet]`: conformal
// Willmore flow (Crane, Pinkall & Schröder 2011, §7.3): N spin transformations with ρ = −τ H of the
// current surface; each ideally multiplies the Willmore energy by (1 − τ)². `--minimal` is one step with
// ρ = −H (the minimal surface of a disk or annulus, Fig. 16 top). The output is written once, at the
// end, atomically: on any error (exit 2 bad input, 3 numerical failure) no output file is left.
// Progress lines (stderr) start once a run has taken more than a second, unless --quiet.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/willmore_flow.hpp"

namespace {

using namespace spinmotor;

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

struct FlowArgs {
  std::string mesh, out;
  double tau = 0;
  int steps = 1;
  bool minimal = false, json = false, quiet = false;
};

void run(const FlowArgs& a) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  if (a.out.empty()) throw Error("flow: --out is required");
  Mesh mesh = read_mesh(a.mesh);
  WillmoreFlowOptions o;
  o.tau = a.minimal ? 1.0 : a.tau;
  o.steps = a.minimal ? 1 : a.steps;
  o.keep_positions = false;
  if (!(o.tau > 0 && o.tau <= 1))
    throw Error("flow: --willmore " + num(o.tau) + " is outside (0, 1] (tau = 1 is --minimal)");
  if (o.steps < 1) throw Error("flow: --steps " + std::to_string(o.steps) + " must be at least 1");
  const bool progress = !a.quiet;
  o.progress = [&](const WillmoreFlowProgress& p) {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    if (progress && elapsed > 1.0)
      std::fprintf(stderr, "flow: step %d/%d  W %.6g  (%.0f ms, elapsed %.1f s)\n", p.step, p.steps,
                   p.willmore, p.step_ms, elapsed);
  };
  const WillmoreFlowResult r = willmore_flow(mesh, o);
  const QuasiConformalSummary q = quasi_conformal_summary(mesh.V, mesh.F, r.V);
  Mesh out = mesh;  // keeps the texture coordinates
  out.V = r.V;
  write_mesh(a.out, out);
  const double total_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  const Eigen::Index N = r.willmore.size() - 1;
  if (a.json) {
    nlohmann::json j;
    j["vertices"] = mesh.V.rows();
    j["faces"] = mesh.F.rows();
    j["tau"] = o.tau;
    j["steps"] = o.steps;
    j["willmore"] = std::vector<double>(r.willmore.data(), r.willmore.data() + r.willmore.size());
    j["willmore_ratio"] = r.willmore[0] > 0 ? r.willmore[N] / r.willmore[0] : 0.0;
    j["step_ms"] = std::vector<double>(r.step_ms.data(), r.step_ms.data() + r.step_ms.size());
    j["total_ms"] = total_ms;
    j["q_mean"] = q.q_mean;
    j["q_max"] = q.q_max;
    std::cout << j.dump(2) << '\n';
  } else if (!a.quiet) {
    std::printf("flow: %lld vertices, %lld faces, %s\n", static_cast<long long>(mesh.V.rows()),
                static_cast<long long>(mesh.F.rows()),
                a.minimal
                    ? "minimal surface (rho = -H)"
                    : ("Willmore, tau " + num(o.tau) + ", " + std::to_string(o.steps) + " steps").c_str());
    std::printf("  Willmore energy %.6g -> %.6g (ratio %.4g; ideal %.4g)\n", r.willmore[0], r.willmore[N],
                r.willmore[0] > 0 ? r.willmore[N] / r.willmore[0] : 0.0,
                std::pow(1 - o.tau, 2.0 * static_cast<double>(o.steps)));
    std::printf("  Q_mean %.6f, Q_max %.6f (output against input)\n", q.q_mean, q.q_max);
    std::printf("  time %.1f ms (%.1f ms per step)\n", total_ms, r.step_ms.mean());
    std::printf("  wrote %s\n", a.out.c_str());
  }
}

const cli::RegisterCommand register_flow{
    "flow", "Conformal Willmore flow (rho = -tau H per step) or the minimal surface in one step (rho = -H)",
    [](CLI::App& sub) {
      auto a = std::make_shared<FlowArgs>();
      sub.add_option("MESH", a->mesh,
                     "Input mesh (OBJ, OFF, PLY, STL); connected oriented manifold, normally a disk")
          ->required();
      auto* w = sub.add_option("--willmore", a->tau,
                               "Step tau in (0, 1]: each step removes the fraction tau of the mean curvature "
                               "half-density (W drops by (1 - tau)^2 per step)");
      sub.add_option("--steps", a->steps, "Number of steps (each rebinds on the current surface)")
          ->capture_default_str();
      auto* m = sub.add_flag("--minimal", a->minimal,
                             "One step with rho = -H: the minimal surface (disk or annulus)");
      w->excludes(m);
      sub.add_option("--out", a->out, "Output mesh (texture coordinates are kept)")->required();
      sub.add_flag("--json", a->json, "Print the energies, timings and Q as JSON");
      sub.add_flag("--quiet,-q", a->quiet, "Print nothing but errors");
      sub.footer(
          "Examples:\n"
          "  spinmotor flow bumpy_disk.obj --willmore 0.3 --steps 5 --out smooth.obj   # W x ~(1-0.3)^2 per "
          "step\n"
          "  spinmotor flow neck.obj --minimal --out minimal.obj --json                # rho = -H in one "
          "step");
      sub.callback([a, w, m] {
        if (w->count() == 0 && m->count() == 0) throw Error("flow: give --willmore TAU or --minimal");
        run(*a);
      });
    }};

}  // namespace
