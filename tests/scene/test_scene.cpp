// Scene files (scene/, docs/scene.md) and `spinmotor deform`: schema errors naming the JSON path, motors
// from their JSON forms, selections, the in-process runner and its outputs (mesh with UVs, metrics,
// colours, numbered frames), and the CLI contract for bad scenes: exit code 2, a message naming the
// JSON path or component, and no output file.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/scene/json_schema.hpp"
#include "spinmotor/scene/run.hpp"
#include "spinmotor/scene/scene.hpp"

namespace test_scene {

using namespace spinmotor;
using namespace spinmotor::scene;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const fs::path kScenes = fs::path(SPINMOTOR_TEST_DATA_DIR) / "scenes";

/// A fresh empty directory under the system temp dir, removed at scope exit.
struct TempDir {
  fs::path path;
  TempDir() {
    std::random_device rd;
    path =
        fs::temp_directory_path() / ("spinmotor-scene-test-" + std::to_string(rd()) + std::to_string(rd()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

struct CliResult {
  int code = -1;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

CliResult run_cli(const std::string& args, const fs::path& scratch) {
  const fs::path out = scratch / "stdout.txt", err = scratch / "stderr.txt";
  const std::string cmd =
      std::string(SPINMOTOR_CLI) + " " + args + " > '" + out.string() + "' 2> '" + err.string() + "'";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

json base_doc() {
  return json::parse(R"({
    "mesh": {"generate": "tube", "radius": 0.5, "length": 4, "rings": 12, "sides": 12},
    "handles": [
      {"name": "base", "select": {"box": {"min": [-1, -1, -0.01], "max": [1, 1, 0.01]}}},
      {"name": "tip", "select": {"box": {"min": [-1, -1, 3.99], "max": [1, 1, 4.01]}}}
    ],
    "deformer": {"type": "surface-harmonic"}
  })");
}

std::string error_of(const json& doc) {
  try {
    const Scene s = parse_scene(doc, kScenes, "doc.json");
    run_scene(s);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

std::size_t count_files(const fs::path& dir) {
  if (!fs::exists(dir)) return 0;
  std::size_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) ++n;
  return n;
}

}  // namespace

TEST_CASE("schema errors name the JSON path of the bad value", "[scene][schema]") {
  struct Case {
    const char* pointer;
    json value;
    const char* path;
    const char* message;
  };
  const Case cases[] = {
      {"/handles/1/select/box/min", json::array({-1, -1}), "/handles/1/select/box/min",
       "expected at least 3 items, got 2"},
      {"/deformer/wieghts", "cotan", "/deformer/wieghts", "unknown key 'wieghts'"},
      {"/deformer/blend", "lin", "/deformer/blend", "expected one of \"log\", \"pivot-log\", \"dlb\""},
      {"/deformer/type", "morph", "/deformer/type", "expected one of \"surface-harmonic\", \"spline\""},
      {"/mesh/radius", -1, "/mesh/radius", "must be > 0"},
      {"/mesh/generate", "tubes", "/mesh/generate", "expected one of \"icosphere\""},
      {"/handles", json::object(), "/handles", "expected an array, got an object"},
      {"/handles/0/select", json::parse(R"({"sphere": {"center": [0, 0, 0]}})"), "/handles/0/select/sphere",
       "missing required key 'radius'"},
      {"/pose", json::parse(R"({"tip": {"matrix": [1, 0, 0]}})"), "/pose/tip/matrix",
       "expected at least 16 items"},
      {"/pose", json::parse(R"({"tip": {"rotate": {"axis": [1, 0, 0]}}})"), "/pose/tip/rotate",
       "missing required key 'degrees'"},
      {"/snap", json::parse(R"({"tradeoff": 2})"), "/snap/tradeoff", "must be ≤ 1"},
      {"/frobnicate", true, "/frobnicate", "unknown key 'frobnicate'"},
  };
  for (const Case& c : cases) {
    json doc = base_doc();
    doc[json::json_pointer(c.pointer)] = c.value;
    const std::string e = error_of(doc);
    CAPTURE(c.pointer, e);
    CHECK(e.find(std::string("doc.json: ") + c.path + ": ") != std::string::npos);
    CHECK(e.find(c.message) != std::string::npos);
  }
  json doc = base_doc();
  doc.erase("deformer");
  CHECK_THAT(error_of(doc), Catch::Contains("doc.json: /: missing required key 'deformer'"));
}

TEST_CASE("schema integers are within the range of int, as the loader reads them", "[scene][schema]") {
  // 1e300 is integral, so it was an "integer", and get<int>() of it undefined (found by fuzz_scene).
  const JsonSchema s(json::parse(R"({"type": "integer"})"));
  CHECK(s.validate(json(2147483647)).empty());
  CHECK(s.validate(json(-2147483648LL)).empty());
  CHECK(s.validate(json(3.0)).empty());
  for (const json& big :
       {json(1e300), json(2147483648LL), json(-2147483649LL), json(18446744073709551615ULL)}) {
    const auto errors = s.validate(big);
    CAPTURE(big.dump());
    REQUIRE(errors.size() == 1);
    CHECK_THAT(errors[0].message, Catch::Contains("out of range"));
  }
}

TEST_CASE("the schema validator rejects unsupported keywords", "[scene][schema]") {
  CHECK_THROWS_WITH(JsonSchema(json::parse(R"({"type": "object", "patternProperties": {}})")),
                    Catch::Contains("unsupported keyword 'patternProperties'"));
  CHECK_THROWS_WITH(JsonSchema(json::parse(R"({"$ref": "#/definitions/nothing"})")),
                    Catch::Contains("does not resolve"));
  CHECK_NOTHROW(JsonSchema(scene_schema()));
  CHECK(pointer_token("a/b~c") == "a~1b~0c");
}

TEST_CASE("motors from their JSON forms", "[scene][motor]") {
  // rotate 90° about z around (1, 0, 0), then translate (0, 0, 1): (2, 0, 0) -> (1, 1, 1).
  const ga::Mot r =
      parse_motor(json::parse(R"({"rotate": {"axis": [0, 0, 1], "degrees": 90, "about": [1, 0, 0]},
                                                "translate": [0, 0, 1]})"),
                  "/pose/x");
  CHECK((ga::transform(r, Eigen::Vector3d(2, 0, 0)) - Eigen::Vector3d(1, 1, 1)).norm() < 1e-15);
  // The same motion as a matrix (row-major) and as a quaternion + translation.
  const ga::Mot m =
      parse_motor(json::parse(R"({"matrix": [0, -1, 0, 1,  1, 0, 0, -1,  0, 0, 1, 1,  0, 0, 0, 1]})"), "/p");
  const ga::Mot q = parse_motor(
      json::parse(
          R"({"quaternion": [1.4142135623730951, 0, 0, 1.4142135623730951], "translate": [1, -1, 1]})"),
      "/p");
  for (const Eigen::Vector3d& x : {Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(0.3, -2, 5)}) {
    const Eigen::Vector3d a = ga::transform(r, x);
    CHECK((ga::transform(m, x) - a).norm() < 1e-14);
    CHECK((ga::transform(q, x) - a).norm() < 1e-14);  // the quaternion is normalized
  }
  CHECK_THROWS_WITH(
      parse_motor(json::parse(R"({"matrix": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0.5, 0, 1]})"),
                  "/pose/t"),
      Catch::Contains("/pose/t/matrix: not a rigid motion"));
  CHECK_THROWS_WITH(
      parse_motor(json::parse(R"({"matrix": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, -1, 0,  0, 0, 0, 1]})"),
                  "/pose/t"),
      Catch::Contains("/pose/t/matrix: not a rigid motion"));
  CHECK_THROWS_WITH(parse_motor(json::parse(R"({"rotate": {"axis": [0, 0, 0], "degrees": 5}})"), "/pose/t"),
                    Catch::Contains("/pose/t/rotate/axis"));
}

TEST_CASE("selections and semantic errors name the handle and its path", "[scene][handles]") {
  json doc = base_doc();
  doc["handles"][1]["select"] = json::parse(R"({"sphere": {"center": [9, 9, 9], "radius": 0.5}})");
  CHECK_THAT(error_of(doc), Catch::Contains("doc.json: /handles/1/select: handle 'tip' selects no vertex"));

  doc = base_doc();
  doc["handles"][1]["select"] = json::parse(R"({"box": {"min": [-1, -1, -1], "max": [1, 1, 0.5]}})");
  CHECK_THAT(
      error_of(doc),
      Catch::Contains("doc.json: /handles/1: handle 'tip' shares vertex 0 with handle 'base' (/handles/0)"));

  doc = base_doc();
  doc["handles"][1]["name"] = "base";
  CHECK_THAT(error_of(doc), Catch::Contains("/handles/1/name: duplicate handle name 'base'"));

  doc = base_doc();
  doc["handles"][1]["select"] = json::parse(R"({"vertices": [3, 1000000]})");
  CHECK_THAT(error_of(doc), Catch::Contains("/handles/1/select/vertices/1: vertex 1000000 is out of range"));

  doc = base_doc();
  doc["pose"] = json::parse(R"({"tpi": {"translate": [0, 1, 0]}})");
  CHECK_THAT(error_of(doc), Catch::Contains("doc.json: /pose/tpi: no handle or control named 'tpi'"));

  doc = base_doc();
  doc["frames"] = json::parse(R"([{}, {"tip": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,2]}}])");
  CHECK_THAT(error_of(doc), Catch::Contains("doc.json: /frames/1/tip/matrix: not a rigid motion"));

  doc = base_doc();
  doc["deformer"] = json::parse(R"({"type": "spline", "from": "base", "to": "top", "keys": ["a", "b"]})");
  CHECK_THAT(error_of(doc), Catch::Contains("doc.json: /deformer/to: no handle named 'top'"));
  doc["deformer"]["to"] = "tip";
  doc["deformer"]["basis"] = "quadratic";
  CHECK_THAT(error_of(doc),
             Catch::Contains("doc.json: /deformer/keys:") && Catch::Contains("exactly 3 keys"));

  // Plane selection: the side the normal points to.
  doc = base_doc();
  doc["handles"][1]["select"] = json::parse(R"({"plane": {"point": [0, 0, 3.9], "normal": [0, 0, 1]}})");
  const Scene s = parse_scene(doc, kScenes, "doc.json");
  CHECK(s.handles[1].vertices.size() == 12);
  for (Eigen::Index k = 0; k < 12; ++k) CHECK(s.mesh.V(s.handles[1].vertices[k], 2) == Approx(4.0));
}

TEST_CASE("running a scene in process: handles exact, outputs complete", "[scene][run]") {
  TempDir tmp;
  const Scene s = load_scene(kScenes / "sh_tube.json");
  REQUIRE(s.handles.size() == 2);
  const RunResult r = run_scene(s);
  REQUIRE(r.frames.size() == 1);
  const json& m = r.frames[0].metrics;
  CHECK(m["max_handle_error"].get<double>() < 1e-12);
  CHECK(m["q_mean"].get<double>() >= 1.0);
  CHECK(m["q_max"].get<double>() >= m["q_mean"].get<double>());
  CHECK(m["vertices"] == s.mesh.V.rows());
  CHECK(m["metrics"].contains("edge_distortion"));
  CHECK_FALSE(m.contains("snap"));
  // The tip moved: rotated 60° about x at its centre and lifted by 0.5 in y.
  const Handle& tip = s.handles[1];
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (Eigen::Index k = 0; k < tip.vertices.size(); ++k) c += r.frames[0].V.row(tip.vertices[k]).transpose();
  c /= tip.vertices.size();
  CHECK((c - Eigen::Vector3d(0, 0.5, 4)).norm() < 1e-12);

  const auto written = write_outputs(s, r, tmp.path);
  REQUIRE(written.size() == 3);
  const Mesh out = read_mesh(tmp.path / "out/sh_tube.obj");
  CHECK(out.F == s.mesh.F);
  CHECK(out.UV == s.mesh.UV);  // texture coordinates kept
  CHECK(out.FUV == s.mesh.FUV);
  CHECK((out.V - r.frames[0].V).cwiseAbs().maxCoeff() == 0.0);
  const json mj = json::parse(slurp(tmp.path / "out/sh_tube.json"));
  CHECK(mj["max_handle_error"] == m["max_handle_error"]);
  const Mesh q = read_mesh(tmp.path / "out/sh_tube_q.ply");  // the PLY reader skips the colour properties
  CHECK(q.F == s.mesh.F);
  CHECK((q.V - r.frames[0].V).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("animations number their outputs, snap metrics per frame", "[scene][run]") {
  TempDir tmp;
  const Scene s = load_scene(kScenes / "frames_tube.json");
  CHECK(s.animated);
  CHECK(s.snap.enabled);
  const RunResult r = run_scene(s);
  REQUIRE(r.frames.size() == 3);
  CHECK((r.frames[0].V - s.mesh.V).cwiseAbs().maxCoeff() < 1e-12);  // frame 0: identity pose, snapped
  for (int f = 0; f < 3; ++f) {
    CHECK(r.frames[f].metrics["frame"] == f);
    const json& sn = r.frames[f].metrics["snap"];
    REQUIRE(sn.is_object());
    // The snap is at least as conformal as the pose (frame 0: both 1) and stays near it.
    CHECK(sn["q_mean"].get<double>() <= r.frames[f].metrics["q_mean"].get<double>() + 1e-9);
    CHECK(sn["rms_edit_to_snap"].get<double>() < 0.1);
    const Eigen::MatrixXd& E = r.frames[f].V_unsnapped;
    const double dg = (E.colwise().maxCoeff() - E.colwise().minCoeff()).norm();
    CHECK(std::sqrt((E - r.frames[f].V).rowwise().squaredNorm().mean()) / dg ==
          Approx(sn["rms_edit_to_snap"].get<double>()).margin(1e-12));
    CHECK(r.frames[f].metrics["max_handle_error"].get<double>() < 1e-12);
  }
  write_outputs(s, r, tmp.path);
  for (const char* f : {"out/frames_tube.0000.obj", "out/frames_tube.0001.obj", "out/frames_tube.0002.obj",
                        "out/frames_tube.0000.json", "out/frames_tube.0002.json"})
    CHECK(fs::exists(tmp.path / f));
}

TEST_CASE("scene snap modes: spin with rho smoothing, shape (extrusion), keys of the other mode rejected",
          "[scene][run][snap]") {
  json doc = json::parse(std::ifstream(kScenes / "sh_tube.json"));
  doc.erase("output");
  doc["snap"] = {{"smooth_rho", 10}};
  const Scene spin = parse_scene(doc, kScenes, "spin.json");
  CHECK(spin.snap.smooth_rho == 10);
  const RunResult rs = run_scene(spin);
  const json& ss = rs.frames[0].metrics["snap"];
  CHECK(ss["mode"] == "free");  // "spin" is the former name (still accepted in scene files)
  CHECK(ss["smooth_rho"] == 10);
  const double q_edit = rs.frames[0].metrics["q_mean"].get<double>();
  CHECK(ss["q_mean"].get<double>() < q_edit);

  doc["snap"] = {{"mode", "shape"}, {"steps", 2}};
  const Scene shape = parse_scene(doc, kScenes, "shape.json");
  CHECK(shape.snap.mode == SnapMode::Shape);
  const RunResult rh = run_scene(shape);
  const json& sh = rh.frames[0].metrics["snap"];
  CHECK(sh["mode"] == "shape");
  CHECK(sh["closure"].size() == 2);
  INFO("edit Q_mean " << q_edit << ", shape snap " << sh["q_mean"] << ", rms " << sh["rms_edit_to_snap"]);
  CHECK(sh["q_mean"].get<double>() < q_edit);          // more conformal than the edit
  CHECK(sh["rms_edit_to_snap"].get<double>() < 0.15);  // and near it (relative to the diagonal)
  CHECK((rh.frames[0].V_unsnapped - rs.frames[0].V_unsnapped).cwiseAbs().maxCoeff() == 0);  // same edit

  for (const char* bad : {R"({"mode": "shape", "tradeoff": 0.5})", R"({"smooth_rho": 3, "steps": 2})",
                          R"({"mode": "sphere"})", R"({"steps": 0, "mode": "shape"})"}) {
    INFO(bad);
    doc["snap"] = json::parse(bad);
    CHECK_THROWS_WITH(parse_scene(doc, kScenes, "bad.json"), Catch::Contains("/snap"));
  }
}

TEST_CASE("scene snap mode pinned: the handles stay where the deformer put them, the rest is cleaned up",
          "[scene][run][snap][pinned]") {
  json doc = json::parse(std::ifstream(kScenes / "sh_tube.json"));
  doc.erase("output");
  doc["snap"] = {{"pins", "handles"}};  // pins given: the mode is pinned
  const Scene s = parse_scene(doc, kScenes, "pinned.json");
  REQUIRE(s.snap.mode == SnapMode::Pinned);
  REQUIRE(s.snap.pin_handles.size() == s.handles.size());
  const RunResult r = run_scene(s);
  const FrameResult& fr = r.frames[0];
  const json& sp = fr.metrics["snap"];
  CHECK(sp["mode"] == "pinned");
  double pin_move = 0;
  Eigen::Index pins = 0;
  for (const Handle& h : s.handles)
    for (Eigen::Index k = 0; k < h.vertices.size(); ++k, ++pins)
      pin_move = std::max(pin_move, (fr.V.row(h.vertices[k]) - fr.V_unsnapped.row(h.vertices[k])).norm());
  CHECK(pin_move == 0.0);  // pins are copied, not solved for
  CHECK(sp["pins"].get<Eigen::Index>() == pins);
  const double q_edit = fr.metrics["q_mean"].get<double>(), q_clean = sp["q_mean"].get<double>();
  INFO("edit Q_mean " << q_edit << ", cleaned " << q_clean << ", measure ratio " << sp["measure_ratio"]);
  CHECK(q_clean < q_edit);
  CHECK(std::abs(sp["measure_ratio"].get<double>() - 1.0) < 1e-6);  // the kept volume (capped tube)
  CHECK(sp["keep"] == "volume");
  // The free region moved: the cleanup did something.
  CHECK(sp["max_edit_to_snap"].get<double>() > 1e-6);

  doc["snap"] = {{"mode", "pinned"}, {"pins", {s.handles[0].name}}, {"iterations", 5}};
  const Scene one = parse_scene(doc, kScenes, "one.json");
  CHECK(one.snap.pin_handles == std::vector<int>{0});
  CHECK(one.snap.iterations == 5);
  CHECK(!one.snap.pose_weight);

  // "pose_weight": the pose attraction holds the free region nearer the deformer's result.
  doc["snap"] = {{"pins", "handles"}, {"pose_weight", 10}};
  const Scene held = parse_scene(doc, kScenes, "held.json");
  CHECK(held.snap.pose_weight == 10);
  const RunResult hr = run_scene(held);
  const FrameResult& hf = hr.frames[0];
  CHECK(hf.metrics["snap"]["pose_weight"] == 10.0);
  CHECK((hf.V - hf.V_unsnapped).norm() < (fr.V - fr.V_unsnapped).norm());

  for (const char* bad :
       {R"({"pins": ["nope"]})", R"({"mode": "pinned", "tradeoff": 1})",
        R"({"pins": "handles", "keep": "mass"})", R"({"mode": "free", "pins": "handles"})", R"({"pins": []})",
        R"({"pins": "handles", "pose_weight": -1})", R"({"mode": "free", "pose_weight": 1})"}) {
    INFO(bad);
    doc["snap"] = json::parse(bad);
    CHECK_THROWS_WITH(parse_scene(doc, kScenes, "bad.json"), Catch::Contains("/snap"));
  }
  doc["snap"] = {{"mode", "spin"}};  // the former name of free
  CHECK(parse_scene(doc, kScenes, "legacy.json").snap.mode == SnapMode::Free);
}

TEST_CASE("spline scene with named keys in matrix, quaternion and rotate forms", "[scene][run][spline]") {
  const Scene s = load_scene(kScenes / "spline_keys_tube.json");
  const RunResult r = run_scene(s);
  const json& m = r.frames[0].metrics;
  CHECK(m["deformer"] == "spline");
  CHECK(m["max_handle_error"].get<double>() < 1e-12);  // base follows k0 (identity), tip follows k3
}

TEST_CASE("spinmotor deform: a good scene writes its outputs and prints JSON", "[scene][cli]") {
  TempDir tmp;
  const CliResult r = run_cli(
      "deform '" + (kScenes / "sh_tube.json").string() + "' --json --out-dir '" + tmp.path.string() + "'",
      tmp.path);
  CHECK(r.code == 0);
  CAPTURE(r.err);
  const json j = json::parse(r.out);
  CHECK(j["max_handle_error"].get<double>() < 1e-12);
  CHECK(fs::exists(tmp.path / "out/sh_tube.obj"));
  CHECK(fs::exists(tmp.path / "out/sh_tube.json"));
  CHECK(fs::exists(tmp.path / "out/sh_tube_q.ply"));

  const CliResult f = run_cli(
      "deform '" + (kScenes / "frames_tube.json").string() + "' --out-dir '" + tmp.path.string() + "'",
      tmp.path);
  CHECK(f.code == 0);
  CHECK_THAT(f.err, !Catch::Contains("warning"));
  CHECK_THAT(f.out, Catch::Contains("frame 2: pose"));

  const CliResult schema = run_cli("deform --schema", tmp.path);
  CHECK(schema.code == 0);
  CHECK(json::parse(schema.out) == scene_schema());
}

TEST_CASE("spinmotor deform: bad scenes exit 2, name the path, write nothing", "[scene][cli][errors]") {
  struct Case {
    const char* file;
    std::vector<const char*> message;
  };
  const Case cases[] = {
      {"empty_handle.json", {"empty_handle.json: /handles/1/select: handle 'nowhere' selects no vertex"}},
      {"shared_vertex.json",
       {"shared_vertex.json: /handles/1: handle 'overlap' shares vertex", "with handle 'base'"}},
      {"unknown_key.json", {"unknown_key.json: /deformer/wieghts: unknown key 'wieghts'"}},
      {"unknown_pose_key.json", {"unknown_pose_key.json: /pose/tpi: no handle or control named 'tpi'"}},
      {"non_rigid.json", {"non_rigid.json: /pose/tip/matrix: not a rigid motion"}},
      {"component_without_handle.json",
       {"component_without_handle.json", "connected component 1", "no constrained vertex"}},
      {"short_vector.json",
       {"short_vector.json: /handles/1/select/box/min: expected at least 3 items, got 2"}},
  };
  for (const Case& c : cases) {
    TempDir tmp;
    const fs::path out = tmp.path / "outdir";
    const CliResult r = run_cli(
        "deform '" + (kScenes / "bad" / c.file).string() + "' --out-dir '" + out.string() + "'", tmp.path);
    CAPTURE(c.file, r.err);
    CHECK(r.code == 2);
    for (const char* m : c.message) CHECK_THAT(r.err, Catch::Contains(m));
    CHECK(count_files(out) == 0);
  }
  TempDir tmp;
  const CliResult missing = run_cli("deform '" + (tmp.path / "nothing.json").string() + "'", tmp.path);
  CHECK(missing.code == 2);
  CHECK_THAT(missing.err, Catch::Contains("cannot read scene file"));
  std::ofstream(tmp.path / "broken.json") << "{\"mesh\": \"x.obj\",\n \"deformer\": }";
  const CliResult broken = run_cli("deform '" + (tmp.path / "broken.json").string() + "'", tmp.path);
  CHECK(broken.code == 2);
  CHECK_THAT(broken.err, Catch::Contains("broken.json: invalid JSON") && Catch::Contains("line 2"));
}

TEST_CASE("spinmotor deform: a failure after the first frame of an animation leaves no output",
          "[scene][cli][errors]") {
  // Injected failure: the mesh of frame 1 cannot be written because a directory occupies its path. The
  // frames are computed first; frame 0's mesh and metrics are written and must be removed again.
  TempDir tmp;
  const fs::path out = tmp.path / "outdir";
  fs::create_directories(out / "out" / "frames_tube.0001.obj" / "blocker");
  const CliResult r = run_cli(
      "deform '" + (kScenes / "frames_tube.json").string() + "' --out-dir '" + out.string() + "'", tmp.path);
  CAPTURE(r.err);
  CHECK((r.code == 2 || r.code == 3));
  CHECK_THAT(r.err, Catch::Contains("frames_tube.0001.obj"));
  CHECK(count_files(out) == 0);  // frame 0's outputs were removed; only the blocker directory remains
  CHECK(fs::is_directory(out / "out" / "frames_tube.0001.obj" / "blocker"));
  // without the blocker the same command writes all 3 frames (mesh + metrics)
  fs::remove_all(out);
  const CliResult ok = run_cli(
      "deform '" + (kScenes / "frames_tube.json").string() + "' --out-dir '" + out.string() + "'", tmp.path);
  CHECK(ok.code == 0);
  CHECK(count_files(out) == 6);
}

}  // namespace test_scene
