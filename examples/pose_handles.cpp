// pose_handles: handle-based posing with motors (CGA paper §IV), then the conformal snap (Crane et al.
// 2011 §7.2) of the pose.
//
// Spot (spot.obj of the shared meshes folder, textured) gets five vertex handles selected by boxes: the body
// and three feet stay, the head turns 45° about the vertical axis through the neck and the front right leg
// lifts (rotated 35° about the hip's x axis). Surface harmonic coordinates (mean-value weights, SuperLU)
// blend the handle motors per vertex (log blend). The pose is then snapped onto its nearest spin
// transformation. Printed: Q_mean / Q_max before and after the snap, and the texture anisotropy change
// (below), the snap's distance to the pose, times.
//
// Texture anisotropy: per face, the ratio σ1/σ2 of the singular values of the map from texture (u, v)
// to the surface; a conformal deformation keeps it on every face (the map rest → posed is a similarity
// per face), so mean |log(ratio_posed / ratio_rest)| measures how much the texture's shape is skewed.
//
//   pose_handles [--mesh spot.obj] [--out out] [--small] [--check]
//
// --small uses a procedural capsule instead of spot (no file needed; the ctest size); --check asserts
// that the snap lowers Q_mean and the anisotropy change and keeps the pose (RMS distance < 5% of the
// bounding-box diagonal), exit 1 otherwise.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>

#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/deform/surface_harmonic.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/deformation_metrics.hpp"
#include "spinmotor/spin/conformal_snap.hpp"

using namespace spinmotor;
using Clock = std::chrono::steady_clock;
using Eigen::Vector3d;

namespace {

const ga::Mot kStay(1, 0, 0, 0, 0, 0, 0, 0);  // the identity motor: a handle that stays

Handle box(const Mesh& m, const Vector3d& lo, const Vector3d& hi, const std::string& name) {
  std::vector<int> v;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    const Vector3d p = m.V.row(i).transpose();
    if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) v.push_back(static_cast<int>(i));
  }
  if (v.empty()) throw Error("pose_handles: handle '" + name + "' selects no vertex");
  return {name, Eigen::Map<Eigen::VectorXi>(v.data(), static_cast<Eigen::Index>(v.size()))};
}

/// Rotation by `degrees` about `axis` through `pivot`, as a motor.
ga::Mot turn(const Vector3d& axis, double degrees, const Vector3d& pivot) {
  const Eigen::Isometry3d T = Eigen::Translation3d(pivot) *
                              Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis.normalized()) *
                              Eigen::Translation3d(-pivot);
  return ga::from_isometry(T);
}

/// Area-weighted mean over faces of |log(anisotropy of V's texture map / anisotropy of R's)|.
double anisotropy_change(const Mesh& rest, const Eigen::MatrixXd& V) {
  auto ratio = [&](const Eigen::MatrixXd& X, Eigen::Index f, double* area) {
    const Eigen::Vector2d t0 = rest.UV.row(rest.FUV(f, 0)), t1 = rest.UV.row(rest.FUV(f, 1)),
                          t2 = rest.UV.row(rest.FUV(f, 2));
    Eigen::Matrix2d T;
    T << t1 - t0, t2 - t0;
    Eigen::Matrix<double, 3, 2> P;
    P << (X.row(rest.F(f, 1)) - X.row(rest.F(f, 0))).transpose(),
        (X.row(rest.F(f, 2)) - X.row(rest.F(f, 0))).transpose();
    const Eigen::Matrix<double, 3, 2> J = P * T.inverse();  // texture → surface
    const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>>(J).singularValues();
    if (area) *area = 0.5 * P.col(0).cross(P.col(1)).norm();
    return s[0] / s[1];
  };
  double sum = 0, total = 0;
  for (Eigen::Index f = 0; f < rest.F.rows(); ++f) {
    double a = 0;
    const double r0 = ratio(rest.V, f, &a), r1 = ratio(V, f, nullptr);
    if (!std::isfinite(r0) || !std::isfinite(r1)) continue;  // degenerate texture triangle
    sum += a * std::abs(std::log(r1 / r0));
    total += a;
  }
  return sum / total;
}

int run(int argc, char** argv) {
  std::string mesh_path = std::string(SPINMOTOR_MESHES_DIR) + "/spot.obj", out = "out";
  bool small = false, check = false;
  CLI::App app{"Pose a mesh with motor handles (surface harmonic coordinates), then snap the pose"};
  app.add_option("--mesh", mesh_path, "a textured mesh with spot's proportions (y up, head towards +z)");
  app.add_option("--out", out, "output directory");
  app.add_flag("--small", small, "a procedural capsule instead of spot (the ctest size)");
  app.add_flag("--check", check, "assert the figures; exit 1 if one fails");
  CLI11_PARSE(app, argc, argv);

  // ---- the mesh and its handles --------------------------------------------------------------------
  Mesh rest;
  std::vector<Handle> handles;
  std::vector<ga::Mot> motors;
  if (small) {
    // capsule along z: the bottom stays, the top turns 45° about z (a twist) and tips over 35°
    rest = capsule(0.5, 3.0, 48, 24);
    const double top = rest.V.col(2).maxCoeff();
    handles = {box(rest, {-1, -1, -1}, {1, 1, 0.0}, "bottom"),
               box(rest, {-1, -1, top - 0.6}, {1, 1, top + 1}, "top")};
    motors = {kStay, turn({1, 0, 0}, 35, {0, 0, top - 1.2}) * turn({0, 0, 1}, 45, {0, 0, 0})};
  } else {
    rest = read_mesh(mesh_path);
    if (rest.UV.rows() == 0) throw Error("pose_handles: " + mesh_path + " has no texture coordinates");
    handles = {
        box(rest, {-1, -0.30, -0.35}, {1, 0.50, 0.10}, "body"),
        box(rest, {-1, -0.30, 0.62}, {1, 1.00, 1.10}, "head"),
        box(rest, {0.0, -0.80, 0.30}, {1, -0.60, 1.00}, "front_right_foot"),
        box(rest, {-1, -0.80, 0.30}, {0.0, -0.60, 1.00}, "front_left_foot"),
        box(rest, {-1, -0.80, -1.0}, {1, -0.60, -0.10}, "hind_feet"),
    };
    motors = {kStay, turn({0, 1, 0}, 45, {0, 0.2, 0.45}), turn({1, 0, 0}, -35, {0.2, -0.25, 0.55}), kStay,
              kStay};
  }

  // ---- bind (all factorization), pose (arithmetic only) ---------------------------------------------
  const auto t_bind = Clock::now();
  SurfaceHarmonicDeformer deformer = SurfaceHarmonicDeformer::bind(rest, handles);
  const double bind_ms = ms_since(t_bind);
  Eigen::MatrixXd posed(rest.V.rows(), 3);
  const auto t_pose = Clock::now();
  deformer.pose(motors, posed);
  const double pose_ms = ms_since(t_pose);

  // ---- snap ---------------------------------------------------------------------------------------
  const auto t_snap = Clock::now();
  const ConformalSnapResult snap = conformal_snap(rest, posed);
  const double snap_ms = ms_since(t_snap);

  const DeformationMetrics before = compute_metrics(rest, posed), after = compute_metrics(rest, snap.V);
  const double diag = before.diagonal;
  const double rms_to_pose = std::sqrt((snap.V - posed).rowwise().squaredNorm().mean()) / diag;
  const bool textured = rest.UV.rows() > 0 && rest.FUV.rows() == rest.F.rows();
  const double aniso_before = textured ? anisotropy_change(rest, posed) : 0.0;
  const double aniso_after = textured ? anisotropy_change(rest, snap.V) : 0.0;

  std::filesystem::create_directories(out);
  Mesh m = rest;
  m.V = posed;
  write_mesh(std::filesystem::path(out) / "pose_handles_posed.obj", m);
  m.V = snap.V;
  write_mesh(std::filesystem::path(out) / "pose_handles_snapped.obj", m);
  const nlohmann::json report = {
      {"example", "pose_handles"},
      {"mesh",
       {{"source", small ? "capsule" : mesh_path}, {"vertices", rest.V.rows()}, {"faces", rest.F.rows()}}},
      {"bind_ms", bind_ms},
      {"pose_ms", pose_ms},
      {"snap_ms", snap_ms},
      {"before",
       {{"q_mean", before.q_mean}, {"q_max", before.q_max}, {"texture_anisotropy_change", aniso_before}}},
      {"after",
       {{"q_mean", after.q_mean}, {"q_max", after.q_max}, {"texture_anisotropy_change", aniso_after}}},
      {"rms_snap_to_pose", rms_to_pose}};
  write_text_atomic(std::filesystem::path(out) / "pose_handles.json", report.dump(1) + "\n");

  std::printf("pose_handles: %s, %lld vertices / %lld faces, %zu handles\n",
              small ? "capsule" : mesh_path.c_str(), static_cast<long long>(rest.V.rows()),
              static_cast<long long>(rest.F.rows()), handles.size());
  std::printf("  bind %.1f ms, pose %.2f ms, snap %.1f ms\n", bind_ms, pose_ms, snap_ms);
  std::printf("  %-8s Q_mean %.4f  Q_max %.3f  texture anisotropy change %.4f\n", "posed", before.q_mean,
              before.q_max, aniso_before);
  std::printf("  %-8s Q_mean %.4f  Q_max %.3f  texture anisotropy change %.4f\n", "snapped", after.q_mean,
              after.q_max, aniso_after);
  std::printf(
      "  snap moved the pose by %.2f%% of the diagonal (RMS); wrote %s/pose_handles_{posed,snapped}.obj\n",
      100 * rms_to_pose, out.c_str());

  if (check) {
    bool ok = true;
    auto expect = [&](bool c, const char* what) {
      std::printf("  check %-44s %s\n", what, c ? "ok" : "FAILED");
      ok = ok && c;
    };
    expect(after.q_mean < before.q_mean, "snap lowers Q_mean");
    expect(after.q_mean < 1.02, "snapped Q_mean below 1.02");
    if (textured) expect(aniso_after < aniso_before, "snap lowers the texture anisotropy change");
    expect(rms_to_pose < 0.05, "snap keeps the pose (RMS < 5% of the diagonal)");
    return ok ? 0 : 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const Error& e) {
    std::fprintf(stderr, "pose_handles: %s\n", e.what());
    return e.kind() == Error::Kind::BadInput ? 2 : 3;
  }
}
