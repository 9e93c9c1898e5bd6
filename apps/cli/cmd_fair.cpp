// `spinmotor fair MESH --steps N --tau T [--area-constraint EPS] --out OUT [--json] [--quiet]`: fairing
// toward a round sphere in curvature space (Le Folgoc & Blanc 2019, §6): N spin transformations, each
// prescribing the half-density (1 − τ)h of the current surface (eq. 8, optionally with the Appendix D
// area soft constraint of tolerance EPS). Genus 0 only. The output (same connectivity, texture
// coordinates kept) is written once, atomically: on error (exit 2 bad input, 3 numerical) no file is left.
// Genus > 0: the exactness constraints of Appendix C keep the handles closed.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/area_distortion.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/spin/curvature_spin_flow.hpp"

namespace {

using namespace spinmotor;

struct FairArgs {
  std::string mesh, out;
  int steps = 10;
  double tau = 0.5, eps = 0.0;
  bool json = false, quiet = false;
};

void run(const FairArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  const Mesh mesh = read_mesh(a.mesh);
  require(mesh, {.manifold = true, .oriented = true, .closed = true}, "fair");
  if (a.steps < 1) throw Error("fair: --steps " + std::to_string(a.steps) + " must be at least 1");
  CurvatureSpinOptions o;
  o.area_epsilon = a.eps;
  const CurvatureFlow r = curvature_fairing(mesh.V, mesh.F, a.steps, a.tau, o);
  const QuasiConformalSummary q = quasi_conformal_summary(mesh.V, mesh.F, r.V);
  const AreaDistortionSummary s = area_distortion_summary(mesh.V, mesh.F, r.V);
  Mesh out = mesh;
  out.V = r.V;
  write_mesh(a.out, out);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (a.json) {
    nlohmann::json j;
    j["vertices"] = mesh.V.rows();
    j["faces"] = mesh.F.rows();
    j["steps"] = a.steps;
    j["tau"] = a.tau;
    j["area_constraint"] = a.eps;
    j["willmore"] = r.willmore;
    j["closure"] = r.closure;
    j["q_mean"] = q.q_mean;
    j["q_max"] = q.q_max;
    j["log_area_mean_abs"] = s.mean_abs;
    j["log_area_max_abs"] = s.max_abs;
    j["total_ms"] = ms;
    std::cout << j.dump(2) << '\n';
  } else if (!a.quiet) {
    std::printf("fair: %lld vertices, %lld faces, %d steps of tau %g%s\n",
                static_cast<long long>(mesh.V.rows()), static_cast<long long>(mesh.F.rows()), a.steps, a.tau,
                a.eps > 0 ? (", area constraint " + std::to_string(a.eps)).c_str() : "");
    std::printf("  Willmore energy (Ye eq. 11) %.6g -> %.6g (round sphere: 4 pi = 12.566)\n",
                r.willmore.front(), r.willmore.back());
    std::printf("  Q_mean %.4f, Q_max %.4f; |log area distortion| mean %.4f, max %.4f\n", q.q_mean, q.q_max,
                s.mean_abs, s.max_abs);
    std::printf("  time %.1f ms; wrote %s\n", ms, a.out.c_str());
  }
}

const cli::RegisterCommand register_fair{
    "fair", "Fair a closed mesh in curvature space, toward a round sphere for genus 0 (Le Folgoc 2019)",
    [](CLI::App& sub) {
      auto a = std::make_shared<FairArgs>();
      sub.add_option(
             "MESH", a->mesh,
             "Closed oriented manifold mesh (OBJ, OFF, PLY, STL); genus > 0 uses the exactness constraints")
          ->required();
      sub.add_option("--steps", a->steps, "Number of steps")->capture_default_str();
      sub.add_option("--tau", a->tau, "Fraction of the half-density removed per step, in (0, 1]")
          ->capture_default_str();
      sub.add_option("--area-constraint", a->eps,
                     "Tolerance of the log-area-distortion soft constraint (Appendix D); 0 = off")
          ->capture_default_str();
      sub.add_option("--out", a->out, "Output mesh (same connectivity, texture coordinates kept)")
          ->required();
      sub.add_flag("--json", a->json, "Print energies, closure residuals, Q and area distortion as JSON");
      sub.add_flag("--quiet,-q", a->quiet, "Print nothing but errors");
      sub.footer(
          "Examples:\n"
          "  spinmotor fair spot.obj --steps 10 --tau 0.5 --out spot_sphere.obj\n"
          "  spinmotor fair spot.obj --steps 6 --tau 0.5 --area-constraint 1.5 --out s.obj --json");
      sub.callback([a] { run(*a); });
    }};

}  // namespace
