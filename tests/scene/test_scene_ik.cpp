// IK-driven spline deformation end to end (CGA paper §III.C, Fig. 5): a scene with an `ik` block bends
// a tube with FABRIK → joint motors → cubic B-spline fit → spline-aligned deformation, and the tube's
// tip lands on the target within radius/100. Also the variant with a posed chain given in `fit`.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "spinmotor/deform/fabrik.hpp"
#include "spinmotor/scene/run.hpp"
#include "spinmotor/scene/scene.hpp"

namespace test_scene_ik {

using namespace spinmotor;
using namespace spinmotor::scene;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const fs::path kScenes = fs::path(SPINMOTOR_TEST_DATA_DIR) / "scenes";
constexpr double kRadius = 0.25;  // ik_tube.json

Eigen::Vector3d centroid(const Eigen::MatrixXd& V, const Handle& h) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (Eigen::Index k = 0; k < h.vertices.size(); ++k) c += V.row(h.vertices[k]).transpose();
  return c / static_cast<double>(h.vertices.size());
}

}  // namespace

TEST_CASE("an IK scene bends a tube so that its tip lands on the target", "[scene][ik]") {
  const Scene s = load_scene(kScenes / "ik_tube.json");
  REQUIRE(s.ik);
  const RunResult r = run_scene(s);
  const Eigen::MatrixXd& V = r.frames[0].V;
  const Eigen::Vector3d target = s.ik->target;
  const Handle& tip = s.handles[1];
  const Eigen::Vector3d c = centroid(V, tip);
  CHECK((c - target).norm() <= kRadius / 100);
  // The tube really bent: the tip moved by more than a radius, and its end ring stays a circle of
  // radius 0.25 (the `to` handle moves rigidly).
  CHECK((c - centroid(s.mesh.V, tip)).norm() > 1.0);
  for (Eigen::Index k = 0; k < tip.vertices.size(); ++k)
    CHECK((V.row(tip.vertices[k]).transpose() - c).norm() == Approx(kRadius).epsilon(1e-10));
  // The base ring turns with the first bone about the root joint (its centre): it stays centred there
  // and stays a circle, like a root bone in skinning.
  const Eigen::Vector3d b = centroid(V, s.handles[0]);
  CHECK(b.norm() < 1e-12);
  for (Eigen::Index k = 0; k < s.handles[0].vertices.size(); ++k)
    CHECK((V.row(s.handles[0].vertices[k]).transpose() - b).norm() == Approx(kRadius).epsilon(1e-10));

  const json& m = r.frames[0].metrics;
  CHECK(m["ik"]["converged"].get<bool>());
  CHECK(m["ik"]["tip_error"].get<double>() <= kRadius / 100);
  CHECK(m["max_handle_error"].get<double>() < 1e-12);
  CHECK(m["fit"]["controls"] == 5);
  CHECK_FALSE(m["fit"]["used_svd"].get<bool>());
  // A smooth bend: angles are nearly kept (Q close to 1; 1.107 measured), no collapsed face.
  CHECK(m["q_mean"].get<double>() < 1.2);
  CHECK(m["metrics"]["collapsed_faces"] == 0);
}

TEST_CASE("a posed chain given in `fit` drives the spline deformer the same way", "[scene][ik]") {
  json doc = json::parse(std::ifstream(kScenes / "ik_tube.json"));
  // Solve the chain here and hand the posed joints to the scene instead of the ik block.
  Eigen::MatrixXd chain(5, 3);
  for (int i = 0; i < 5; ++i) chain.row(i) << 0, 0, i;
  const FabrikResult f =
      fabrik(chain, Eigen::Vector3d(1.5, 0, 3.2), {.tolerance = 1e-4, .max_iterations = 100});
  json posed = json::array();
  for (int i = 0; i < 5; ++i) posed.push_back({f.joints(i, 0), f.joints(i, 1), f.joints(i, 2)});
  doc.erase("ik");
  doc["deformer"]["fit"] = {{"chain", json::parse("[[0,0,0],[0,0,1],[0,0,2],[0,0,3],[0,0,4]]")},
                            {"posed", posed}};
  const Scene s = parse_scene(doc, kScenes, "fit.json");
  const RunResult r = run_scene(s);
  CHECK((centroid(r.frames[0].V, s.handles[1]) - f.joints.row(4).transpose()).norm() < 1e-10);

  const Scene ik = load_scene(kScenes / "ik_tube.json");
  const RunResult rik = run_scene(ik);
  CHECK((rik.frames[0].V - r.frames[0].V).cwiseAbs().maxCoeff() < 1e-12);  // same chain, same deformation
}

TEST_CASE("spinmotor deform runs the IK scene", "[scene][ik][cli]") {
  const fs::path tmp = fs::temp_directory_path() / "spinmotor-scene-ik-test";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  const std::string cmd = std::string(SPINMOTOR_CLI) + " deform '" + (kScenes / "ik_tube.json").string() +
                          "' --json --out-dir '" + tmp.string() + "' > '" + (tmp / "o.json").string() + "'";
  const int status = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  const json j = json::parse(std::ifstream(tmp / "o.json"));
  CHECK(j["ik"]["tip_error"].get<double>() <= kRadius / 100);
  CHECK(fs::exists(tmp / "out/ik_tube.obj"));
  fs::remove_all(tmp);
}

TEST_CASE("the IK target animates: frames move the control 'ik.target' and the tip follows each",
          "[scene][ik]") {
  json doc = json::parse(std::ifstream(kScenes / "ik_tube.json"));
  doc["frames"] = json::array();
  const Eigen::Vector3d moves[3] = {{0, 0, 0}, {0, 0.5, 0}, {-0.5, 0.3, -0.4}};
  for (const auto& t : moves)
    doc["frames"].push_back({{"ik.target", {{"translate", {t.x(), t.y(), t.z()}}}}});
  const Scene s = parse_scene(doc, kScenes, "ik_frames.json");
  const RunResult r = run_scene(s);
  REQUIRE(r.frames.size() == 3);
  for (int f = 0; f < 3; ++f) {
    const Eigen::Vector3d target = s.ik->target + moves[f];
    INFO("frame " << f);
    CHECK((centroid(r.frames[f].V, s.handles[1]) - target).norm() <= kRadius / 100);
    const json& ik = r.frames[f].metrics["ik"];
    CHECK((Eigen::Vector3d(ik["target"][0], ik["target"][1], ik["target"][2]) - target).norm() < 1e-12);
    CHECK(ik["tip_error"].get<double>() <= kRadius / 100);
  }
  // Frame 0 is the scene's own target: the same deformation as the unanimated scene.
  const RunResult still = run_scene(load_scene(kScenes / "ik_tube.json"));
  CHECK((r.frames[0].V - still.frames[0].V).cwiseAbs().maxCoeff() < 1e-12);
  // Without an ik block there is no such control: the pose entry is an error naming its path.
  json keys = json::parse(std::ifstream(kScenes / "spline_keys_tube.json"));
  keys["pose"]["ik.target"] = {{"translate", {0, 1, 0}}};
  CHECK_THROWS_WITH(run_scene(parse_scene(keys, kScenes, "keys.json")), Catch::Contains("/pose/ik.target"));
}

}  // namespace test_scene_ik
