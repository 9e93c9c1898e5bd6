// The CLI's shared surface: every subcommand has --help with examples, --version, -q/--quiet where a
// command reports, and exit code 2 for usage errors (unknown option, missing argument).
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace test_cli_help {

namespace fs = std::filesystem;

namespace {

struct Run {
  int code = -1;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Run run_cli(const std::string& args) {
  const fs::path base = fs::temp_directory_path() / ("spinmotor_test_cli_help_" + std::to_string(::getpid()));
  fs::create_directories(base);
  const fs::path out = base / "out.txt", err = base / "err.txt";
  std::string cmd =
      "'";  // appended, not "'" + std::string&&: GCC 12's -Wrestrict false positive (bug 105329)
  cmd += SPINMOTOR_CLI;
  cmd += "' " + args + " > '" + out.string() + "' 2> '" + err.string() + "'";
  const int status = std::system(cmd.c_str());
  Run r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  fs::remove_all(base);
  return r;
}

const fs::path kData = SPINMOTOR_TEST_DATA_DIR;

}  // namespace

TEST_CASE("every subcommand's --help shows examples", "[cli]") {
  for (const char* cmd : {"batch", "check", "deform", "demo", "extrude", "fair", "flow", "metrics", "snap",
                          "spectrum", "spin", "willmore"}) {
    const Run r = run_cli(std::string(cmd) + " --help");
    CAPTURE(cmd, r.out);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("Example"));
    CHECK_THAT(r.out, Catch::Contains(std::string("spinmotor ") + cmd));
  }
}

TEST_CASE("render --help shows examples when the renderer is built", "[cli]") {
  if (run_cli("--help").out.find(" render ") == std::string::npos) {
    WARN("spinmotor render is not in this build (SPINMOTOR_BUILD_VIEWER=OFF)");
    return;
  }
  const Run r = run_cli("render --help");
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Catch::Contains("Example"));
}

TEST_CASE("version flag and usage errors (exit 2)", "[cli]") {
  const Run v = run_cli("--version");
  CHECK(v.code == 0);
  CHECK_THAT(v.out, Catch::StartsWith("spinmotor "));
  CHECK(run_cli("").code == 2);  // a subcommand is required
  CHECK(run_cli("no-such-command").code == 2);
  CHECK(run_cli("check --no-such-option x.obj").code == 2);
  CHECK(run_cli("metrics only_one.obj").code == 2);  // missing argument
}

TEST_CASE("quiet flag prints nothing but the exit code still reports", "[cli]") {
  const std::string good = (kData / "tetrahedron.obj").string();
  const std::string bad = (kData / "bad" / "nonmanifold_edge.obj").string();
  REQUIRE(fs::exists(good));
  const Run ok = run_cli("check -q '" + good + "'");
  CHECK(ok.code == 0);
  CHECK(ok.out.empty());
  const Run defect = run_cli("check -q '" + bad + "'");
  CHECK(defect.code == 2);
  CHECK(defect.out.empty());
  CHECK_THAT(defect.err, Catch::Contains("non-manifold"));  // errors are never silenced
  const Run m = run_cli("metrics -q '" + good + "' '" + good + "'");
  CHECK(m.code == 0);
  CHECK(m.out.empty());
}

TEST_CASE("spinmotor demo: every use runs on the embedded defaults and its figures hold", "[cli][demo]") {
  const fs::path out = fs::temp_directory_path() / ("spinmotor_test_demo_" + std::to_string(::getpid()));
  const Run r = run_cli("demo --json --out '" + out.string() + "'");
  REQUIRE(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK(j == nlohmann::json::parse(slurp(out / "demo.json")));
  // the twist (Fig. 21: not conformal) snaps back to Q_mean near 1; the pose and the skinned arm improve
  CHECK(j["twist"]["q_mean"].get<double>() > 1.2);
  CHECK(j["snap_twist"]["q_mean"].get<double>() < 1.01);
  CHECK(j["snap_pose"]["q_mean"].get<double>() < j["surface_harmonic"]["q_mean"].get<double>());
  CHECK(j["snap_pose"]["q_mean"].get<double>() < 1.02);
  CHECK(j["rig_cleanup"]["snapped"]["q_mean"].get<double>() <
        j["rig_cleanup"]["lbs"]["q_mean"].get<double>());
  CHECK(j["ik_spline"]["tip_error"].get<double>() <= 0.25 / 100);  // tube radius / 100
  CHECK(j["spin"]["q_mean"].get<double>() < 1.1);
  // The glTF stage: the procedural standing character (seven meshes on one skin, a Mixamo-style scaled
  // armature) read back welded per mesh (UV seams double vertices in the file), the LBS walk loses volume,
  // the cleanup restores it piece by piece with the pins exactly in place and calms Q_max; the cleaned
  // walk as a few corrective targets within the bound.
  const nlohmann::json& g = j["gltf_rig"];
  CHECK(g["meshes"] == 7);
  CHECK(g["file_vertices"].get<int>() > g["vertices"].get<int>());
  CHECK(g["joints"] == 17);
  CHECK(g["piece_statuses"]["cleaned"].get<int>() >= 5);
  CHECK(std::abs(g["volume_ratio_lbs"].get<double>() - 1) > 1e-4);  // measured 1.00027
  CHECK(g["volume_ratio_cleaned"].get<double>() == Approx(1.0).margin(1e-7));
  CHECK(g["pin_error"].get<double>() <= 1e-12);
  CHECK(g["cleaned"]["q_max"].get<double>() < g["lbs"]["q_max"].get<double>());
  CHECK(g["cleaned"]["q_mean"].get<double>() < g["lbs"]["q_mean"].get<double>());
  CHECK(g["corrective_max_error"].get<double>() <= 1e-3);
  for (const char* f : {"character-rig.glb", "character-rest.obj", "character-lbs.obj", "character-dlb.obj",
                        "character-cleaned.obj", "character-correctives.glb"})
    CHECK(fs::exists(out / f));
  for (const char* f :
       {"capsule.obj", "capsule-twisted.obj", "capsule-posed.obj", "capsule-twist-snapped.obj",
        "capsule-pose-snapped.obj", "capsule-spin.obj", "tube-ik.obj", "arm-lbs.obj", "arm-lbs-snapped.obj"})
    CHECK(fs::exists(out / f));
  fs::remove_all(out);
}

}  // namespace test_cli_help
