// `spinmotor spin` and `spinmotor spectrum` end to end: the built binary on the SpinXForm reference case
// and on an icosphere, its JSON parsed and checked; bad input exits with code 2 and leaves no file.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli_support.hpp"
#include "shared_data.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"

namespace test_spin_cli {

using namespace spinmotor;
namespace fs = std::filesystem;
using spinmotor_test::Run;
using spinmotor_test::run_cli;
using spinmotor_test::TempDir;

namespace {

const std::string kSpin = std::string(SPINMOTOR_MESHES_DIR) + "/spinxform/";

}  // namespace

TEST_CASE("spin --rho-image --spinxform reproduces the reference output", "[cli][spin]") {
  SPINMOTOR_REQUIRE_MESHES();
  TempDir tmp;
  const Run r = run_cli(tmp.path, "spin '" + kSpin + "sphere.obj' --rho-image '" + kSpin +
                                      "bumpy.tga' --spinxform --out " + tmp.file("bumpy.obj") + " --json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["vertices"] == 4002);
  CHECK(j["faces"] == 8000);
  CHECK(j["eigen_iterations"] == 3);
  CHECK(j["problem"] == "unweighted");
  for (const char* key : {"bind_ms", "assembly_ms", "factor_ms", "eigen_ms", "poisson_ms", "total_ms",
                          "eigenvalue", "eigen_residual"})
    CHECK(j.contains(key));
  CHECK(j["q_mean"].get<double>() <= 1.052);
  CHECK(j["q_max"].get<double>() < 1.13);
  const Mesh out = read_mesh(tmp.path / "bumpy.obj");
  const Mesh ref = read_mesh(kSpin + "bumpy_reference.obj");
  CHECK(vertex_distances(ref.V, out.V, Alignment::None).rms < 1e-5);
  CHECK(out.has_uv());  // texture coordinates are kept
}

TEST_CASE("spin with per-face and per-vertex rho files, converged default", "[cli][spin]") {
  TempDir tmp;
  const Mesh m = icosphere(3, 3.0);
  write_mesh(tmp.path / "sphere.obj", m);
  {
    std::ofstream f(tmp.path / "rho_v.txt");
    f << "# one value per vertex\n";
    for (Eigen::Index i = 0; i < m.V.rows(); ++i) f << 0.5 * std::sin(2 * m.V(i, 0)) << '\n';
    std::ofstream g(tmp.path / "rho_f.txt");
    for (Eigen::Index i = 0; i < m.F.rows(); ++i) g << 0.0 << ' ';
  }
  const Run rv = run_cli(tmp.path, "spin " + tmp.file("sphere.obj") + " --rho-vertices " +
                                       tmp.file("rho_v.txt") + " --out " + tmp.file("v.obj") + " --json");
  INFO(rv.err);
  REQUIRE(rv.code == 0);
  const auto jv = nlohmann::json::parse(rv.out);
  CHECK(jv["problem"] == "standard");
  CHECK(jv["eigen_residual"].get<double>() < 1e-10);
  CHECK(jv["q_mean"].get<double>() > 1.0);
  // ρ = 0: the output equals the input (same area, same place).
  const Run rf = run_cli(tmp.path, "spin " + tmp.file("sphere.obj") + " --rho-faces " +
                                       tmp.file("rho_f.txt") + " --out " + tmp.file("f.obj"));
  INFO(rf.err);
  REQUIRE(rf.code == 0);
  CHECK(vertex_distances(m.V, read_mesh(tmp.path / "f.obj").V, Alignment::None).rms < 1e-8);
}

TEST_CASE("spin on an open tube: free boundaries warn, --keep-boundary-tangents stays conformal",
          "[cli][spin]") {
  TempDir tmp;
  write_mesh(tmp.path / "tube.obj", tube(1.0, 10.0, 100, 40, false));
  const std::string args =
      "spin " + tmp.file("tube.obj") + " --rho-expr '0.2*exp(-20*((z-5)^2+(x-1)^2))' --json";
  const Run free = run_cli(tmp.path, args + " --out " + tmp.file("free.obj"));
  REQUIRE(free.code == 0);
  INFO(free.err);
  CHECK(nlohmann::json::parse(free.out)["q_mean"].get<double>() > 1.5);  // 2.14 measured
  CHECK(free.err.find("--keep-boundary-tangents") != std::string::npos);
  const Run kept = run_cli(tmp.path, args + " --keep-boundary-tangents --out " + tmp.file("kept.obj"));
  REQUIRE(kept.code == 0);
  CHECK(nlohmann::json::parse(kept.out)["q_mean"].get<double>() < 1.01);  // 1.0022 measured
  CHECK(kept.err.empty());
  write_mesh(tmp.path / "sphere.obj", icosphere(2));
  const Run closed =
      run_cli(tmp.path, "spin " + tmp.file("sphere.obj") + " --rho-expr 0 --keep-boundary-tangents --out " +
                            tmp.file("c.obj"));
  CHECK(closed.code == 2);
  CHECK(closed.err.find("no boundary") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(tmp.path / "c.obj"));
}

TEST_CASE("spin errors exit with code 2 and write nothing", "[cli][spin]") {
  SPINMOTOR_REQUIRE_MESHES();
  TempDir tmp;
  Mesh m = icosphere(2);
  m.UV.resize(0, 2);
  m.FUV.resize(0, 3);
  write_mesh(tmp.path / "nouv.obj", m);
  const Run a = run_cli(tmp.path, "spin " + tmp.file("nouv.obj") + " --rho-image '" + kSpin +
                                      "bumpy.tga' --out " + tmp.file("a.obj"));
  CHECK(a.code == 2);
  CHECK(a.err.find("texture coordinates") != std::string::npos);
  CHECK_FALSE(fs::exists(tmp.path / "a.obj"));
  const Run b = run_cli(tmp.path, "spin " + tmp.file("nouv.obj") + " --out " + tmp.file("b.obj"));
  CHECK(b.code == 2);
  {
    std::ofstream f(tmp.path / "short.txt");
    f << "1 2 3\n";
  }
  const Run c = run_cli(tmp.path, "spin " + tmp.file("nouv.obj") + " --rho-faces " + tmp.file("short.txt") +
                                      " --out " + tmp.file("c.obj"));
  CHECK(c.code == 2);
  CHECK(c.err.find("3 values for 320 faces") != std::string::npos);
  CHECK_FALSE(fs::exists(tmp.path / "c.obj"));
}

TEST_CASE("spectrum --operator crane on the unit sphere", "[cli][spectrum]") {
  TempDir tmp;
  write_mesh(tmp.path / "sphere.obj", icosphere(3));
  const Run r = run_cli(tmp.path, "spectrum " + tmp.file("sphere.obj") + " --operator crane -k 12 --json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["constant_kernel"] == 4);
  const auto ev = j["eigenvalues"].get<std::vector<double>>();
  REQUIRE(ev.size() == 12);
  for (int t = 0; t < 8; ++t) CHECK(ev[t] == Approx(1.0).epsilon(0.02));
  for (int t = 8; t < 12; ++t) CHECK(ev[t] == Approx(-2.0).epsilon(0.02));
  const Run bad = run_cli(tmp.path, "spectrum " + tmp.file("sphere.obj") + " --operator ye -k 4");
  CHECK(bad.code == 2);
}

}  // namespace test_spin_cli
