// `spinmotor metrics REST DEFORMED` end to end: files written with write_mesh, the built binary run,
// its JSON parsed and compared with closed forms; mismatched inputs exit with code 2.
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"

namespace test_cli_metrics {

using namespace spinmotor;
namespace fs = std::filesystem;

namespace {

struct Run {
  int code;
  std::string out, err;
};

// Runs the CLI with the given arguments (already shell-quoted), capturing stdout and stderr.
Run run_cli(const fs::path& dir, const std::string& args) {
  const fs::path err_file = dir / "stderr.txt";
  const std::string cmd = std::string("'") + SPINMOTOR_CLI + "' " + args + " 2> '" + err_file.string() + "'";
  FILE* pipe = popen(cmd.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string out;
  char buf[4096];
  for (size_t n; (n = fread(buf, 1, sizeof buf, pipe)) > 0;) out.append(buf, n);
  const int status = pclose(pipe);
  std::ifstream in(err_file);
  std::stringstream err;
  err << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out, err.str()};
}

struct TempDir {
  fs::path path;
  TempDir() : path(fs::temp_directory_path() / ("spinmotor_cli_metrics_" + std::to_string(getpid()))) {
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string file(const std::string& name) const {
    std::string q =
        "'";  // appended, not "'" + std::string&&: GCC 12's -Wrestrict false positive (bug 105329)
    q += (path / name).string();
    q += '\'';
    return q;
  }
};

double shear_q(double s) { return std::pow(0.5 * (s + std::sqrt(s * s + 4)), 2); }

}  // namespace

TEST_CASE("metrics --json on a sheared grid reports the closed-form Q", "[cli][metrics]") {
  TempDir tmp;
  const Mesh g = grid(Eigen::Vector2d(2.0, 1.0), Eigen::Vector2i(9, 6));
  Mesh sheared = g;
  const double s = 0.5;
  sheared.V.col(0) += s * g.V.col(1);
  write_mesh(tmp.path / "rest.obj", g);
  write_mesh(tmp.path / "sheared.obj", sheared);

  const Run r =
      run_cli(tmp.path, "metrics " + tmp.file("rest.obj") + " " + tmp.file("sheared.obj") + " --json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  for (const char* key : {"q_mean", "q_max", "area_distortion", "rms", "max", "edge_distortion", "vertices",
                          "faces", "willmore_rest", "willmore_deformed"})
    CHECK(j.contains(key));
  CHECK(j["vertices"] == 54);
  CHECK(j["faces"] == 80);
  // OBJ round trips are exact, so the closed form holds to rounding.
  CHECK(std::abs(j["q_mean"].get<double>() - shear_q(s)) < 1e-12);
  CHECK(std::abs(j["q_max"].get<double>() - shear_q(s)) < 1e-12);
  CHECK(j["area_distortion"].get<double>() < 1e-12);
  CHECK(std::abs(j["max"].get<double>() - s * 0.5 / std::sqrt(5.0)) < 1e-14);

  // The table form names the same quantities.
  const Run t = run_cli(tmp.path, "metrics " + tmp.file("rest.obj") + " " + tmp.file("sheared.obj"));
  REQUIRE(t.code == 0);
  CHECK(t.out.find("q_mean") != std::string::npos);
  CHECK(t.out.find("1.6403882") != std::string::npos);
}

TEST_CASE("metrics --align similarity removes a similarity from the distances", "[cli][metrics]") {
  TempDir tmp;
  const Mesh m = icosphere(2);
  Mesh moved = m;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  moved.V = ((2.5 * m.V * R.transpose()).rowwise() + Eigen::RowVector3d(1, -2, 0.5)).eval();
  write_mesh(tmp.path / "a.ply", m);
  write_mesh(tmp.path / "b.ply", moved);
  const std::string files = tmp.file("a.ply") + " " + tmp.file("b.ply");
  const Run raw = run_cli(tmp.path, "metrics " + files + " --json --no-willmore");
  REQUIRE(raw.code == 0);
  const nlohmann::json jr = nlohmann::json::parse(raw.out);
  CHECK(jr["rms"].get<double>() > 0.5);
  CHECK(!jr.contains("willmore_rest"));
  const Run al = run_cli(tmp.path, "metrics " + files + " --json --align similarity");
  REQUIRE(al.code == 0);
  const nlohmann::json ja = nlohmann::json::parse(al.out);
  CHECK(ja["rms"].get<double>() < 1e-13);
  CHECK(ja["max"].get<double>() < 1e-13);
  CHECK(std::abs(ja["alignment_scale"].get<double>() - 1 / 2.5) < 1e-13);
  CHECK(std::abs(ja["q_mean"].get<double>() - 1.0) < 1e-12);
  CHECK(std::abs(ja["willmore_rest"].get<double>() - ja["willmore_deformed"].get<double>()) < 1e-10);
}

TEST_CASE("metrics rejects meshes of different connectivity with exit code 2", "[cli][metrics]") {
  TempDir tmp;
  const Mesh a = icosphere(1), b = icosphere(2);
  write_mesh(tmp.path / "a.off", a);
  write_mesh(tmp.path / "b.off", b);
  Mesh flipped = a;
  std::swap(flipped.F(7, 1), flipped.F(7, 2));
  write_mesh(tmp.path / "flipped.off", flipped);

  const Run counts = run_cli(tmp.path, "metrics " + tmp.file("a.off") + " " + tmp.file("b.off") + " --json");
  CHECK(counts.code == 2);
  CHECK(counts.out.empty());
  CHECK(counts.err.find("42 vertices") != std::string::npos);

  const Run faces = run_cli(tmp.path, "metrics " + tmp.file("a.off") + " " + tmp.file("flipped.off"));
  CHECK(faces.code == 2);
  CHECK(faces.err.find("face 7 differs") != std::string::npos);

  const Run missing = run_cli(tmp.path, "metrics " + tmp.file("a.off") + " " + tmp.file("nope.obj"));
  CHECK(missing.code == 2);
  const Run bad_align =
      run_cli(tmp.path, "metrics " + tmp.file("a.off") + " " + tmp.file("a.off") + " --align affine");
  CHECK(bad_align.code == 2);
}

}  // namespace test_cli_metrics
