// Scene files naming a glTF rig (docs/scene.md `rig`): the project's procedural limb written to a
// temporary .glb (mesh/procedural_rig.hpp, mesh/gltf_rig_writer.hpp) posed by the skin deformer from its
// animation, against the glTF formula (skin_positions) and closed forms; frame times and numbers; pose
// entries as edits on top of the animation; Delta Mush; "pins": "weights"; errors naming /rig/...
// With ../shared/rigs: CesiumMan through `spinmotor deform`.
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "shared_data.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/mesh/gltf_rig_writer.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/procedural_rig.hpp"
#include "spinmotor/scene/deformer_registry.hpp"
#include "spinmotor/scene/run.hpp"
#include "spinmotor/scene/scene.hpp"

namespace test_scene_rig {

using namespace spinmotor;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

struct Fixture {
  fs::path dir;
  GltfRig rig;  // as read back from limb.glb
  Fixture() : dir(fs::temp_directory_path() / ("spinmotor_scene_rig_" + std::to_string(getpid()))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    LimbRigOptions o;
    o.rings = 48;
    o.sides = 16;
    o.joints = 3;
    o.length = 3.0;  // joints at z = 0, 1, 2
    write_gltf_rig(dir / "limb.glb", limb_rig(o));
    rig = read_gltf(dir / "limb.glb");
  }
  ~Fixture() { fs::remove_all(dir); }

  scene::Scene parse(const json& doc) const { return scene::parse_scene(doc, dir, "rig.json"); }
  /// The posed frames of a scene.
  std::vector<Eigen::MatrixXd> run(const json& doc) const {
    const scene::Scene s = parse(doc);
    std::vector<Eigen::MatrixXd> out;
    for (const auto& f : scene::run_scene(s).frames) out.push_back(f.V);
    return out;
  }
};

json limb_scene(const json& rig_block, const json& deformer = {{"type", "skin"}, {"blend", "lbs"}}) {
  return {{"rig", rig_block}, {"deformer", deformer}};
}

double max_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  REQUIRE(a.rows() == b.rows());
  return (a - b).cwiseAbs().maxCoeff();
}

std::string error_of(const Fixture& f, const json& doc) {
  try {
    const scene::Scene s = f.parse(doc);
    (void)scene::run_scene(s);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE(
    "rig scene: the limb's surface, skeleton and weights, LBS = the glTF formula, rest pose without time") {
  Fixture f;
  const scene::Scene s = f.parse(limb_scene({{"gltf", "limb.glb"}, {"animation", "bend"}, {"time", 1.0}}));
  REQUIRE(s.rig);
  CHECK(s.rig->animation == 0);
  CHECK(s.mesh.V == f.rig.mesh.V);
  CHECK(s.mesh.F == f.rig.mesh.F);
  CHECK_FALSE(s.animated);
  REQUIRE(s.frames.size() == 1);
  REQUIRE(s.frames[0].time);
  CHECK(*s.frames[0].time == 1.0);

  const std::unique_ptr<scene::SceneDeformer> d = scene::bind_deformer(s);
  CHECK(d->control_names() == std::vector<std::string>{"joint0", "joint1", "joint2"});
  REQUIRE(d->skin());
  CHECK(d->skin()->weights.cols() == 3);
  const scene::RunResult r = scene::run_scene(s);
  // SkinDeformer's LBS with the motors of S_j against the matrix formula: the float32 file leaves
  // rotations unit to ~1e-7.
  const double lbs = max_diff(r.frames[0].V, skin_positions(f.rig, 0, 1.0));
  CHECK(lbs <= 2e-6);
  // And the closed form: the top segment (weight 1 on joint2) turned 60° about x at z = 1, then again
  // at z = 2: p' = e + R (e + R (p − 2e)).
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(std::numbers::pi / 3, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d e(0, 0, 1);
  const Eigen::MatrixXd W(f.rig.weights);
  double closed = 0;
  int top = 0;
  for (Eigen::Index i = 0; i < W.rows(); ++i)
    if (W(i, 2) == 1.0) {
      const Eigen::Vector3d p = s.mesh.V.row(i).transpose();
      closed = std::max(closed, (r.frames[0].V.row(i).transpose() - (e + R * (e + R * (p - 2 * e)))).norm());
      ++top;
    }
  CHECK(top > 100);
  CHECK(closed <= 2e-6);
  CHECK(r.frames[0].metrics["time"] == 1.0);
  CHECK(r.frames[0].metrics["rig"]["joints"] == 3);
  CHECK(r.frames[0].metrics["rig"]["animation"]["name"] == "bend");

  // No time: the rest pose (identity skinning), whatever the blend.
  for (const char* blend : {"lbs", "dlb", "log", "pivot-log"}) {
    const auto V = f.run(limb_scene({{"gltf", "limb.glb"}}, {{"type", "skin"}, {"blend", blend}}));
    REQUIRE(V.size() == 1);
    CHECK(max_diff(V[0], f.rig.mesh.V) <= 1e-12);
  }
  // The twist animation by index: DLB keeps the radius of the twisted band where LBS shrinks it
  // (the candy wrapper), both with the rigid ends where the animation puts them.
  const auto lbs_tw = f.run(limb_scene({{"gltf", "limb.glb"}, {"animation", 1}, {"time", 1.0}}));
  const auto dlb_tw = f.run(limb_scene({{"gltf", "limb.glb"}, {"animation", 1}, {"time", 1.0}},
                                       {{"type", "skin"}, {"blend", "dlb"}}));
  double r_lbs = 1e9, r_dlb = 1e9;  // smallest distance from the axis in the band around z = 2
  for (Eigen::Index i = 0; i < W.rows(); ++i)
    if (std::abs(s.mesh.V(i, 2) - 2.0) < 0.05) {
      r_lbs = std::min(r_lbs, lbs_tw[0].row(i).head<2>().norm());
      r_dlb = std::min(r_dlb, dlb_tw[0].row(i).head<2>().norm());
    }
  // At the joint the two weights are ½ and the twist 90°: LBS puts a rim point at cos 45° of the
  // radius, DLB keeps it on the cylinder.
  CHECK(r_lbs == Approx(0.5 * std::sqrt(0.5)).epsilon(0.02));
  CHECK(r_dlb == Approx(0.5).epsilon(1e-3));
}

TEST_CASE("rig scene: frames n and [first, last] at fps give the times and the output numbers") {
  Fixture f;
  {
    const scene::Scene s = f.parse(limb_scene({{"gltf", "limb.glb"}, {"frames", 5}}));
    CHECK(s.animated);
    REQUIRE(s.frames.size() == 5);
    for (int k = 0; k < 5; ++k) CHECK(*s.frames[k].time == Approx(0.5 * k).margin(1e-15));  // over [0, 2]
  }
  json doc = limb_scene({{"gltf", "limb.glb"}, {"frames", {3, 6}}, {"fps", 4}});
  doc["output"] = {{"mesh", "out/limb.obj"}, {"metrics", "out/limb.json"}};
  const scene::Scene s = f.parse(doc);
  CHECK(s.first_frame == 3);
  REQUIRE(s.frames.size() == 4);
  const scene::RunResult r = scene::run_scene(s);
  for (int k = 0; k < 4; ++k) {
    const double t = (3 + k) / 4.0;
    CHECK(*s.frames[k].time == t);
    CHECK(r.frames[k].metrics["time"] == t);
    CHECK(r.frames[k].metrics["frame"] == 3 + k);
    CHECK(max_diff(r.frames[k].V, skin_positions(f.rig, 0, t)) <= 2e-6);
  }
  const auto written = scene::write_outputs(s, r, std::nullopt);
  CHECK(written.size() == 8);
  for (int k = 3; k <= 6; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "limb.%04d.obj", k);
    CHECK(fs::exists(f.dir / "out" / name));
  }
  CHECK_FALSE(fs::exists(f.dir / "out" / "limb.0000.obj"));
  // Frame 8 at 4 fps is t = 2, the last key; past it the animation clamps (t = 2.5 poses as t = 2).
  const auto V = f.run(limb_scene({{"gltf", "limb.glb"}, {"frames", {8, 10}}, {"fps", 4}}));
  REQUIRE(V.size() == 3);
  CHECK(max_diff(V[2], V[0]) <= 1e-12);
}

TEST_CASE("rig scene: pose entries move joints on top of the animation, children following") {
  Fixture f;
  json doc = limb_scene({{"gltf", "limb.glb"}, {"time", 1.0}});
  const Eigen::MatrixXd animated = f.run(doc)[0];
  // joint0 is the root: its edit moves the whole limb (every joint inherits it).
  doc["pose"] = {{"joint0", {{"rotate", {{"axis", {0, 0, 1}}, {"degrees", 90}}}}}};
  const Eigen::MatrixXd edited = f.run(doc)[0];
  const Eigen::Matrix3d Rz =
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  CHECK(max_diff(edited, animated * Rz.transpose()) <= 1e-9);
  // An edit of joint2 alone moves only what joint2 weighs (joint0's segment stays).
  doc["pose"] = {{"joint2", {{"translate", {0.1, 0, 0}}}}};
  const Eigen::MatrixXd moved = f.run(doc)[0];
  const Eigen::MatrixXd W(f.rig.weights);
  double err = 0;
  for (Eigen::Index i = 0; i < W.rows(); ++i)
    err = std::max(err, (moved.row(i) - animated.row(i) - Eigen::RowVector3d(0.1 * W(i, 2), 0, 0)).norm());
  CHECK(err <= 1e-9);  // LBS: the translation is weighted
}

TEST_CASE("rig scene: Delta Mush of 0 iterations is the skin, pins from the weights keep the rigid parts") {
  Fixture f;
  const json rigb = {{"gltf", "limb.glb"}, {"time", 1.0}};
  const Eigen::MatrixXd lbs = f.run(limb_scene(rigb))[0];
  const Eigen::MatrixXd mush0 = f.run(limb_scene(
      rigb, {{"type", "skin"}, {"blend", "lbs"}, {"mush", "delta-mush"}, {"mush_iterations", 0}}))[0];
  CHECK(max_diff(mush0, lbs) <= 1e-9);
  const Eigen::MatrixXd mush = f.run(limb_scene(
      rigb, {{"type", "skin"}, {"blend", "lbs"}, {"mush", "delta-mush"}, {"mush_iterations", 10}}))[0];
  CHECK(max_diff(mush, lbs) > 1e-3);

  json doc = limb_scene(rigb);
  doc["snap"] = {{"pins", "weights"}};
  const scene::Scene s = f.parse(doc);
  CHECK(s.snap.pin_weights);
  const std::unique_ptr<scene::SceneDeformer> d = scene::bind_deformer(s);
  const std::vector<int> pins = scene::skin_pins(s.mesh, *d->skin(), 0.999, -1);
  const scene::RunResult r = scene::run_scene(s);
  const json& m = r.frames[0].metrics["snap"];
  CHECK(m["mode"] == "pinned");
  CHECK(m["pins"] == pins.size());
  CHECK(pins.size() > 100);
  CHECK(m["pin_error"].get<double>() <= 1e-9);
  double pinned = 0;
  for (int v : pins) pinned = std::max(pinned, (r.frames[0].V.row(v) - lbs.row(v)).norm());
  CHECK(pinned <= 1e-9);
  CHECK(max_diff(r.frames[0].V, lbs) > 1e-3);  // the blend bands moved
  // A fixed margin pins more than the default (a quarter of the 0.5 band) when it is smaller.
  doc["snap"] = {{"pins", "weights"}, {"pin_margin", 0.0}};
  const scene::Scene s0 = f.parse(doc);
  CHECK(scene::run_scene(s0).frames[0].metrics["snap"]["pins"].get<size_t>() > pins.size());
}

TEST_CASE("rig scene: bad rig blocks name /rig/... and the problem") {
  Fixture f;
  auto has = [&](const json& doc, const std::string& a, const std::string& b = "") {
    const std::string msg = error_of(f, doc);
    INFO(msg);
    CHECK(msg.find(a) != std::string::npos);
    CHECK(msg.find(b) != std::string::npos);
  };
  const json ok = limb_scene({{"gltf", "limb.glb"}, {"time", 1.0}});
  json doc = ok;
  doc["mesh"] = {{"generate", "icosphere"}};
  has(doc, "rig.json: /rig: give `mesh` or `rig`, not both");
  has(json{{"deformer", {{"type", "skin"}}}}, "/mesh: missing `mesh`");
  has(limb_scene({{"gltf", "missing.glb"}}), "/rig/gltf", "no such file");
  has(limb_scene({{"gltf", "limb.glb"}, {"animation", "walk"}}), "/rig/animation",
      "no animation named 'walk' (the file has 'bend', 'twist')");
  has(limb_scene({{"gltf", "limb.glb"}, {"animation", 2}}), "/rig/animation", "out of range");
  has(limb_scene({{"gltf", "limb.glb"}, {"time", 1.0}, {"frames", 3}}), "/rig/frames", "not both");
  has(limb_scene({{"gltf", "limb.glb"}, {"frames", {1, 4}}}), "/rig/frames", "need `fps`");
  has(limb_scene({{"gltf", "limb.glb"}, {"frames", 4}, {"fps", 24}}), "/rig/fps");
  has(limb_scene({{"gltf", "limb.glb"}, {"frames", {4, 1}}, {"fps", 24}}), "/rig/frames", "before the first");
  has(limb_scene({{"gltf", "limb.glb"}, {"frames", {0, 1}}, {"fps", 0}}), "/rig/fps");  // schema
  has(limb_scene({{"gltf", "limb.glb"}, {"tme", 1}}), "/rig", "tme");                   // typo: schema
  has(limb_scene({{"gltf", "limb.glb"}}, {{"type", "arap"}}), "/deformer/type", "skin deformer");
  doc = ok;
  doc["skeleton"] = {{"bones", {{{"name", "a"}, {"head", {0, 0, 0}}, {"tail", {0, 0, 1}}}}}};
  has(doc, "/skeleton", "from the glTF file");
  doc = ok;
  doc["frames"] = json::array({json::object()});
  has(doc, "/frames", "from the animation");
  doc = ok;
  doc["pose"] = {{"elbow", {{"translate", {0, 0, 1}}}}};
  has(doc, "/pose/elbow", "'joint0', 'joint1', 'joint2'");
  doc = ok;
  // No pin at all is not an error: the attraction anchors the limb, or (γ = 0) it stays as skinned.
  doc["snap"] = {{"pins", "weights"}, {"pin_threshold", 1.0}, {"pin_margin", 10.0}, {"pose_weight", 0.0}};
  {
    const scene::Scene s = f.parse(doc);
    const auto fr = scene::run_scene(s).frames.at(0);
    CHECK(fr.metrics["snap"]["pins"] == 0);
    CHECK(fr.V == fr.V_unsnapped);
  }
  doc = ok;
  doc["snap"] = {{"pin_margin", 0.1}};
  has(doc, "/snap/pin_margin", "belongs to \"pins\": \"weights\"");
  has(json{{"mesh", {{"generate", "icosphere"}, {"level", 2}}},
           {"deformer", {{"type", "surface-harmonic"}}},
           {"handles", {{{"name", "a"}, {"select", {{"all", true}}}}}},
           {"snap", {{"pins", "weights"}}}},
      "/snap/pins", "must be \"skin\"");
}

TEST_CASE("rig scene on CesiumMan through spinmotor deform: the glTF formula and the rig metrics") {
  SPINMOTOR_REQUIRE_RIGS();
  Fixture f;
  const fs::path file = fs::path(SPINMOTOR_RIGS_DIR) / "CesiumMan.gltf";
  const json doc = {{"rig", {{"gltf", file.string()}, {"time", 1.0}}},
                    {"deformer", {{"type", "skin"}, {"blend", "lbs"}}},
                    {"output", {{"mesh", "cesium.ply"}, {"metrics", "cesium.json"}}}};
  std::ofstream(f.dir / "cesium-scene.json") << doc.dump(1);
  const std::string cmd = std::string(SPINMOTOR_CLI) + " deform '" + (f.dir / "cesium-scene.json").string() +
                          "' > /dev/null 2> '" + (f.dir / "err.txt").string() + "'";
  const int status = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
  const GltfRig rig = read_gltf(file);
  const Mesh posed = read_mesh(f.dir / "cesium.ply");
  const Eigen::MatrixXd& V = rig.mesh.V;
  const double diag = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  CHECK(max_diff(posed.V, skin_positions(rig, 0, 1.0)) <= 1e-5 * diag);
  std::ifstream in(f.dir / "cesium.json");
  const json m = json::parse(in);
  CHECK(m["rig"]["joints"] == 19);
  CHECK(m["vertices"] == 2338);
  CHECK(m["rig"]["renormalised_rows"] == rig.renormalised_rows);
  CHECK(m["time"] == 1.0);
}

}  // namespace test_scene_rig
