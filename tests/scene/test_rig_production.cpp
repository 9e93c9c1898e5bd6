// Production rigs (scene/rig_cleanup.hpp, scene/rig_pose.hpp, deform/gltf_correctives.hpp): the rig
// cleanup on a surface of many pieces (closed, open, rigid, blended without an anchor, non-manifold,
// with a degenerate triangle) that never aborts and reports each piece; the procedural character in every
// layout production files come in, posed through the CLI against the independent evaluation of the glTF
// formula (support/gltf_reference.hpp); the cleaned walk as corrective morph targets, played back by the
// independent evaluation within the error bound.
#include <unistd.h>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>

#include "cli_support.hpp"
#include "gltf_reference.hpp"
#include "shared_data.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/gltf_correctives.hpp"
#include "spinmotor/deform/gltf_skin.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/gltf_rig_writer.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics.hpp"
#include "spinmotor/mesh/procedural_rig.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"
#include "spinmotor/scene/rig_pose.hpp"

namespace test_rig_production {

using namespace spinmotor;
using nlohmann::json;
namespace fs = std::filesystem;
using scene::RigPieceStatus;

namespace {

double diagonal(const Eigen::MatrixXd& V) { return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm(); }

double signed_volume(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  double s = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    s += Eigen::Vector3d(V.row(F(f, 0)))
             .dot(Eigen::Vector3d(V.row(F(f, 1))).cross(Eigen::Vector3d(V.row(F(f, 2)))));
  return s / 6;
}

double area(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  double s = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    s += 0.5 * (Eigen::Vector3d(V.row(F(f, 1)) - V.row(F(f, 0)))
                    .cross(Eigen::Vector3d(V.row(F(f, 2)) - V.row(F(f, 0)))))
                   .norm();
  return s;
}

/// A surface of many pieces on two bones (upper: bone 0, lower: bone 1, the joint at z = 1):
///   0 arm    a closed capsule on z ∈ [0, 2], smoothstep weights over z ∈ [0.75, 1.25];
///   1 helmet a closed sphere at (2, 0, 0) on bone 0 alone (moves rigidly);
///   2 ball   a closed sphere at (−2, 0, 0) weighted ½ / ½ everywhere (no pin, no attraction);
///   3 cape   an open tube at (0, 2, ·) with weights from 0.6 to 0.95 along z (no pin, attracted);
///   4 bowtie two fans of triangles joined at one vertex (non-manifold) at (0, −2, 1), blended like the
///            arm, plus a degenerate triangle (a vertex on an edge's midpoint) whose third vertex no
///            other triangle holds.
struct Pieces {
  Mesh mesh;
  Eigen::MatrixXd W;
  std::vector<Bone> bones;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> ranges;  // vertex range of each part
};

void append(Pieces& p, const Mesh& m, const std::function<double(const Eigen::Vector3d&)>& lower) {
  const Eigen::Index v0 = p.mesh.V.rows(), f0 = p.mesh.F.rows();
  p.mesh.V.conservativeResize(v0 + m.V.rows(), 3);
  p.mesh.V.bottomRows(m.V.rows()) = m.V;
  p.mesh.F.conservativeResize(f0 + m.F.rows(), 3);
  p.mesh.F.bottomRows(m.F.rows()) = m.F.array() + static_cast<int>(v0);
  p.W.conservativeResize(v0 + m.V.rows(), 2);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    const double w = lower(m.V.row(i).transpose());
    p.W(v0 + i, 0) = 1 - w, p.W(v0 + i, 1) = w;
  }
  p.ranges.emplace_back(v0, m.V.rows());
}

Pieces make_pieces() {
  Pieces p;
  p.mesh.V.resize(0, 3), p.mesh.F.resize(0, 3);
  p.bones = {{.name = "upper", .parent = -1, .head = {0, 0, 0}, .tail = {0, 0, 1}},
             {.name = "lower", .parent = 0, .head = {0, 0, 1}, .tail = {0, 0, 2}}};
  auto smooth = [](const Eigen::Vector3d& x) {
    const double u = std::clamp((x.z() - 0.75) / 0.5, 0.0, 1.0);
    return u * u * (3 - 2 * u);
  };
  append(p, capsule(0.3, 2.0, 48, 24), smooth);
  Mesh s = icosphere(2, 0.2);
  s.V.rowwise() += Eigen::RowVector3d(2, 0, 0);
  append(p, s, [](const Eigen::Vector3d&) { return 0.0; });
  s.V.rowwise() += Eigen::RowVector3d(-4, 0, 0);
  append(p, s, [](const Eigen::Vector3d&) { return 0.5; });
  Mesh cape = tube(0.2, 1.0, 12, 16);
  cape.V.rowwise() += Eigen::RowVector3d(0, 2, 0.5);
  append(p, cape, [](const Eigen::Vector3d& x) { return 0.05 + 0.35 * std::clamp(x.z() - 0.5, 0.0, 1.0); });
  Mesh bow;
  bow.V.resize(8, 3);
  bow.V << 0, -2, 1, 0.3, -2, 0.7, 0.3, -2, 1.3, 0.5, -2, 1, -0.3, -2, 0.7, -0.3, -2, 1.3, -0.5, -2, 1, 0.4,
      -2, 0.85;
  bow.F.resize(5, 3);
  bow.F << 0, 1, 3, 0, 3, 2, 0, 5, 6, 0, 6, 4, 1, 3,
      7;  // 7 = midpoint of 1–3: the last triangle is degenerate
  bow.V.row(7) = 0.5 * (bow.V.row(1) + bow.V.row(3));
  append(p, bow, smooth);
  return p;
}

Eigen::MatrixXd lbs(const Pieces& p, double degrees) {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(degrees * std::numbers::pi / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d e(0, 0, 1);
  Eigen::MatrixXd E = p.mesh.V;
  for (Eigen::Index i = 0; i < E.rows(); ++i) {
    const Eigen::Vector3d x = p.mesh.V.row(i).transpose();
    E.row(i) = (p.W(i, 0) * x + p.W(i, 1) * (e + R * (x - e))).transpose();
  }
  return E;
}

}  // namespace

TEST_CASE("rig cleanup: every piece of a many-piece, non-manifold surface gets a status, none aborts",
          "[rig][pieces]") {
  const Pieces p = make_pieces();
  scene::RigCleanupOptions o;
  o.pin_margin = 0.1;
  scene::RigCleanup rc = scene::RigCleanup::bind(p.mesh, p.W, p.bones, o);
  const auto& pieces = rc.pieces();
  REQUIRE(pieces.size() == 6);  // the five parts and the vertex only the degenerate triangle holds
  auto piece_of = [&](Eigen::Index v) {
    for (size_t k = 0; k < pieces.size(); ++k)
      if (std::find(pieces[k].vertices.begin(), pieces[k].vertices.end(), v) != pieces[k].vertices.end())
        return k;
    FAIL("vertex " << v << " in no piece");
    return size_t(0);
  };
  const auto &arm = pieces[piece_of(p.ranges[0].first)], &helmet = pieces[piece_of(p.ranges[1].first)],
             &ball = pieces[piece_of(p.ranges[2].first)], &cape = pieces[piece_of(p.ranges[3].first)],
             &bow = pieces[piece_of(p.ranges[4].first)], &lone = pieces[piece_of(p.ranges[4].first + 7)];
  CHECK(arm.status == RigPieceStatus::Cleaned);
  CHECK(arm.keep == CleanupKeep::Volume);
  CHECK(arm.pins > 0);
  CHECK(helmet.status ==
        RigPieceStatus::Pinned);  // weight 1 on one bone, far from any blend: every vertex a pin
  CHECK(ball.status == RigPieceStatus::Unanchored);
  CHECK(ball.pins == 0);
  CHECK(cape.status == RigPieceStatus::Cleaned);  // anchored by the attraction alone
  CHECK(cape.pins == 0);
  CHECK(cape.keep == CleanupKeep::Area);
  CHECK(bow.status == RigPieceStatus::Cleaned);
  CHECK(bow.keep == CleanupKeep::Area);
  CHECK(bow.degenerate == 1);
  CHECK(lone.status == RigPieceStatus::Pinned);
  CHECK(lone.vertices.size() == 1);
  CHECK(static_cast<size_t>(rc.cleaned_vertices()) ==
        arm.vertices.size() + cape.vertices.size() + bow.vertices.size());

  const Eigen::MatrixXd E = lbs(p, 70);
  Eigen::MatrixXd V;
  const scene::RigCleanupResult r = rc(E, V);
  CHECK(r.converged);
  CHECK(r.pin_error == 0);
  // Pieces not cleaned are the edit, bit for bit; pins too.
  for (const auto* q : {&helmet, &ball, &lone})
    for (int v : q->vertices) CHECK(V.row(v) == E.row(v));
  for (int v : rc.pins()) CHECK(V.row(v) == E.row(v));
  // The arm keeps its rest volume and becomes more conformal; the cape keeps its area.
  auto sub = [&](const scene::RigCleanupPiece& q, const Eigen::MatrixXd& X) {
    std::vector<int> local(X.rows(), -1);
    Eigen::MatrixXd Y(q.vertices.size(), 3);
    for (size_t k = 0; k < q.vertices.size(); ++k)
      local[q.vertices[k]] = static_cast<int>(k), Y.row(k) = X.row(q.vertices[k]);
    std::vector<Eigen::RowVector3i> faces;
    for (Eigen::Index f = 0; f < p.mesh.F.rows(); ++f)
      if (local[p.mesh.F(f, 0)] >= 0)
        faces.emplace_back(local[p.mesh.F(f, 0)], local[p.mesh.F(f, 1)], local[p.mesh.F(f, 2)]);
    Eigen::MatrixXi F(faces.size(), 3);
    for (size_t f = 0; f < faces.size(); ++f) F.row(f) = faces[f];
    return std::pair{Y, F};
  };
  const auto [arm_rest, arm_F] = sub(arm, p.mesh.V);
  const auto [arm_edit, unused1] = sub(arm, E);
  const auto [arm_out, unused2] = sub(arm, V);
  CHECK(signed_volume(arm_out, arm_F) / signed_volume(arm_rest, arm_F) == Approx(1).margin(1e-6));
  CHECK(signed_volume(arm_edit, arm_F) / signed_volume(arm_rest, arm_F) < 0.995);  // LBS lost volume
  MetricsOptions mo;
  mo.willmore = false;
  CHECK(compute_metrics(arm_rest, arm_F, arm_out, mo).q_mean <
        compute_metrics(arm_rest, arm_F, arm_edit, mo).q_mean - 0.02);
  const auto [cape_rest, cape_F] = sub(cape, p.mesh.V);
  const auto [cape_out, unused3] = sub(cape, V);
  CHECK(area(cape_out, cape_F) / area(cape_rest, cape_F) == Approx(1).margin(1e-6));
  // Metrics skip the degenerate rest triangle when asked, and count it.
  mo.skip_degenerate_rest = true;
  const DeformationMetrics all = compute_metrics(p.mesh.V, p.mesh.F, V, mo);
  CHECK(all.degenerate_rest_faces == 1);
  CHECK(std::isfinite(all.q_mean));
  mo.skip_degenerate_rest = false;
  CHECK_THROWS_WITH(compute_metrics(p.mesh.V, p.mesh.F, V, mo), Catch::Contains("degenerate"));

  // γ = 0: the cape has nothing to hold it either; still no abort.
  o.cleanup.pose_weight = 0;
  scene::RigCleanup rc0 = scene::RigCleanup::bind(p.mesh, p.W, p.bones, o);
  CHECK(rc0.pieces()[piece_of(p.ranges[3].first)].status == RigPieceStatus::Unanchored);
  CHECK(rc0.pieces()[piece_of(p.ranges[0].first)].status == RigPieceStatus::Cleaned);
}

TEST_CASE("rig pose: the character in every layout equals the independent glTF formula, through the CLI",
          "[rig][layouts]") {
  spinmotor_test::TempDir tmp;
  struct Layout {
    const char* name;
    CharacterLayout layout;
    bool offset;
  };
  for (const Layout& l :
       {Layout{"scene", CharacterLayout::Scene, false}, Layout{"mixamo", CharacterLayout::Mixamo, true},
        Layout{"armature", CharacterLayout::Armature, true}}) {
    INFO(l.name);
    const fs::path file = tmp.path / (std::string(l.name) + ".gltf");  // data: URI (the reference reads it)
    write_gltf_rig(file, character_rig({.layout = l.layout, .mesh_node_offset = l.offset, .resolution = 1}));
    const GltfRig rig = read_gltf(file);
    const test::GltfReference ref(file);
    REQUIRE(ref.skinned.size() == 7);
    const double diag = diagonal(rig_skin(rig).rest.V);
    for (int anim : {0, 1})
      for (double t : {0.0, 0.3, 0.65}) {
        INFO("animation " << anim << " t " << t);
        const auto r = spinmotor_test::run_cli(
            tmp.path, "rig pose " + file.string() + " --animation " + std::to_string(anim) + " --time " +
                          std::to_string(t) + " --out " + tmp.file("posed.obj"));
        INFO(r.err);
        REQUIRE(r.code == 0);
        const Mesh posed = read_mesh(tmp.path / "posed.obj");
        const std::vector<Eigen::Vector3d> x = ref.skin(anim, t);
        double worst = 0;
        for (Eigen::Index i = 0; i < rig.file_vertices; ++i)
          worst = std::max(worst, (posed.V.row(rig.file_to_surface[i]).transpose() - x[i]).norm());
        CHECK(worst <= 1e-9 * diag);  // the OBJ holds the shortest round-trip digits
      }
    // Every layout is the same character in the scene (1.845 tall): the formula's rest pose.
    const std::vector<Eigen::Vector3d> rest = ref.skin(-1, 0);
    double top = -1e9;
    for (const auto& x : rest) top = std::max(top, x.y());
    CHECK(top == Approx(1.845).margin(1e-5));
  }
}

TEST_CASE(
    "corrective export: a few morph targets reproduce the cleaned walk within the bound, played back "
    "independently",
    "[rig][correctives]") {
  spinmotor_test::TempDir tmp;
  const GltfRig rig =
      character_rig({.layout = CharacterLayout::Mixamo, .mesh_node_offset = true, .walk_degrees = 50});
  scene::RigPoseOptions o{.animation = 0, .blend = SkinBlend::LBS, .cleanup = scene::RigCleanupMode::Pinned};
  o.cleanup_options.cleanup.warm_start = true;
  scene::RigPoser poser(rig, o);
  const std::vector<double> times = scene::rig_frame_times(rig, 0, 17);
  std::vector<Eigen::MatrixXd> frames;
  for (double t : times) frames.push_back(poser.pose_scene(t));
  const double diag = diagonal(poser.rig_skin().rest.V);
  // The frames differ from the skinning (the cleanup did something the targets must carry).
  Eigen::MatrixXd skinned;
  poser.skin(times[4], skinned);
  REQUIRE((frames[4] - skinned).rowwise().norm().maxCoeff() > 1e-3 * diag);
  for (const double bound : {1e-3, 1e-4}) {
    INFO("bound " << bound);
    const CorrectiveRig cr = corrective_rig(rig, 0, times, frames, {.max_error = bound});
    CHECK(cr.bound_met);
    CHECK(cr.max_error <= bound);
    int total = 0;
    for (size_t p = 0; p < rig.pieces.size(); ++p) {
      total += cr.targets[p];
      CHECK(cr.rig.pieces[p].num_targets() == rig.pieces[p].num_targets() + cr.targets[p]);
    }
    for (const GltfChannel& c : cr.rig.animations.at(0).channels)  // Blender clamps shape keys to [0, 1]
      if (c.path == GltfPath::Weights) CHECK((c.values.minCoeff() >= 0 && c.values.maxCoeff() <= 1 + 1e-15));
    CHECK(cr.targets[1] == 0);  // the head moves rigidly: no corrective
    CHECK(cr.targets[6] == 0);  // nor its cap
    CHECK(total > 0);
    CHECK(total < 17 * 5);  // fewer than one target per frame and cleaned piece
    const fs::path out = tmp.path / "correctives.gltf";
    write_gltf_rig(out, cr.rig);
    // Played back by the independent evaluation of the glTF formula (joints, morph targets, weights
    // channel): the cleaned frames to the bound plus float32 storage.
    const test::GltfReference ref(out);
    const GltfRig back = read_gltf(out);
    double worst = 0;
    for (size_t f = 0; f < times.size(); ++f) {
      const std::vector<Eigen::Vector3d> x = ref.skin(0, times[f]);
      for (Eigen::Index i = 0; i < back.file_vertices; ++i)
        worst = std::max(worst, (frames[f].row(back.file_to_surface[i]).transpose() - x[i]).norm());
    }
    WARN("bound " << bound << ": " << total << " corrective targets, max error " << cr.max_error
                  << " (computed), " << worst / diag << " (played back) of the diagonal");
    CHECK(worst <= (bound + 2e-6) * diag);
  }
  // Bad input names the problem.
  CHECK_THROWS_WITH(corrective_rig(rig, 0, {0.0}, frames, {}), Catch::Contains("17 frames for 1 times"));
  CHECK_THROWS_WITH(corrective_rig(rig, 5, times, frames, {}), Catch::Contains("animation 5 out of range"));
  CHECK_THROWS_WITH(corrective_rig(rig, 0, times, frames, {.max_error = 0}), Catch::Contains("max_error"));
}

TEST_CASE("rig pose --bake correctives and --json through the CLI, bad options exit 2 and write nothing",
          "[rig][correctives]") {
  spinmotor_test::TempDir tmp;
  write_gltf_rig(tmp.path / "c.glb", character_rig({.layout = CharacterLayout::Mixamo}));
  auto r = spinmotor_test::run_cli(
      tmp.path, "rig pose " + tmp.file("c.glb") +
                    " --frames 9 --cleanup pinned --bake correctives --json --out " + tmp.file("fix.glb"));
  INFO(r.err);
  REQUIRE(r.code == 0);
  const json j = json::parse(r.out);
  CHECK(j["correctives"]["bound_met"] == true);
  CHECK(j["correctives"]["max_error"].get<double>() <= 1e-3);
  REQUIRE(j["frames"].size() == 9);
  REQUIRE(j["cleanup"]["pieces"].size() == 7);
  CHECK(j["cleanup"]["statuses"]["cleaned"].get<int>() >= 3);
  for (const json& f : j["frames"]) {
    CHECK(f["cleaned"]["q_max"].get<double>() <= f["skinned"]["q_max"].get<double>() + 1e-9);
    CHECK(f["cleaned"]["volume_ratio"].get<double>() == Approx(1).margin(1e-4));
  }
  const GltfRig back = read_gltf(tmp.path / "fix.glb");
  CHECK(back.animations.size() == 1);
  CHECK(back.pieces[0].num_targets() > 0);
  r = spinmotor_test::run_cli(tmp.path, "rig pose " + tmp.file("c.glb") +
                                            " --frames 9 --cleanup pinned --out " + tmp.file("frames.glb"));
  REQUIRE(r.code == 0);
  WARN("9 cleaned frames: correctives " << fs::file_size(tmp.path / "fix.glb") << " bytes, per-frame bake "
                                        << fs::file_size(tmp.path / "frames.glb") << " bytes");
  for (const std::string& args :
       {"--bake correctives --out " + tmp.file("x.obj"),
        "--bake correctives --space mesh --out " + tmp.file("x.glb"),
        "--bake sideways --out " + tmp.file("x.glb"), "--mesh Nope --out " + tmp.file("x.glb"),
        "--max-error 0 --bake correctives --out " + tmp.file("x.glb")}) {
    INFO(args);
    r = spinmotor_test::run_cli(tmp.path, "rig pose " + tmp.file("c.glb") + " --frames 3 " + args);
    CHECK(r.code == 2);
    CHECK(!fs::exists(tmp.path / "x.glb"));
    CHECK(!fs::exists(tmp.path / "x.obj"));
  }
  // --mesh picks pieces; OBJ output holds one object per piece.
  r = spinmotor_test::run_cli(
      tmp.path,
      "rig pose " + tmp.file("c.glb") + " --time 0.3 --mesh ArmL --mesh LegR --out " + tmp.file("two.obj"));
  REQUIRE(r.code == 0);
  CHECK(read_mesh(tmp.path / "two.obj").V.rows() ==
        read_gltf(tmp.path / "c.glb", {.meshes = {"ArmL", "LegR"}}).mesh.V.rows());
}

}  // namespace test_rig_production
