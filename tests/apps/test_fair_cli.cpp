// `spinmotor fair`, `extrude`, `willmore` and `spectrum --operator ye-*` end to end on the built binary:
// an ellipsoid faired to a sphere (JSON: W falls at every step) and extruded back (reconstruction error
// below 0.5% of the diagonal), the unit sphere's Willmore energy and intrinsic spectrum, and bad input
// (an open grid, mismatched connectivity, a bad tau) exits with code 2 and leaves no output file.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli_support.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"

namespace test_fair_cli {

using namespace spinmotor;
namespace fs = std::filesystem;
using spinmotor_test::Run;
using spinmotor_test::run_cli;
using spinmotor_test::TempDir;

TEST_CASE("fair, extrude, willmore and the Ye spectra from the CLI", "[cli][lefolgoc]") {
  TempDir dir;
  Mesh e = icosphere(3);
  e.V.col(0) *= 2.0;
  e.V.col(2) *= 0.7;
  write_mesh(dir.path / "ellipsoid.obj", e);
  write_mesh(dir.path / "sphere.obj", icosphere(3));
  write_mesh(dir.path / "torus.obj", torus(2.0, 1.0, 16, 8));
  write_mesh(dir.path / "disk.obj", grid({1.0, 1.0}, {6, 6}));
  write_mesh(dir.path / "small.obj", icosphere(1));

  Run r = run_cli(dir.path, "fair " + dir.file("ellipsoid.obj") + " --steps 5 --tau 0.5 --out " +
                                dir.file("faired.obj") + " --json");
  REQUIRE(r.code == 0);
  nlohmann::json j = nlohmann::json::parse(r.out);
  const auto W = j["willmore"].get<std::vector<double>>();
  REQUIRE(W.size() == 6);
  for (std::size_t k = 1; k < W.size(); ++k) CHECK(W[k] < W[k - 1]);
  CHECK(j["q_max"].get<double>() < 1.5);

  r = run_cli(dir.path, "extrude " + dir.file("faired.obj") + " " + dir.file("ellipsoid.obj") + " --out " +
                            dir.file("back.obj") + " --json");
  REQUIRE(r.code == 0);
  j = nlohmann::json::parse(r.out);
  CHECK(j["distance_mean_relative"].get<double>() < 0.005);
  CHECK(fs::exists(dir.path / "back.obj"));

  r = run_cli(dir.path, "willmore " + dir.file("sphere.obj") + " --json");
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(r.out)["willmore_face"].get<double>() == Approx(4 * M_PI).epsilon(0.01));

  r = run_cli(dir.path, "spectrum " + dir.file("sphere.obj") + " --operator ye-intrinsic -k 12 --json");
  REQUIRE(r.code == 0);
  for (const double l : nlohmann::json::parse(r.out)["eigenvalues"].get<std::vector<double>>())
    CHECK(std::abs(std::abs(l) - std::round(std::abs(l))) < 0.02);

  // Bad input: exit 2, message on stderr, no output.
  // A torus fairs (exactness constraints on); an open grid is refused.
  r = run_cli(dir.path, "fair " + dir.file("torus.obj") + " --steps 2 --out " + dir.file("torus_faired.obj"));
  CHECK(r.code == 0);
  r = run_cli(dir.path, "fair " + dir.file("disk.obj") + " --steps 2 --out " + dir.file("bad1.obj"));
  CHECK(r.code == 2);
  CHECK(r.err.find("boundary") != std::string::npos);
  r = run_cli(dir.path, "fair " + dir.file("ellipsoid.obj") + " --tau 1.5 --out " + dir.file("bad2.obj"));
  CHECK(r.code == 2);
  r = run_cli(dir.path, "extrude " + dir.file("small.obj") + " " + dir.file("ellipsoid.obj") + " --out " +
                            dir.file("bad3.obj"));
  CHECK(r.code == 2);
  CHECK(r.err.find("same connectivity") != std::string::npos);
  for (const char* f : {"bad1.obj", "bad2.obj", "bad3.obj"}) CHECK_FALSE(fs::exists(dir.path / f));
}

}  // namespace test_fair_cli
