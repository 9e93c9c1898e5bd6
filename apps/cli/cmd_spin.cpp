// `spinmotor spin MESH (--rho-image IMG | --rho-faces FILE | --rho-vertices FILE | --rho-expr E) --out OUT
// [--json]`: the spin transformation of Crane, Pinkall & Schröder 2011 for a painted curvature change ρ.
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/spin/boundary_prescription.hpp"
#include "spinmotor/spin/curvature_change.hpp"
#include "spinmotor/spin/scalar_expression.hpp"
#include "spinmotor/spin/spin_transform.hpp"

namespace {

using namespace spinmotor;

struct SpinArgs {
  std::string mesh, image, faces, vertices, expr, out;
  double rho_scale = 5.0, tolerance = 1e-10;
  int iterations = 50;
  std::string problem = "standard", scale = "area", ordering = "metis";
  bool json = false, spinxform = false, real_form = false, quiet = false, keep_boundary = false;
};

// Declares the positionals, options, flags and footer of `spin` on `sub`, bound to `a` (the four rho
// sources exclude each other).
void add_spin_options(CLI::App& sub, SpinArgs& a) {
  sub.add_option("MESH", a.mesh, "Input mesh (OBJ, OFF, PLY, STL); connected oriented manifold")->required();
  auto* img = sub.add_option("--rho-image", a.image,
                             "Grayscale TGA/PNG sampled through the mesh's texture coordinates: "
                             "rho = (2 g/255 - 1) * rho-scale per face (SpinXForm); the mesh is first "
                             "centred and scaled to max |v| = 1");
  auto* fac = sub.add_option("--rho-faces", a.faces, "Text file with one rho value per face");
  auto* ver = sub.add_option("--rho-vertices", a.vertices,
                             "Text file with one rho value per vertex (averaged to faces)");
  auto* exp = sub.add_option("--rho-expr", a.expr,
                             "rho as an expression of the position (x, y, z, r), e.g. '5*sin(3*x)*cos(2*y)', "
                             "evaluated at face barycentres");
  img->excludes(fac)->excludes(ver)->excludes(exp);
  fac->excludes(ver)->excludes(exp);
  ver->excludes(exp);
  sub.add_option("--out", a.out, "Output mesh (texture coordinates are kept)")->required();
  sub.add_flag("--keep-boundary-tangents", a.keep_boundary,
               "On a mesh with boundary, keep each boundary vertex's tangent direction (§5.7). With free "
               "boundaries the eigenproblem has many near-zero modes on some shapes (an open tube: Q_mean "
               "above 2 for any bump); the viewer's paint tool always keeps them");
  sub.add_flag("--json", a.json, "Print sizes, timings and quality as JSON");
  sub.add_flag("-q,--quiet", a.quiet, "Print nothing unless --json");
  sub.footer(
      "Examples:\n"
      "  spinmotor spin sphere.obj --rho-image bumpy.tga --out bumpy.obj\n"
      "  spinmotor spin capsule.obj --rho-expr \"0.5*exp(-20*(z-1)^2)\" --out bulge.obj --json\n"
      "  spinmotor spin sphere.obj --rho-faces rho.txt --out out.obj --spinxform   # the reference "
      "code's settings");
  sub.add_option("--rho-scale", a.rho_scale, "Image mode: rho of a white pixel")->capture_default_str();
  sub.add_flag("--spinxform", a.spinxform,
               "Reference-code settings: unweighted problem, exactly 3 inverse iterations, output centred "
               "with max |v| = 1");
  sub.add_option("--problem", a.problem, "Eigenproblem: standard (eq. 7), generalized (eq. 6), unweighted")
      ->check(CLI::IsMember(option_values<SpinEigenProblem>()))
      ->capture_default_str();
  sub.add_option("--tolerance", a.tolerance, "Eigen-residual at which inverse iteration stops")
      ->capture_default_str();
  sub.add_option("--max-iterations", a.iterations, "Maximum inverse iterations")->capture_default_str();
  sub.add_option("--scale", a.scale, "Output normalisation: area (keep area), unit (max |v| = 1), none")
      ->check(CLI::IsMember(option_values<SpinScale>()))
      ->capture_default_str();
  sub.add_option("--ordering", a.ordering, "Fill-reducing ordering of the vertex graph")
      ->check(CLI::IsMember(vertex_ordering_values()))
      ->capture_default_str();
  sub.add_flag("--real-form", a.real_form,
               "Factor the real 4n x 4n matrix instead of the complex 2n x 2n one");
}

// The solver options from `a`: the reference code's with --spinxform, else problem, tolerance,
// iterations and scale as given; the ordering and the form in both cases.
SpinTransformOptions solver_options(const SpinArgs& a) {
  SpinTransformOptions o = a.spinxform ? SpinTransformOptions::spinxform() : SpinTransformOptions{};
  if (!a.spinxform) {
    o.problem = parse_option<SpinEigenProblem>(a.problem, "spin: --problem: ");
    o.tolerance = a.tolerance;
    o.iterations = a.iterations;
    o.scale = parse_option<SpinScale>(a.scale, "spin: --scale: ");
  }
  o.ordering = parse_option<Ordering>(a.ordering, "spin: --ordering: ");
  o.complex_form = !a.real_form;
  return o;
}

// The per-face rho and the frame it was painted in (mesh = (input - centre) / radius).
struct PaintedRho {
  Eigen::VectorXd rho;
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
  double radius = 1.0;
};

// Reads the per-face rho from the source `a` names: image, expression, face or vertex values. Image
// mode centres `mesh` and scales it to max |v| = 1 first (rho has units 1/length and the image's range
// is meant for a unit-size mesh); throws when the mesh has no texture coordinates, no vertices or all
// its vertices coincide.
PaintedRho read_rho(Mesh& mesh, const SpinArgs& a) {
  PaintedRho p;
  if (!a.image.empty()) {
    if (!mesh.has_uv())
      throw Error("spin: --rho-image needs texture coordinates, but " + a.mesh +
                  " has none (OBJ 'vt' lines with faces 'f v/vt')");
    if (mesh.V.rows() == 0) throw Error("spin: " + a.mesh + " has no vertices");
    p.centre = mesh.V.colwise().mean();
    mesh.V.rowwise() -= p.centre;
    // A squared norm and one sqrt: a vectorised rowwise norm trips GCC 12 -Wuninitialized in its AVX-512
    // rsqrt intrinsic.
    p.radius = std::sqrt(mesh.V.rowwise().squaredNorm().maxCoeff());
    if (!(p.radius > 0)) throw Error("spin: all vertices of " + a.mesh + " coincide");
    mesh.V /= p.radius;
    p.rho = face_rho_from_image(mesh, read_grayscale_image(a.image), a.rho_scale);
  } else if (!a.expr.empty()) {
    p.rho = face_rho_from_function(mesh.V, mesh.F, parse_scalar_expression(a.expr));
  } else if (!a.faces.empty()) {
    p.rho = read_scalar_values(a.faces, mesh.F.rows(), "faces");
  } else {
    p.rho = face_rho_from_vertices(mesh.F, read_scalar_values(a.vertices, mesh.V.rows(), "vertices"));
  }
  return p;
}

// Prints sizes, timings and quality of the solve (`st`, its result r, the quality q) as JSON or as
// text, or nothing with --quiet.
void report_spin(const Mesh& mesh, const SpinTransform& st, const SpinTransformResult& r,
                 const QuasiConformalSummary& q, const SpinTransformOptions& o, const SpinArgs& a) {
  const SpinTimings& t = r.timings;
  if (a.json) {
    nlohmann::json j;
    j["vertices"] = mesh.V.rows();
    j["faces"] = mesh.F.rows();
    j["unknowns"] = st.num_unknowns();
    j["factor_nonzeros"] = st.factor_nonzeros();
    j["problem"] = std::string(option_name(o.problem));
    j["bind_ms"] = t.bind;
    j["assembly_ms"] = t.assembly;
    j["factor_ms"] = t.factor;
    j["eigen_ms"] = t.eigen;
    j["poisson_ms"] = t.poisson;
    j["poisson_setup_ms"] = t.poisson_setup;  // overlapped with bind/assembly/factor
    j["total_ms"] = t.bind + t.solve_total();
    j["eigen_iterations"] = r.iterations;
    j["eigen_residual"] = r.residual;
    j["eigenvalue"] = r.eigenvalue;
    j["q_mean"] = q.q_mean;
    j["q_max"] = q.q_max;
    std::cout << j.dump(2) << '\n';
  } else if (!a.quiet) {
    std::printf("spin: %lld vertices, %lld faces, %s problem\n", static_cast<long long>(mesh.V.rows()),
                static_cast<long long>(mesh.F.rows()), option_name(o.problem).data());
    std::printf("  eigenvalue %.10g after %d inverse iterations (residual %.3g)\n", r.eigenvalue,
                r.iterations, r.residual);
    std::printf("  times (ms): bind %.1f, assembly %.1f, factor %.1f, eigen %.1f, poisson %.1f\n", t.bind,
                t.assembly, t.factor, t.eigen, t.poisson);
    std::printf("  Q_mean %.6f, Q_max %.6f\n", q.q_mean, q.q_max);
    std::printf("  wrote %s\n", a.out.c_str());
  }
}

// The command: reads the mesh and rho, solves, warns when a result with free boundaries is far from
// conformal, maps the result back to the input's frame (unless normalised to max |v| = 1 anyway),
// writes it and reports. Throws when no rho source is given, or --keep-boundary-tangents on a closed mesh.
void run_spin(const SpinArgs& a) {
  if (a.image.empty() && a.faces.empty() && a.vertices.empty() && a.expr.empty())
    throw Error("spin: give one of --rho-image, --rho-faces, --rho-vertices, --rho-expr");
  Mesh mesh = read_mesh(a.mesh);
  SpinTransformOptions o = solver_options(a);
  const PaintedRho painted = read_rho(mesh, a);
  const bool has_boundary = !boundary_loops(mesh.F).empty();
  if (a.keep_boundary) {
    if (!has_boundary) throw Error("spin: --keep-boundary-tangents: " + a.mesh + " has no boundary");
    o.boundary = boundary_tangents(mesh.V, mesh.F);
  }
  SpinTransform st(mesh, o);
  const SpinTransformResult r = st.solve(painted.rho);
  const QuasiConformalSummary q = quasi_conformal_summary(mesh.V, mesh.F, r.V);
  if (has_boundary && !a.keep_boundary && q.q_mean > 1.2)
    std::fprintf(stderr,
                 "spin: warning: the result is far from conformal (Q_mean %.3f) on a mesh with free "
                 "boundaries; try --keep-boundary-tangents\n",
                 q.q_mean);
  Mesh out = mesh;
  out.V = r.V;
  if (o.scale != SpinScale::UnitMaxNorm) out.V = ((out.V * painted.radius).rowwise() + painted.centre).eval();
  write_mesh(a.out, out);
  report_spin(mesh, st, r, q, o, a);
}

const cli::RegisterCommand register_spin{
    "spin", "Spin transformation (Crane et al. 2011) of a mesh for a painted curvature change rho",
    [](CLI::App& sub) {
      auto a = std::make_shared<SpinArgs>();
      add_spin_options(sub, *a);
      sub.callback([a] { run_spin(*a); });
    }};

}  // namespace
