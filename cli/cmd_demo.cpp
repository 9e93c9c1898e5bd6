// `spinmotor demo`: the main job on embedded defaults. Generates its own inputs (procedural meshes),
// runs a representative case of each capability that exists, writes meshes + one metrics JSON to
// out/, and prints one summary table (sizes, times, quality).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <numbers>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "spinmotor/error.hpp"
#include "spinmotor/mesh/atomic_file.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics.hpp"
#include "spinmotor/mesh/metrics/json.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/deform/surface_harmonic.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/spin/spin_transform.hpp"
#include <Eigen/Geometry>
#include "summary_table.hpp"

namespace spinmotor::cli {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

struct Demo {
  std::filesystem::path out_dir;
  bool quiet = false;
  SummaryTable table{{"stage", "vertices", "faces", "time ms", "Q_mean", "Q_max", "output"}};
  nlohmann::json report = nlohmann::json::object();

  void row(const std::string& stage, const Mesh& m, double ms, double q_mean, double q_max,
           const std::string& output) {
    table.add_row({stage, std::to_string(m.num_vertices()), std::to_string(m.num_faces()), fmt(ms, 1),
                   fmt(q_mean, 4), fmt(q_max, 4), output});
  }
  void progress(const std::string& what) const {
    if (!quiet) std::cerr << "demo: " << what << '\n';
  }
};

/// A closed-form twist about the z axis: angle grows linearly from 0 at z0 to `degrees` at z1.
/// Twisting is not conformal (Crane 2011, Fig. 21), so it is the demo's "edit" to measure.
Eigen::MatrixXd twist_z(const Eigen::MatrixXd& V, double z0, double z1, double degrees) {
  Eigen::MatrixXd W = V;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double t = std::clamp((V(i, 2) - z0) / (z1 - z0), 0.0, 1.0);
    const double a = t * degrees * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
    W(i, 0) = c * V(i, 0) - s * V(i, 1);
    W(i, 1) = s * V(i, 0) + c * V(i, 1);
  }
  return W;
}

void run_demo(Demo& d) {
  // 1. The embedded default: a capsule (closed, genus 0, with texture coordinates).
  auto t0 = std::chrono::steady_clock::now();
  const Mesh capsule_mesh = capsule(0.5, 3.0, 96, 48);
  const MeshReport report = validate(capsule_mesh);
  if (report.has_defects()) throw numerical_error("demo: the generated capsule has defects");
  const double gen_ms = ms_since(t0);
  write_mesh(d.out_dir / "capsule.obj", capsule_mesh);
  d.row("capsule: generate + validate", capsule_mesh, gen_ms, 1.0, 1.0, "capsule.obj");
  d.report["capsule"] = {{"vertices", report.vertices}, {"faces", report.faces}, {"genus", report.genus},
                         {"generate_validate_ms", gen_ms}};
  d.progress("generated and validated the capsule");

  // 2. A non-conformal edit (twist 90° along the axis), measured with the quality metrics.
  t0 = std::chrono::steady_clock::now();
  Mesh twisted = capsule_mesh;
  twisted.V = twist_z(capsule_mesh.V, 0.0, 3.0, 90.0);
  const DeformationMetrics tm = compute_metrics(capsule_mesh, twisted.V);
  const double twist_ms = ms_since(t0);
  write_mesh(d.out_dir / "capsule-twisted.obj", twisted);
  d.row("twist 90 deg (closed form) + metrics", twisted, twist_ms, tm.q_mean, tm.q_max, "capsule-twisted.obj");
  d.report["twist"] = to_json(tm);
  d.progress("twisted the capsule and measured it");

  // 3. Handle-based posing: surface harmonic coordinates with motor handles (CGA paper §IV). The
  //    bottom cap stays, the top cap turns 60° about x around the top of the cylinder and moves.
  Handle base{"base", {}}, tip{"tip", {}};
  {
    std::vector<int> b, t;
    for (Eigen::Index i = 0; i < capsule_mesh.V.rows(); ++i) {
      if (capsule_mesh.V(i, 2) < -0.2) b.push_back(static_cast<int>(i));
      if (capsule_mesh.V(i, 2) > 3.2) t.push_back(static_cast<int>(i));
    }
    base.vertices = Eigen::Map<Eigen::VectorXi>(b.data(), static_cast<Eigen::Index>(b.size()));
    tip.vertices = Eigen::Map<Eigen::VectorXi>(t.data(), static_cast<Eigen::Index>(t.size()));
  }
  const std::vector<Handle> handles{base, tip};
  t0 = std::chrono::steady_clock::now();
  auto deformer = SurfaceHarmonicDeformer::bind(capsule_mesh, handles);
  const double bind_ms = ms_since(t0);
  Eigen::Isometry3d tip_pose = Eigen::Isometry3d::Identity();
  tip_pose.translate(Eigen::Vector3d(0.0, 0.6, 3.0));
  tip_pose.rotate(Eigen::AngleAxisd(std::numbers::pi / 3.0, Eigen::Vector3d::UnitX()));
  tip_pose.translate(Eigen::Vector3d(0.0, 0.0, -3.0));
  const std::vector<ga::Mot> motors{ga::from_isometry(Eigen::Isometry3d::Identity()), ga::from_isometry(tip_pose)};
  Mesh posed = capsule_mesh;
  deformer.pose(motors, posed.V);  // first frame sizes the buffer
  t0 = std::chrono::steady_clock::now();
  deformer.pose(motors, posed.V);
  const double pose_ms = ms_since(t0);
  const DeformationMetrics pm = compute_metrics(capsule_mesh, posed.V);
  write_mesh(d.out_dir / "capsule-posed.obj", posed);
  d.row("surface-harmonic bind (MV, 2 handles)", capsule_mesh, bind_ms, std::nan(""), std::nan(""), "");
  d.row("surface-harmonic pose (log blend)", posed, pose_ms, pm.q_mean, pm.q_max, "capsule-posed.obj");
  d.report["surface_harmonic"] = to_json(pm);
  d.report["surface_harmonic"]["bind_ms"] = bind_ms;
  d.report["surface_harmonic"]["pose_ms"] = pose_ms;
  d.progress("posed the capsule with two motor handles");

  // 4. A spin transformation (Crane et al. 2011): paint a bump of curvature change ρ on the side of
  //    the capsule; the result is conformal by construction (Q stays near 1).
  Eigen::VectorXd rho(capsule_mesh.num_faces());
  const Eigen::RowVector3d bump_centre(0.5, 0.0, 1.5);
  for (Eigen::Index f = 0; f < capsule_mesh.num_faces(); ++f) {
    const Eigen::RowVector3d c = (capsule_mesh.V.row(capsule_mesh.F(f, 0)) + capsule_mesh.V.row(capsule_mesh.F(f, 1)) +
                                  capsule_mesh.V.row(capsule_mesh.F(f, 2))) / 3.0;
    rho[f] = 4.0 * std::exp(-(c - bump_centre).squaredNorm() / (2 * 0.3 * 0.3));
  }
  t0 = std::chrono::steady_clock::now();
  SpinTransform spin(capsule_mesh);
  const SpinTransformResult sr = spin.solve(rho);
  const double spin_ms = ms_since(t0);
  const DeformationMetrics sm = compute_metrics(capsule_mesh, sr.V);
  Mesh spun = capsule_mesh;
  spun.V = sr.V;
  write_mesh(d.out_dir / "capsule-spin.obj", spun);
  d.row("spin transform (bump, eq. 7)", spun, spin_ms, sm.q_mean, sm.q_max, "capsule-spin.obj");
  d.report["spin"] = to_json(sm);
  d.report["spin"]["total_ms"] = spin_ms;
  d.report["spin"]["eigen_iterations"] = sr.iterations;
  d.report["spin"]["eigen_residual"] = sr.residual;
  d.progress("applied a spin transformation");
}

const RegisterCommand reg{
    "demo", "Run the main job on embedded procedural meshes; write out/ and print a summary",
    [](CLI::App& sub) {
      auto out = std::make_shared<std::string>("out");
      auto quiet = std::make_shared<bool>(false);
      sub.add_option("--out", *out, "Output directory")->capture_default_str();
      sub.add_flag("--quiet", *quiet, "Print only the summary table");
      sub.footer("Example:\n  spinmotor demo --out out\n");
      sub.callback([out, quiet] {
        Demo d;
        d.out_dir = *out;
        d.quiet = *quiet;
        const auto t0 = std::chrono::steady_clock::now();
        run_demo(d);
        d.report["total_ms"] = ms_since(t0);
        write_text_atomic(d.out_dir / "demo.json", d.report.dump(2) + "\n");
        std::cout << "spinmotor demo: outputs in " << d.out_dir.string() << "/\n\n";
        d.table.print(std::cout);
        std::cout << "\ntotal " << fmt(ms_since(t0), 0) << " ms; metrics in "
                  << (d.out_dir / "demo.json").string() << '\n';
      });
    }};

}  // namespace
}  // namespace spinmotor::cli
