// cleanup_study: the pose-keeping conformal cleanup against what technical artists use to clean
// skinned meshes, on the same edits, with the same measures.
//
// Cases (the issue's): a two-bone arm (capsule of radius 1, cylinder length 6, elbow blend band of
// width 2: the lower bone's weight a smoothstep over z ∈ [2, 4]) bent 90° and 120° at the elbow,
// twisted 90° and 180° about the forearm, and bent 90° + twisted 90°; a sausage (icosphere level 4,
// z × 3) bent 90° by a closed-form circular bend with its end caps (|z| > 2.4) rigid.
// Methods, per arm case: LBS; DQS (dual-quaternion linear blend, SkinDeformer::Blend::DLB); Delta
// Mush on LBS (Mancewicz et al. 2014: 10 uniform sweeps, λ = 0.5); Direct Delta Mush (Le & Lewis
// 2019, variant 0); the §7.2 conformal snap of LBS (Crane et al. 2011); the pose-keeping cleanup of LBS
// (spin/pinned_cleanup.hpp) with the pins of the rig (vertices of one bone, weight ≥ 0.999, farther
// than 0.5 from the blend band: pins_from_weights). The sausage: the bend itself, its snap, its cleanup
// with the caps pinned.
// Measures: Q_mean (rest-area weighted) and Q_max of the quasi-conformal error against the rest mesh
// (mesh/metrics), enclosed volume / rest volume (divergence theorem), the largest pin displacement
// relative to the bounding-box diagonal, the RMS distance to the edit (LBS for the arm and the rigs)
// relative to the diagonal, and the time of the method's per-frame work (bind excluded).
//
// Rigs (--rigs DIR, the Cesium glTF samples, CC BY 4.0 Cesium): CesiumMan and RiggedFigure at ¼, ½ and ¾
// of their animation, LBS / DQS / Delta Mush / Direct Delta Mush / the cleanup of LBS with the pins of
// the rig (weight ≥ 0.999, default margin: a quarter of the widest joint blend band).
//
//   cleanup_study [--out out] [--small] [--check] [--rigs DIR]
//
// Prints one markdown table and writes out/cleanup_study.json (with --rigs also each rig's rest mesh and
// its LBS, Delta Mush and cleaned meshes as OBJ: out/<rig>-<percent>-<method>.obj). --small uses coarser
// meshes (the ctest size). --check asserts the cleanup's required figures at 90° (pins exact to 1e-9 of the
// diagonal, Q_mean ≤ 1.06, Q_max ≤ 1.5, volume ≥ 0.93) and that on every bend case its Q_mean is below every
// baseline's at a volume no lower than theirs; exits 1 if one fails.
#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <numbers>

#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/deform/delta_mush.hpp"
#include "spinmotor/deform/direct_delta_mush.hpp"
#include "spinmotor/deform/gltf_skin.hpp"
#include "spinmotor/deform/rig_pins.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/ga/rotor_fit.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/deformation_metrics.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

using namespace spinmotor;
using Eigen::Vector3d;

namespace {

double volume(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  double s = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    s += Vector3d(V.row(F(f, 0))).dot(Vector3d(V.row(F(f, 1))).cross(Vector3d(V.row(F(f, 2)))));
  return s / 6.0;
}

double diagonal(const Eigen::MatrixXd& V) { return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm(); }

ga::Mot about(const Vector3d& axis, double degrees, const Vector3d& pivot) {
  return ga::from_isometry(Eigen::Isometry3d(Eigen::Translation3d(pivot) *
                                             Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis) *
                                             Eigen::Translation3d(-pivot)));
}

struct Row {
  std::string edit, method;
  double q_mean = 0, q_max = 0, volume = 0, pin_error = 0, rms_to_edit = 0, ms = 0;
};

/// Measures one result against the rest mesh.
Row measure(const std::string& edit, const std::string& method, const Mesh& rest, const Eigen::MatrixXd& V,
            const Eigen::MatrixXd& V_pins, const Eigen::VectorXi& pins, double ms) {
  const DeformationMetrics m = compute_metrics(rest, V);
  double pe = 0;
  for (Eigen::Index k = 0; k < pins.size(); ++k)
    pe = std::max(pe, (V.row(pins[k]) - V_pins.row(pins[k])).norm());
  const double rms = std::sqrt((V - V_pins).rowwise().squaredNorm().mean());
  return {edit,
          method,
          m.q_mean,
          m.q_max,
          volume(V, rest.F) / volume(rest.V, rest.F),
          pe / diagonal(V_pins),
          rms / diagonal(V_pins),
          ms};
}

/// Times f() once after a warm-up call (the first call sizes the buffers).
double time_ms(const std::function<void()>& f) {
  f();
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return ms_since(t0);
}

struct ArmCase {
  const char* name;
  double bend, twist;
};

/// The method name of the rig defaults' rows.
const std::string kRigDefault = "pose-keeping cleanup of LBS, rig defaults (+ attraction γ = 10)";

/// γ of the pose attraction rows (--pose-weight; 0 = none).
double g_pose_weight = 0;

std::string attraction_label() {
  char b[96];
  std::snprintf(b, sizeof b, "pose-keeping cleanup of LBS + attraction (γ = %g)", g_pose_weight);
  return b;
}

void arm_study(bool small, std::vector<Row>& rows) {
  const Mesh arm = capsule(1.0, 6.0, small ? 47 : 93, small ? 32 : 64);
  const Eigen::Index n = arm.V.rows();
  Eigen::MatrixXd W(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = std::clamp((arm.V(i, 2) - 2.0) / 2.0, 0.0, 1.0), w = t * t * (3 - 2 * t);
    W.row(i) << 1 - w, w;
  }
  std::vector<Bone> bones(2);
  bones[0] = {.name = "upper", .parent = -1, .head = {0, 0, -1}, .tail = {0, 0, 3}};
  bones[1] = {.name = "lower", .parent = 0, .head = {0, 0, 3}, .tail = {0, 0, 7}};
  const Eigen::VectorXi pins = pins_from_weights(arm.V, W, kRigidWeight, 0.5);
  SkinDeformer lbs = SkinDeformer::bind(arm, bones, W, {.blend = SkinBlend::LBS});
  SkinDeformer dqs = SkinDeformer::bind(arm, bones, W, {.blend = SkinBlend::DLB});
  DeltaMushDeformer dm = DeltaMushDeformer::bind(arm, bones, W, DeltaMushDeformer::Options{});
  DirectDeltaMushDeformer ddm =
      DirectDeltaMushDeformer::bind(arm, bones, W, DirectDeltaMushDeformer::Options{});
  ConformalSnap snap(arm);
  PinnedCleanup cleanup = PinnedCleanup::bind(arm, pins);
  const Eigen::VectorXd attraction = pin_attraction_from_weights(W);
  PinnedCleanupOptions ao;
  ao.pose_weight = g_pose_weight;
  PinnedCleanup attracted = PinnedCleanup::bind(arm, pins, ao, attraction);
  const Vector3d elbow(0, 0, 3);
  for (const ArmCase& c :
       {ArmCase{"arm bend 90", 90, 0}, ArmCase{"arm bend 120", 120, 0}, ArmCase{"arm twist 90", 0, 90},
        ArmCase{"arm twist 180", 0, 180}, ArmCase{"arm bend 90 + twist 90", 90, 90}}) {
    const std::vector<ga::Mot> frames = {
        ga::Mot(1, 0, 0, 0, 0, 0, 0, 0),
        about(Vector3d::UnitX(), c.bend, elbow) * about(Vector3d::UnitZ(), c.twist, elbow)};
    Eigen::MatrixXd V_lbs, V;
    double ms = time_ms([&] { lbs.pose(frames, V_lbs); });
    rows.push_back(measure(c.name, "LBS", arm, V_lbs, V_lbs, pins, ms));
    ms = time_ms([&] { dqs.pose(frames, V); });
    rows.push_back(measure(c.name, "DQS", arm, V, V_lbs, pins, ms));
    ms = time_ms([&] { dm.pose(frames, V); });
    rows.push_back(measure(c.name, "Delta Mush (LBS)", arm, V, V_lbs, pins, ms));
    ms = time_ms([&] { ddm.pose(frames, V); });
    rows.push_back(measure(c.name, "Direct Delta Mush", arm, V, V_lbs, pins, ms));
    try {
      ms = time_ms([&] { V = snap.snap(V_lbs).V; });
      rows.push_back(measure(c.name, "§7.2 snap of LBS", arm, V, V_lbs, pins, ms));
    } catch (const Error& e) {  // the 180° twist collapses LBS onto the axis
      std::fprintf(stderr, "cleanup_study: %s: §7.2 snap failed: %s\n", c.name, e.what());
    }
    ms = time_ms([&] { (void)cleanup.cleanup(V_lbs, V); });
    rows.push_back(measure(c.name, "pose-keeping cleanup of LBS", arm, V, V_lbs, pins, ms));
    if (g_pose_weight > 0) {
      ms = time_ms([&] { (void)attracted.cleanup(V_lbs, V); });
      rows.push_back(measure(c.name, attraction_label(), arm, V, V_lbs, pins, ms));
    }
  }
}

void sausage_study(bool small, std::vector<Row>& rows) {
  Mesh s = icosphere(small ? 3 : 4);
  s.V.col(2) *= 3.0;
  const double half = 2.4, kappa = (std::numbers::pi / 2) / (2 * half), R = 1 / kappa;
  Eigen::MatrixXd bent = s.V;
  std::vector<int> caps;
  for (Eigen::Index i = 0; i < s.V.rows(); ++i) {
    const double x = s.V(i, 0), y = s.V(i, 1), z = s.V(i, 2);
    const double t = std::clamp(z, -half, half), th = kappa * t;
    const Vector3d c(R * (1 - std::cos(th)), 0, R * std::sin(th)), tan(std::sin(th), 0, std::cos(th)),
        nor(std::cos(th), 0, -std::sin(th));
    bent.row(i) = (c + x * nor + Vector3d(0, y, 0) + (z - t) * tan).transpose();
    if (std::abs(z) > half) caps.push_back(static_cast<int>(i));
  }
  const Eigen::VectorXi pins =
      Eigen::Map<Eigen::VectorXi>(caps.data(), static_cast<Eigen::Index>(caps.size()));
  rows.push_back(measure("sausage bend 90", "the bend", s, bent, bent, pins, 0));
  ConformalSnap snap(s);
  Eigen::MatrixXd V;
  double ms = time_ms([&] { V = snap.snap(bent).V; });
  rows.push_back(measure("sausage bend 90", "§7.2 snap", s, V, bent, pins, ms));
  PinnedCleanup cleanup = PinnedCleanup::bind(s, pins);
  ms = time_ms([&] { (void)cleanup.cleanup(bent, V); });
  rows.push_back(measure("sausage bend 90", "pose-keeping cleanup", s, V, bent, pins, ms));
}

void rig_study(const std::filesystem::path& dir, const std::filesystem::path& out, std::vector<Row>& rows) {
  for (const char* file : {"RiggedFigure.gltf", "CesiumMan.gltf"}) {
    const GltfRig rig = read_gltf(dir / file);
    const RigSkin skin = rig_skin(rig);
    const Eigen::MatrixXd W(skin.rig.weights);
    const Mesh& rest = skin.rest;  // scene coordinates, the bones' frame
    const Eigen::VectorXi pins =
        pins_from_weights(rest.V, W, kRigidWeight, default_pin_margins(rest.V, W, skin.rig.skeleton));
    SkinDeformer lbs = SkinDeformer::bind(rest, skin.rig, {.blend = SkinBlend::LBS});
    SkinDeformer dqs = SkinDeformer::bind(rest, skin.rig, {.blend = SkinBlend::DLB});
    DeltaMushDeformer dm = DeltaMushDeformer::bind(rest, skin.rig, DeltaMushDeformer::Options{});
    DirectDeltaMushDeformer ddm =
        DirectDeltaMushDeformer::bind(rest, skin.rig, DirectDeltaMushDeformer::Options{});
    PinnedCleanup cleanup = PinnedCleanup::bind(rest, pins);
    // Soft-weighted rigs (CesiumMan: 313 of 2338 vertices reach 0.999 at all) pin little, and the
    // cleanup drifts from the pose; the rig defaults (scene/rig_cleanup.hpp: the same pins, the rest
    // held near the pose by the weights' attraction, γ = 10) keep it.
    scene::RigCleanup rig_default = scene::RigCleanup::bind(rest, W, skin.rig.skeleton);
    PinnedCleanupOptions ao;
    ao.pose_weight = g_pose_weight;
    PinnedCleanup attracted = PinnedCleanup::bind(rest, pins, ao, pin_attraction_from_weights(W));
    const GltfAnimation& anim = rig.animations.at(0);
    for (double frac : {0.25, 0.5, 0.75}) {
      const double t = anim.start + frac * anim.duration();
      std::vector<ga::Mot> frames;  // the rigid joint transforms T_j(t) (gltf_skin.hpp) as motors
      for (const SkinDeformer::Affine& T : rig_joint_transforms(rig, skin, 0, t)) {
        Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
        M.linear() = ga::closest_rotation(T.leftCols<3>());
        M.translation() = T.col(3);
        frames.push_back(ga::normalize(ga::from_isometry(M)));
      }
      char edit[96];
      std::snprintf(edit, sizeof edit, "%s t = %.2f s (%zu pins of %lld)", file, t,
                    static_cast<std::size_t>(pins.size()), static_cast<long long>(rest.V.rows()));
      Eigen::MatrixXd V_lbs, V;
      // The meshes of each method (rest UVs kept), e.g. for `spinmotor render` pictures.
      const std::string stem =
          std::filesystem::path(file).stem().string() + "-" + std::to_string(int(frac * 100));
      auto save = [&](const char* method, const Eigen::MatrixXd& P) {
        Mesh m = rest;
        m.V = P;
        write_mesh(out / (stem + "-" + method + ".obj"), m);
      };
      double ms = time_ms([&] { lbs.pose(frames, V_lbs); });
      rows.push_back(measure(edit, "LBS", rest, V_lbs, V_lbs, pins, ms));
      save("lbs", V_lbs);
      ms = time_ms([&] { dqs.pose(frames, V); });
      rows.push_back(measure(edit, "DQS", rest, V, V_lbs, pins, ms));
      ms = time_ms([&] { dm.pose(frames, V); });
      rows.push_back(measure(edit, "Delta Mush (LBS)", rest, V, V_lbs, pins, ms));
      save("deltamush", V);
      ms = time_ms([&] { ddm.pose(frames, V); });
      rows.push_back(measure(edit, "Direct Delta Mush", rest, V, V_lbs, pins, ms));
      ms = time_ms([&] { (void)cleanup.cleanup(V_lbs, V); });
      rows.push_back(measure(edit, "pose-keeping cleanup of LBS", rest, V, V_lbs, pins, ms));
      save("cleaned", V);
      ms = time_ms([&] { (void)rig_default(V_lbs, V); });
      rows.push_back(measure(edit, kRigDefault, rest, V, V_lbs, pins, ms));
      save("cleaned-rig", V);
      if (g_pose_weight > 0) {
        ms = time_ms([&] { (void)attracted.cleanup(V_lbs, V); });
        rows.push_back(measure(edit, attraction_label(), rest, V, V_lbs, pins, ms));
        save("attracted", V);
      }
      if (frac == 0.25) write_mesh(out / (std::filesystem::path(file).stem().string() + "-rest.obj"), rest);
    }
  }
}

int run(int argc, char** argv) {
  std::string out = "out";
  bool small = false, check = false;
  CLI::App app{
      "The pose-keeping conformal cleanup against LBS, DQS, Delta Mush, Direct Delta Mush and the §7.2 snap"};
  app.add_option("--out", out, "output directory");
  app.add_flag("--small", small, "coarser meshes (the ctest size)");
  app.add_flag("--check", check, "assert the cleanup's figures; exit 1 if one fails");
  std::string rigs;
  app.add_option("--rigs", rigs, "folder with CesiumMan.gltf and RiggedFigure.gltf (the Cesium samples)");
  app.add_option("--pose-weight", g_pose_weight,
                 "γ of the cleanup's pose attraction (pin_attraction_from_weights) for extra rows; 0 = none");
  CLI11_PARSE(app, argc, argv);

  std::vector<Row> rows;
  arm_study(small, rows);
  sausage_study(small, rows);
  if (!rigs.empty()) {
    if (!std::filesystem::is_directory(rigs)) {
      std::printf("skipped: %s not found\n", rigs.c_str());
      return 77;  // the ctest SKIP_RETURN_CODE (examples/CMakeLists.txt)
    }
    std::filesystem::create_directories(out);
    rig_study(rigs, out, rows);
  }

  nlohmann::json j = nlohmann::json::array();
  std::printf(
      "| edit | method | Q_mean | Q_max | volume / rest | pin error / diagonal | RMS to the edit / diagonal "
      "| ms |\n");
  std::printf("| --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (const Row& r : rows) {
    std::printf("| %s | %s | %.4f | %.3g | %.4f | %.1e | %.4f | %.1f |\n", r.edit.c_str(), r.method.c_str(),
                r.q_mean, r.q_max, r.volume, r.pin_error, r.rms_to_edit, r.ms);
    j.push_back({{"edit", r.edit},
                 {"method", r.method},
                 {"q_mean", r.q_mean},
                 {"q_max", std::isfinite(r.q_max) ? nlohmann::json(r.q_max) : nlohmann::json(nullptr)},
                 {"volume_ratio", r.volume},
                 {"pin_error", r.pin_error},
                 {"rms_to_edit", r.rms_to_edit},
                 {"ms", r.ms}});
  }
  std::filesystem::create_directories(out);
  write_text_atomic(std::filesystem::path(out) / "cleanup_study.json", j.dump(1) + "\n");

  if (!check) return 0;
  bool ok = true;
  auto expect = [&](bool c, const std::string& what) {
    std::printf("  check %-78s %s\n", what.c_str(), c ? "ok" : "FAILED");
    ok = ok && c;
  };
  auto find = [&](const std::string& edit, const std::string& method) -> const Row* {
    for (const Row& r : rows)
      if (r.edit == edit && r.method == method) return &r;
    return nullptr;
  };
  const Row* c90 = find("arm bend 90", "pose-keeping cleanup of LBS");
  expect(c90 && c90->pin_error <= 1e-9, "arm bend 90: pins exact (1e-9 of the diagonal)");
  expect(c90 && c90->q_mean <= 1.06, "arm bend 90: Q_mean <= 1.06");
  expect(c90 && c90->q_max <= 1.5, "arm bend 90: Q_max <= 1.5");
  expect(c90 && c90->volume >= 0.93, "arm bend 90: volume >= 0.93 of rest");
  for (const char* edit : {"arm bend 90", "arm bend 120", "arm bend 90 + twist 90"}) {
    const Row* c = find(edit, "pose-keeping cleanup of LBS");
    for (const char* base : {"LBS", "DQS", "Delta Mush (LBS)", "Direct Delta Mush", "§7.2 snap of LBS"}) {
      const Row* b = find(edit, base);
      if (!b) continue;
      expect(c && c->q_mean < b->q_mean && c->volume >= std::min(b->volume, 1.0) - 1e-6,
             std::string(edit) + ": cleanup Q_mean below " + base + " at a volume no lower");
    }
  }
  // Rigs: lower Q_mean and Q_max than every baseline, at a volume no lower than theirs (the plain
  // cleanup and the rig defaults), and the rig defaults within 1% of the diagonal of the pose.
  for (const Row& c : rows) {
    if (c.method == kRigDefault)
      expect(c.rms_to_edit <= 0.01, c.edit + ": rig defaults within 1% of the diagonal of the LBS pose");
    if ((c.method != "pose-keeping cleanup of LBS" && c.method != kRigDefault) || c.edit.rfind("arm", 0) == 0)
      continue;
    for (const char* base : {"LBS", "DQS", "Delta Mush (LBS)", "Direct Delta Mush"}) {
      const Row* b = find(c.edit, base);
      if (!b) continue;
      expect(c.q_mean < b->q_mean && c.q_max < b->q_max && c.volume >= std::min(b->volume, 1.0) - 1e-6,
             c.edit + ": cleanup Q_mean and Q_max below " + base + " at a volume no lower");
    }
  }
  const Row* sc = find("sausage bend 90", "pose-keeping cleanup");
  expect(sc && sc->q_mean <= (small ? 1.05 : 1.035), "sausage: Q_mean <= 1.035 (1.05 at the ctest size)");
  expect(sc && std::abs(sc->volume - 1) <= 0.03, "sausage: volume within 3%");
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const Error& e) {
    std::fprintf(stderr, "cleanup_study: %s\n", e.what());
    return e.exit_code();
  }
}
