// The `arap` scene deformer: a scene runs in process, its metrics carry the ARAP energies, and a mesh
// component without a handle is named in the error.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/scene/run.hpp"
#include "spinmotor/scene/scene.hpp"

namespace test_arap_scene {

using namespace spinmotor;
using nlohmann::json;

namespace {

json bar_scene(const std::string& initial) {
  json doc = json::parse(R"({
    "mesh": {"generate": "tube", "radius": 0.5, "length": 4, "rings": 30, "sides": 12, "capped": false},
    "handles": [
      {"name": "base", "select": {"box": {"min": [-1, -1, -0.01], "max": [1, 1, 0.2]}}},
      {"name": "tip",  "select": {"box": {"min": [-1, -1, 3.8], "max": [1, 1, 4.01]}}}
    ],
    "deformer": {"type": "arap", "energy": "spokes", "iterations": 200, "tolerance": 1e-6},
    "pose": {"tip": {"rotate": {"axis": [0, 1, 0], "degrees": 60, "about": [0, 0, 4]}, "translate": [0.5, 0, 0]}}
  })");
  doc["deformer"]["initial"] = initial;
  return doc;
}

}  // namespace

TEST_CASE("arap scene: energies in the metrics, non-increasing, handles exact", "[arap][scene]") {
  for (const std::string initial : {"rest", "harmonic"}) {
    const scene::Scene s = scene::parse_scene(bar_scene(initial), ".", "bar.json");
    const scene::RunResult r = scene::run_scene(s);
    REQUIRE(r.frames.size() == 1);
    const json& m = r.frames[0].metrics;
    INFO(m.dump(1));
    REQUIRE(m.contains("arap"));
    const json& a = m["arap"];
    CHECK(a["energy_type"] == "spokes");
    CHECK(a["initial"] == initial);
    const std::vector<double> E = a["energy"].get<std::vector<double>>();
    REQUIRE(E.size() == a["iterations"].get<std::size_t>() + 1);
    for (std::size_t k = 1; k < E.size(); ++k) CHECK(E[k] <= E[k - 1] * (1 + 1e-13));
    CHECK(a["converged"] == true);
    CHECK(m["max_handle_error"].get<double>() < 1e-12);
  }
}

TEST_CASE("arap scene: a component without a handle is named", "[arap][scene]") {
  // Two disjoint tubes in one OBJ; the handles select vertices of the first one only.
  const Mesh a = tube(0.5, 4.0, 30, 12);
  Mesh two;
  two.V.resize(2 * a.V.rows(), 3);
  two.V << a.V, (a.V.rowwise() + Eigen::RowVector3d(5, 0, 0));
  two.F.resize(2 * a.F.rows(), 3);
  two.F << a.F, (a.F.array() + static_cast<int>(a.V.rows())).matrix();
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "spinmotor_test_arap_scene";
  std::filesystem::create_directories(dir);
  write_mesh(dir / "two_tubes.obj", two);
  json doc = bar_scene("rest");
  doc["mesh"] = "two_tubes.obj";
  try {
    scene::run_scene(scene::parse_scene(doc, dir, "two.json"));
    FAIL("no error for a component without a handle");
  } catch (const Error& e) {
    const std::string msg = e.what();
    INFO(msg);
    CHECK(msg.find("two.json") != std::string::npos);
    CHECK(msg.find("connected component 1 of 2 (360 vertices, e.g. vertex 360)") != std::string::npos);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("arap scene: 'previous' starts each frame from the last result and saves iterations",
          "[arap][scene]") {
  // Three frames turning the tip by 20°, 40°, 60°: from frame 2 on, the previous frame's result is a
  // much better start than the rest pose, and the converged shapes agree within the tolerance.
  auto frames_scene = [](const std::string& initial) {
    json doc = bar_scene(initial);
    doc.erase("pose");
    doc["frames"] = json::array();
    for (int k = 1; k <= 3; ++k)
      doc["frames"].push_back(
          {{"tip", {{"rotate", {{"axis", {0, 1, 0}}, {"degrees", 20 * k}, {"about", {0, 0, 4}}}}}}});
    doc["deformer"]["clamp_negative_weights"] = false;
    return doc;
  };
  const scene::RunResult prev =
      scene::run_scene(scene::parse_scene(frames_scene("previous"), ".", "anim.json"));
  const scene::RunResult rest = scene::run_scene(scene::parse_scene(frames_scene("rest"), ".", "anim.json"));
  REQUIRE(prev.frames.size() == 3);
  REQUIRE(rest.frames.size() == 3);
  // frame 1 has no previous result: identical to rest
  CHECK(prev.frames[0].metrics["arap"]["iterations"] == rest.frames[0].metrics["arap"]["iterations"]);
  for (int k = 1; k < 3; ++k) {
    const int it_prev = prev.frames[k].metrics["arap"]["iterations"].get<int>();
    const int it_rest = rest.frames[k].metrics["arap"]["iterations"].get<int>();
    INFO("frame " << k << ": previous " << it_prev << " iterations, rest " << it_rest);
    CHECK(it_prev < it_rest);
    CHECK(prev.frames[k].metrics["arap"]["initial"] == "previous");
    const double diag =
        (prev.frames[k].V.colwise().maxCoeff() - prev.frames[k].V.colwise().minCoeff()).norm();
    CHECK((prev.frames[k].V - rest.frames[k].V).rowwise().norm().maxCoeff() < 1e-2 * diag);
  }
}

}  // namespace test_arap_scene
