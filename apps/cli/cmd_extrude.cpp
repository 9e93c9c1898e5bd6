// `spinmotor extrude SPHERE ORIGINAL [--steps N] [--area-constraint EPS] --out OUT [--json] [--quiet]`:
// extrusion in curvature space (Le Folgoc & Blanc 2019, §6; Ye et al. 2018, §5.2): starting from SPHERE
// (same connectivity as ORIGINAL, e.g. the output of `spinmotor fair`), N spin transformations ramp the
// half-density to ORIGINAL's; reports the reconstruction error (vertex distances after similarity
// alignment, relative to ORIGINAL's bounding-box diagonal). Written once, atomically.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/spin/curvature_spin_flow.hpp"

namespace {

using namespace spinmotor;

struct ExtrudeArgs {
  std::string sphere, original, out;
  int steps = 8;
  double eps = 0.0;
  bool json = false, quiet = false;
};

void run(const ExtrudeArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  const Mesh sphere = read_mesh(a.sphere), orig = read_mesh(a.original);
  if (sphere.V.rows() != orig.V.rows() || sphere.F.rows() != orig.F.rows() || sphere.F != orig.F) {
    std::ostringstream s;
    s << "extrude: " << a.sphere << " (" << sphere.V.rows() << " vertices, " << sphere.F.rows()
      << " faces) and " << a.original << " (" << orig.V.rows() << " vertices, " << orig.F.rows()
      << " faces) must have the same connectivity";
    throw Error(s.str());
  }
  require(orig, {.manifold = true, .oriented = true, .closed = true}, "extrude");
  if (a.steps < 1) throw Error("extrude: --steps " + std::to_string(a.steps) + " must be at least 1");
  CurvatureSpinOptions o{.alpha = 0.05};
  o.area_epsilon = a.eps;
  const CurvatureFlow r = curvature_extrusion(sphere.V, sphere.F, orig.V, a.steps, o);
  const VertexDistances d = vertex_distances(orig.V, r.V, Alignment::Similarity);
  Mesh out = orig;
  out.V = r.V;
  write_mesh(a.out, out);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const double mean = d.d.mean() / d.diagonal;
  if (a.json) {
    nlohmann::json j;
    j["vertices"] = orig.V.rows();
    j["faces"] = orig.F.rows();
    j["steps"] = a.steps;
    j["area_constraint"] = a.eps;
    j["willmore"] = r.willmore;
    j["closure"] = r.closure;
    j["distance_mean_relative"] = mean;
    j["distance_max_relative"] = d.max;
    j["total_ms"] = ms;
    std::cout << j.dump(2) << '\n';
  } else if (!a.quiet) {
    std::printf("extrude: %lld vertices, %lld faces, %d steps\n", static_cast<long long>(orig.V.rows()),
                static_cast<long long>(orig.F.rows()), a.steps);
    std::printf("  Willmore energy %.6g -> %.6g\n", r.willmore.front(), r.willmore.back());
    std::printf("  distance to ORIGINAL after similarity alignment: mean %.4g, max %.4g of the diagonal\n",
                mean, d.max);
    std::printf("  time %.1f ms; wrote %s\n", ms, a.out.c_str());
  }
}

const cli::RegisterCommand register_extrude{
    "extrude", "Extrude a sphere back to a mesh's curvature (same connectivity; Le Folgoc 2019)",
    [](CLI::App& sub) {
      auto a = std::make_shared<ExtrudeArgs>();
      sub.add_option("SPHERE", a->sphere, "Starting surface, e.g. the output of `spinmotor fair`")
          ->required();
      sub.add_option("ORIGINAL", a->original, "Mesh whose half-density is prescribed (same connectivity)")
          ->required();
      sub.add_option("--steps", a->steps, "Number of steps (the half-density is ramped linearly)")
          ->capture_default_str();
      sub.add_option("--area-constraint", a->eps,
                     "Tolerance of the area soft constraint toward ORIGINAL's areas; 0 = off")
          ->capture_default_str();
      sub.add_option("--out", a->out, "Output mesh (ORIGINAL's texture coordinates)")->required();
      sub.add_flag("--json", a->json, "Print energies and the reconstruction error as JSON");
      sub.add_flag("--quiet,-q", a->quiet, "Print nothing but errors");
      sub.footer(
          "Examples:\n"
          "  spinmotor fair spot.obj --steps 6 --tau 0.5 --out spot_sphere.obj\n"
          "  spinmotor extrude spot_sphere.obj spot.obj --out spot_back.obj --json");
      sub.callback([a] { run(*a); });
    }};

}  // namespace
