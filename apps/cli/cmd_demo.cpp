// `spinmotor demo`: the main job on embedded defaults. Generates its own inputs (procedural meshes),
// runs a representative case of each of the project's three uses — handle-based posing (then the
// conformal snap and the pose-keeping cleanup of the pose), IK-driven spline deformation, conformal
// cleanup of a rigged edit (snap and pose-keeping cleanup with the rigid parts pinned; then a glTF
// character the project writes itself, posed from its animation, cleaned up and baked back) — plus
// a closed-form twist snapped back (Crane 2011 Fig. 21) and a painted spin transformation, writes
// meshes + one metrics JSON to out/, and prints one summary table (sizes, bind/pose/snap times, Q).
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "command.hpp"
#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/deform/gltf_correctives.hpp"
#include "spinmotor/deform/gltf_skin.hpp"
#include "spinmotor/deform/rig_pins.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/deform/spline_deformer.hpp"
#include "spinmotor/deform/spline_ik.hpp"
#include "spinmotor/deform/surface_harmonic.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/mesh/gltf_rig_writer.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics.hpp"
#include "spinmotor/mesh/metrics/json.hpp"
#include "spinmotor/mesh/procedural_rig.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"
#include "spinmotor/scene/rig_pose.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"
#include "spinmotor/spin/spin_transform.hpp"
#include "summary_table.hpp"

namespace spinmotor::cli {
namespace {

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

/// 1. The embedded default: a capsule (closed, genus 0, with texture coordinates).
Mesh stage_capsule(Demo& d) {
  auto t0 = std::chrono::steady_clock::now();
  const Mesh capsule_mesh = capsule(0.5, 3.0, 96, 48);
  const MeshReport report = validate(capsule_mesh);
  if (report.has_defects()) throw numerical_error("demo: the generated capsule has defects");
  const double gen_ms = ms_since(t0);
  write_mesh(d.out_dir / "capsule.obj", capsule_mesh);
  d.row("capsule: generate + validate", capsule_mesh, gen_ms, 1.0, 1.0, "capsule.obj");
  d.report["capsule"] = {{"vertices", report.vertices},
                         {"faces", report.faces},
                         {"genus", report.genus},
                         {"generate_validate_ms", gen_ms}};
  d.progress("generated and validated the capsule");

  return capsule_mesh;
}

/// 2. A non-conformal edit (twist 90° along the axis), measured with the quality metrics.
Mesh stage_twist(Demo& d, const Mesh& capsule_mesh) {
  auto t0 = std::chrono::steady_clock::now();
  Mesh twisted = capsule_mesh;
  twisted.V = twist_z(capsule_mesh.V, 0.0, 3.0, 90.0);
  const DeformationMetrics tm = compute_metrics(capsule_mesh, twisted.V);
  const double twist_ms = ms_since(t0);
  write_mesh(d.out_dir / "capsule-twisted.obj", twisted);
  d.row("twist 90 deg (closed form) + metrics", twisted, twist_ms, tm.q_mean, tm.q_max,
        "capsule-twisted.obj");
  d.report["twist"] = to_json(tm);
  d.progress("twisted the capsule and measured it");

  return twisted;
}

/// 3. Handle-based posing: surface harmonic coordinates with motor handles (CGA paper §IV). The
///    bottom cap stays, the top cap turns 60° about x around the top of the cylinder and moves.
Mesh stage_pose(Demo& d, const Mesh& capsule_mesh, std::vector<Handle>& handles) {
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
  handles = {base, tip};
  auto t0 = std::chrono::steady_clock::now();
  auto deformer = SurfaceHarmonicDeformer::bind(capsule_mesh, handles);
  const double bind_ms = ms_since(t0);
  Eigen::Isometry3d tip_pose = Eigen::Isometry3d::Identity();
  tip_pose.translate(Eigen::Vector3d(0.0, 0.6, 3.0));
  tip_pose.rotate(Eigen::AngleAxisd(std::numbers::pi / 3.0, Eigen::Vector3d::UnitX()));
  tip_pose.translate(Eigen::Vector3d(0.0, 0.0, -3.0));
  const std::vector<ga::Mot> motors{ga::from_isometry(Eigen::Isometry3d::Identity()),
                                    ga::from_isometry(tip_pose)};
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

  return posed;
}

/// 3b. The conformal snap (Crane 2011 §7.2) of both edits, from one bind on the rest capsule: the
///     twist is not conformal and snaps back towards the untwisted capsule; the pose gives part of its
///     bend away.
void stage_snaps(Demo& d, const Mesh& capsule_mesh, const Mesh& twisted, const Mesh& posed) {
  auto t0 = std::chrono::steady_clock::now();
  ConformalSnap snapper(capsule_mesh);
  const double snap_bind_ms = ms_since(t0);
  d.row("conformal snap bind (rest capsule)", capsule_mesh, snap_bind_ms, std::nan(""), std::nan(""), "");
  for (const auto& [name, edit] :
       {std::pair<std::string, const Mesh*>{"twist", &twisted}, {"pose", &posed}}) {
    t0 = std::chrono::steady_clock::now();
    const ConformalSnapResult r = snapper.snap(edit->V);
    const double ms = ms_since(t0);
    const DeformationMetrics m = compute_metrics(capsule_mesh, r.V);
    Mesh snapped = capsule_mesh;
    snapped.V = r.V;
    const std::string file = "capsule-" + name + "-snapped.obj";
    write_mesh(d.out_dir / file, snapped);
    d.row("conformal snap of the " + name, snapped, ms, m.q_mean, m.q_max, file);
    d.report["snap_" + name] = to_json(m);
    d.report["snap_" + name]["snap_ms"] = ms;
    d.report["snap_" + name]["rms_to_edit"] =
        std::sqrt((r.V - edit->V).rowwise().squaredNorm().mean()) / m.diagonal;
  }
  d.report["snap_bind_ms"] = snap_bind_ms;
  d.progress("snapped the twist and the pose");
}

/// Root mean square distance between two vertex sets, relative to the bounding-box diagonal of `to`.
double rms_to(const Eigen::MatrixXd& V, const Eigen::MatrixXd& to) {
  return std::sqrt((V - to).rowwise().squaredNorm().mean()) /
         (to.colwise().maxCoeff() - to.colwise().minCoeff()).norm();
}

/// 3c. The pose-keeping cleanup (spin/pinned_cleanup.hpp) of the pose: the handles' vertices stay
///     exactly where the deformer put them, the rest is made as conformal as possible at the rest volume.
///     Two end caps pin little, so a pose attraction of γ = 1 holds the body near the bend (without it
///     the body straightens: 10.7% of the diagonal from the pose at Q_mean 1.018, with it 4.8% at 1.033).
void stage_pose_cleanup(Demo& d, const Mesh& capsule_mesh, const Mesh& posed,
                        std::span<const Handle> handles) {
  std::vector<int> pins;
  for (const Handle& h : handles)
    pins.insert(pins.end(), h.vertices.data(), h.vertices.data() + h.vertices.size());
  auto t0 = std::chrono::steady_clock::now();
  PinnedCleanupOptions options;
  options.pose_weight = 1;
  PinnedCleanup cleanup = PinnedCleanup::bind(capsule_mesh, pins, options);
  const double bind_ms = ms_since(t0);
  Mesh cleaned = capsule_mesh;
  t0 = std::chrono::steady_clock::now();
  const PinnedCleanupResult r = cleanup.cleanup(posed.V, cleaned.V);
  const double ms = ms_since(t0);
  const DeformationMetrics m = compute_metrics(capsule_mesh, cleaned.V);
  write_mesh(d.out_dir / "capsule-pose-cleaned.obj", cleaned);
  d.row("pinned cleanup bind (handles pinned)", capsule_mesh, bind_ms, std::nan(""), std::nan(""), "");
  d.row("pinned cleanup of the pose", cleaned, ms, m.q_mean, m.q_max, "capsule-pose-cleaned.obj");
  d.report["cleanup_pose"] = to_json(m);
  d.report["cleanup_pose"]["bind_ms"] = bind_ms;
  d.report["cleanup_pose"]["cleanup_ms"] = ms;
  d.report["cleanup_pose"]["iterations"] = r.iterations;
  d.report["cleanup_pose"]["volume_ratio"] = r.measure_ratio();
  d.report["cleanup_pose"]["pin_error"] = r.pin_error;
  d.report["cleanup_pose"]["pose_weight"] = options.pose_weight;
  d.report["cleanup_pose"]["rms_to_edit"] = rms_to(cleaned.V, posed.V);
  d.progress("cleaned the pose up with the handles pinned");
}

/// 4. A spin transformation (Crane et al. 2011): paint a bump of curvature change ρ on the side of
///    the capsule; the result is conformal by construction (Q stays near 1).
void stage_spin(Demo& d, const Mesh& capsule_mesh) {
  Eigen::VectorXd rho(capsule_mesh.num_faces());
  const Eigen::RowVector3d bump_centre(0.5, 0.0, 1.5);
  for (Eigen::Index f = 0; f < capsule_mesh.num_faces(); ++f) {
    const Eigen::RowVector3d c =
        (capsule_mesh.V.row(capsule_mesh.F(f, 0)) + capsule_mesh.V.row(capsule_mesh.F(f, 1)) +
         capsule_mesh.V.row(capsule_mesh.F(f, 2))) /
        3.0;
    rho[f] = 4.0 * std::exp(-(c - bump_centre).squaredNorm() / (2 * 0.3 * 0.3));
  }
  auto t0 = std::chrono::steady_clock::now();
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

/// 5. IK-driven spline deformation (CGA paper §III.C): a tube tentacle's 5-joint FABRIK chain reaches
///    a target; the joint motors are fitted by a cubic B-spline that drives the spline deformer.
void stage_ik(Demo& d) {
  const Mesh tube_mesh = tube(0.25, 4.0, 161, 32);
  auto ring = [&](double z, const char* name) {
    std::vector<int> v;
    for (Eigen::Index i = 0; i < tube_mesh.V.rows(); ++i)
      if (std::abs(tube_mesh.V(i, 2) - z) < 1e-9) v.push_back(static_cast<int>(i));
    return Handle{name, Eigen::Map<Eigen::VectorXi>(v.data(), static_cast<Eigen::Index>(v.size()))};
  };
  const Handle ends[2] = {ring(0.0, "base"), ring(4.0, "tip")};
  Eigen::MatrixXd chain(5, 3);
  for (int i = 0; i < 5; ++i) chain.row(i) << 0.0, 0.0, i;
  const Eigen::Vector3d target(1.5, 0.5, 3.0);
  auto t0 = std::chrono::steady_clock::now();
  // The rest target is the tip joint; the pose's one motor carries it to `target` (FABRIK + fit + pose).
  Rig ik_rig{.handles = {ends[0], ends[1]}};
  ik_rig.ik =
      IkChain{.chain = chain, .target = chain.row(4).transpose(), .tolerance = 1e-6, .iterations = 100};
  SplineIkDeformer spline = SplineIkDeformer::bind(tube_mesh, ik_rig, {.controls = 5, .degree = 3});
  const double spline_bind_ms = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  Mesh bent = tube_mesh;
  const ga::Mot to_target =
      ga::from_isometry(Eigen::Isometry3d(Eigen::Translation3d(target - chain.row(4).transpose())));
  spline.pose(std::span(&to_target, 1), bent.V);
  const double ik_pose_ms = ms_since(t0);
  Eigen::Vector3d tip_centre = Eigen::Vector3d::Zero();
  for (Eigen::Index k = 0; k < ends[1].vertices.size(); ++k)
    tip_centre += bent.V.row(ends[1].vertices[k]).transpose();
  tip_centre /= static_cast<double>(ends[1].vertices.size());
  const DeformationMetrics im = compute_metrics(tube_mesh, bent.V);
  write_mesh(d.out_dir / "tube-ik.obj", bent);
  d.row("spline bind (tube, harmonic parameter)", tube_mesh, spline_bind_ms, std::nan(""), std::nan(""), "");
  d.row("IK + B-spline fit + spline pose", bent, ik_pose_ms, im.q_mean, im.q_max, "tube-ik.obj");
  d.report["ik_spline"] = to_json(im);
  d.report["ik_spline"]["bind_ms"] = spline_bind_ms;
  d.report["ik_spline"]["ik_fit_pose_ms"] = ik_pose_ms;
  d.report["ik_spline"]["tip_error"] = (tip_centre - target).norm();
  d.progress("bent the tube with IK");
}

/// 6. Conformal cleanup of a rigged edit: a two-bone arm with harmonic bone weights, the forearm bent
///    90° and twisted 90°, skinned with LBS (the candy wrapper), then snapped (§7.2) and cleaned up
///    with the rig defaults (scene/rig_cleanup.hpp: the bones' rigid parts pinned, the rest held near
///    the pose by the weights' attraction).
void stage_rig(Demo& d) {
  const Mesh arm = capsule(0.3, 4.0, 96, 48);
  const double z0 = arm.V.col(2).minCoeff(), z1 = arm.V.col(2).maxCoeff(), elbow = 0.5 * (z0 + z1);
  std::vector<Bone> bones(2);
  bones[0] = {.name = "upper", .parent = -1, .head = {0, 0, z0}, .tail = {0, 0, elbow}};
  bones[1] = {.name = "fore", .parent = 0, .head = {0, 0, elbow}, .tail = {0, 0, z1}};
  auto t0 = std::chrono::steady_clock::now();
  const Eigen::MatrixXd W = bone_harmonic_weights(arm, bones);
  SkinDeformer skin = SkinDeformer::bind(arm, bones, W, {.blend = SkinDeformer::Blend::LBS});
  const double skin_bind_ms = ms_since(t0);
  auto about = [](const Eigen::Vector3d& axis, double degrees, const Eigen::Vector3d& pivot) {
    return ga::from_isometry(Eigen::Isometry3d(Eigen::Translation3d(pivot) *
                                               Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis) *
                                               Eigen::Translation3d(-pivot)));
  };
  const std::vector<ga::Mot> frames = {ga::from_isometry(Eigen::Isometry3d::Identity()),
                                       about(Eigen::Vector3d::UnitX(), 90, {0, 0, elbow}) *
                                           about(Eigen::Vector3d::UnitZ(), 90, {0, 0, elbow})};
  Mesh skinned = arm;
  t0 = std::chrono::steady_clock::now();
  skin.pose(frames, skinned.V);
  const double skin_pose_ms = ms_since(t0);
  const DeformationMetrics km = compute_metrics(arm, skinned.V);
  write_mesh(d.out_dir / "arm.obj", arm);  // the rest arm (Q pictures: scripts/make-gallery)
  write_mesh(d.out_dir / "arm-lbs.obj", skinned);
  t0 = std::chrono::steady_clock::now();
  const ConformalSnapResult ks = conformal_snap(arm, skinned.V);
  const double arm_snap_ms = ms_since(t0);
  const DeformationMetrics ksm = compute_metrics(arm, ks.V);
  Mesh arm_snapped = arm;
  arm_snapped.V = ks.V;
  write_mesh(d.out_dir / "arm-lbs-snapped.obj", arm_snapped);
  d.row("skin bind (2 bones, harmonic weights)", arm, skin_bind_ms, std::nan(""), std::nan(""), "");
  d.row("skin pose (LBS, bend + twist 90 deg)", skinned, skin_pose_ms, km.q_mean, km.q_max, "arm-lbs.obj");
  d.row("conformal snap of the skinned arm", arm_snapped, arm_snap_ms, ksm.q_mean, ksm.q_max,
        "arm-lbs-snapped.obj");
  // The pose-keeping cleanup with the rig defaults: vertices of one bone (weight ≥ 0.999) farther than
  // a quarter of the elbow's blend width from any blended vertex are pinned, the others attracted to
  // the skinned pose by their dominant weight (γ = 10).
  t0 = std::chrono::steady_clock::now();
  scene::RigCleanup cleanup = scene::RigCleanup::bind(arm, W, bones);
  const Eigen::VectorXi& pins = cleanup.pins();
  const double clean_bind_ms = ms_since(t0);
  Mesh arm_cleaned = arm;
  t0 = std::chrono::steady_clock::now();
  const scene::RigCleanupResult kc = cleanup(skinned.V, arm_cleaned.V);
  const double arm_clean_ms = ms_since(t0);
  const DeformationMetrics kcm = compute_metrics(arm, arm_cleaned.V);
  write_mesh(d.out_dir / "arm-lbs-cleaned.obj", arm_cleaned);
  d.row("pinned cleanup bind (" + std::to_string(pins.size()) + " pins from the weights)", arm, clean_bind_ms,
        std::nan(""), std::nan(""), "");
  d.row("pinned cleanup of the skinned arm", arm_cleaned, arm_clean_ms, kcm.q_mean, kcm.q_max,
        "arm-lbs-cleaned.obj");
  d.report["rig_cleanup"] = {{"lbs", to_json(km)},
                             {"snapped", to_json(ksm)},
                             {"cleaned", to_json(kcm)},
                             {"bind_ms", skin_bind_ms},
                             {"pose_ms", skin_pose_ms},
                             {"snap_ms", arm_snap_ms},
                             {"cleanup_bind_ms", clean_bind_ms},
                             {"cleanup_ms", arm_clean_ms},
                             {"pins", pins.size()},
                             {"cleanup_iterations", kc.iterations},
                             {"volume_ratio_lbs", kc.edit_volume_ratio},
                             {"volume_ratio_cleaned", kc.volume_ratio},
                             {"pin_error", kc.pin_error},
                             {"pose_weight", scene::RigCleanupOptions{}.cleanup.pose_weight},
                             {"rms_to_lbs_snapped", rms_to(ks.V, skinned.V)},
                             {"rms_to_lbs_cleaned", rms_to(arm_cleaned.V, skinned.V)}};
  d.progress("skinned the arm, snapped it and cleaned it up with the rigid parts pinned");
}

/// 7. A glTF character end to end, on the project's own procedural standing figure (procedural_rig.hpp:
///    seven separate pieces on one skin, in the layout Mixamo characters come in through Blender: a
///    scaled, turned armature above centimetre joints, morph targets on the head): written as a skinned
///    .glb and read back, posed mid-stride with LBS (the spec's formula) and DLB, cleaned up piece by piece
///    with the rig defaults, and the cleaned walk stored as a few corrective morph targets on the rig.
void stage_gltf_rig(Demo& d) {
  const std::filesystem::path file = d.out_dir / "character-rig.glb";
  auto t0 = std::chrono::steady_clock::now();
  write_gltf_rig(file, character_rig({.layout = CharacterLayout::Mixamo, .walk_degrees = 50}));
  const GltfRig rig = read_gltf(file);
  const double io_ms = ms_since(t0);
  const int walk = 0;
  const double t = 0.25;  // mid-stride
  scene::RigPoseOptions po;
  po.animation = walk;
  po.blend = SkinBlend::LBS;
  scene::RigPoser lbs_poser(rig, po);
  po.blend = SkinBlend::DLB;
  scene::RigPoser dlb_poser(rig, po);
  const Mesh& rest = lbs_poser.rig_skin().rest;
  Mesh lbs = rest, dlb = rest;
  t0 = std::chrono::steady_clock::now();
  lbs.V = lbs_poser.pose(t);
  const double lbs_ms = ms_since(t0);
  dlb.V = dlb_poser.pose(t);
  const MetricsOptions mo{.willmore = false, .skip_degenerate_rest = true};
  const DeformationMetrics ml = compute_metrics(rest.V, rest.F, lbs.V, mo),
                           md = compute_metrics(rest.V, rest.F, dlb.V, mo);
  const WriteOptions pieces = [&] {
    WriteOptions w;
    for (const GltfPiece& p : rig.pieces) w.objects.emplace_back(p.name, p.first_face);
    return w;
  }();
  write_mesh(d.out_dir / "character-rest.obj", rest, pieces);
  write_mesh(d.out_dir / "character-lbs.obj", lbs, pieces);
  write_mesh(d.out_dir / "character-dlb.obj", dlb, pieces);
  d.row("glTF rig: write + read character-rig.glb (" + std::to_string(rig.pieces.size()) + " meshes)", rest,
        io_ms, std::nan(""), std::nan(""), "character-rig.glb");
  d.row("rig pose (LBS, walk t = 0.25 s)", lbs, lbs_ms, ml.q_mean, ml.q_max, "character-lbs.obj");
  d.row("rig pose (DLB, walk t = 0.25 s)", dlb, std::nan(""), md.q_mean, md.q_max, "character-dlb.obj");
  // The pose-keeping cleanup with the rig defaults (scene/rig_cleanup.hpp), piece by piece.
  t0 = std::chrono::steady_clock::now();
  scene::RigPoseOptions co;
  co.animation = walk;
  co.blend = SkinBlend::LBS;
  co.cleanup = scene::RigCleanupMode::Pinned;
  co.cleanup_options.cleanup.warm_start = true;
  scene::RigPoser poser(rig, co);
  const double bind_ms = ms_since(t0);
  Mesh cleaned = rest;
  t0 = std::chrono::steady_clock::now();
  cleaned.V = poser.pose(t);
  const double clean_ms = ms_since(t0);
  const scene::RigCleanupResult r = poser.last_cleanup();
  const DeformationMetrics mc = compute_metrics(rest.V, rest.F, cleaned.V, mo);
  write_mesh(d.out_dir / "character-cleaned.obj", cleaned, pieces);
  std::map<std::string, int> statuses;
  for (const scene::RigCleanupPiece& p : poser.cleanup()->pieces())
    ++statuses[std::string(option_name(p.status))];
  d.row("rig cleanup bind (" + std::to_string(poser.cleanup()->pins().size()) + " pins, " +
            std::to_string(statuses["cleaned"]) + " of " + std::to_string(poser.cleanup()->pieces().size()) +
            " pieces to clean)",
        rest, bind_ms, std::nan(""), std::nan(""), "");
  d.row("rig cleanup of the LBS walk", cleaned, clean_ms, mc.q_mean, mc.q_max, "character-cleaned.obj");
  // The cleaned walk (9 frames) as corrective morph targets on the rig (Blender, three.js: shape keys).
  t0 = std::chrono::steady_clock::now();
  const std::vector<double> times = scene::rig_frame_times(rig, walk, 9);
  std::vector<Eigen::MatrixXd> frames;
  poser.cleanup()->reset();
  for (double tf : times) frames.push_back(poser.pose_scene(tf));
  const CorrectiveRig cr = corrective_rig(rig, walk, times, frames);
  write_gltf_rig(d.out_dir / "character-correctives.glb", cr.rig);
  const double bake_ms = ms_since(t0);
  int targets = 0;
  for (int k : cr.targets) targets += k;
  d.row("rig bake: 9 cleaned frames as " + std::to_string(targets) + " corrective targets", rest, bake_ms,
        std::nan(""), std::nan(""), "character-correctives.glb");
  d.report["gltf_rig"] = {{"vertices", rig.mesh.num_vertices()},
                          {"file_vertices", rig.file_vertices},
                          {"meshes", rig.pieces.size()},
                          {"joints", rig.num_joints()},
                          {"write_read_ms", io_ms},
                          {"lbs", to_json(ml)},
                          {"dlb", to_json(md)},
                          {"cleaned", to_json(mc)},
                          {"pins", poser.cleanup()->pins().size()},
                          {"piece_statuses", statuses},
                          {"cleanup_bind_ms", bind_ms},
                          {"cleanup_ms", clean_ms},
                          {"cleanup_iterations", r.iterations},
                          {"volume_ratio_lbs", r.edit_volume_ratio},  // over the closed pieces cleaned
                          {"volume_ratio_cleaned", r.volume_ratio},
                          {"pin_error", r.pin_error},
                          {"corrective_targets", cr.targets},
                          {"corrective_max_error", cr.max_error},
                          {"bake_frames", times.size()},
                          {"bake_ms", bake_ms}};
  d.progress("wrote a glTF character, posed its walk, cleaned it up and baked correctives");
}

void run_demo(Demo& d) {
  const Mesh capsule_mesh = stage_capsule(d);
  const Mesh twisted = stage_twist(d, capsule_mesh);
  std::vector<Handle> handles;
  const Mesh posed = stage_pose(d, capsule_mesh, handles);
  stage_snaps(d, capsule_mesh, twisted, posed);
  stage_pose_cleanup(d, capsule_mesh, posed, handles);
  stage_spin(d, capsule_mesh);
  stage_ik(d);
  stage_rig(d);
  stage_gltf_rig(d);
}

const RegisterCommand register_demo{
    "demo", "Run the main job on embedded procedural meshes; write out/ and print a summary",
    [](CLI::App& sub) {
      auto out = std::make_shared<std::string>("out");
      auto quiet = std::make_shared<bool>(false);
      auto json = std::make_shared<bool>(false);
      sub.add_option("--out", *out, "Output directory")->capture_default_str();
      sub.add_flag("-q,--quiet", *quiet, "Print only the summary table");
      sub.add_flag("--json", *json,
                   "Print the metrics JSON (also written to OUT/demo.json) instead of the table");
      sub.footer(
          "Examples:\n  spinmotor demo\n  spinmotor demo --out /tmp/demo --json | jq .snap_twist.q_mean\n");
      sub.callback([out, quiet, json] {
        Demo d;
        d.out_dir = *out;
        d.quiet = *quiet;
        const auto t0 = std::chrono::steady_clock::now();
        run_demo(d);
        d.report["total_ms"] = ms_since(t0);
        write_text_atomic(d.out_dir / "demo.json", d.report.dump(2) + "\n");
        if (*json) {
          std::cout << d.report.dump(2) << '\n';
          return;
        }
        std::cout << "spinmotor demo: outputs in " << d.out_dir.string() << "/\n\n";
        d.table.print(std::cout);
        std::cout << "\ntotal " << fmt(ms_since(t0), 0) << " ms; metrics in "
                  << (d.out_dir / "demo.json").string() << '\n';
      });
    }};

}  // namespace
}  // namespace spinmotor::cli
