// `spinmotor flow` end to end: the built binary on a bumpy disk (JSON parsed: the energy falls at every
// step; --minimal removes nearly all of it), and bad input (a broken mesh, a missing mode, a step
// outside (0, 1]) exits with code 2 and leaves no output file.
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

namespace test_flow_cli {

using namespace spinmotor;
namespace fs = std::filesystem;
using spinmotor_test::Run;
using spinmotor_test::run_cli;
using spinmotor_test::TempDir;

namespace {

/// A 2×2 grid (31×31 vertices) lifted onto a Gaussian bump, written to dir/bump.obj.
fs::path write_bump(const fs::path& dir) {
  Mesh g = grid({2, 2}, {31, 31});
  for (int i = 0; i < g.V.rows(); ++i) {
    const double x = g.V(i, 0), y = g.V(i, 1);
    g.V(i, 2) = 0.3 * std::exp(-4 * (x * x + y * y));
  }
  const fs::path p = dir / "bump.obj";
  write_mesh(p, g);
  return p;
}

}  // namespace

TEST_CASE("flow --willmore lowers the energy at every step, --minimal removes it", "[cli][flow]") {
  TempDir tmp;
  const fs::path in = write_bump(tmp.path);
  const Run r = run_cli(
      tmp.path, "flow '" + in.string() + "' --willmore 0.3 --steps 3 --out " + tmp.file("w.obj") + " --json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  REQUIRE(j["willmore"].size() == 4);
  for (int k = 1; k <= 3; ++k) {
    const double ratio = j["willmore"][k].get<double>() / j["willmore"][k - 1].get<double>();
    CHECK(ratio < 1.0);
    CHECK(ratio == Approx(0.49).epsilon(0.06));  // (1 − τ)² per step
  }
  CHECK(j["q_mean"].get<double>() < 1.05);
  const Mesh out = read_mesh(tmp.path / "w.obj");
  CHECK(out.V.rows() == 31 * 31);
  CHECK(out.has_uv());  // texture coordinates kept

  const Run m =
      run_cli(tmp.path, "flow '" + in.string() + "' --minimal --out " + tmp.file("m.obj") + " --json");
  INFO(m.err);
  REQUIRE(m.code == 0);
  const nlohmann::json jm = nlohmann::json::parse(m.out);
  CHECK(jm["steps"] == 1);
  CHECK(jm["willmore_ratio"].get<double>() < 1e-2);
  CHECK(fs::exists(tmp.path / "m.obj"));
}

TEST_CASE("flow: bad input exits with code 2 and writes nothing", "[cli][flow][errors]") {
  TempDir tmp;
  {
    std::ofstream bad(tmp.path / "bad.obj");
    bad << "v 0 0 0\nv 1 0 0\nf 1 2 3\n";  // index out of range
  }
  const fs::path in = write_bump(tmp.path);
  const std::string bad = spinmotor_test::quoted((tmp.path / "bad.obj").string());
  const std::string good = spinmotor_test::quoted(in.string());
  for (const std::string& args : {"flow " + bad + " --minimal --out " + tmp.file("o.obj"),
                                  "flow " + bad + " --willmore 0.2 --steps 2 --out " + tmp.file("o.obj"),
                                  "flow " + good + " --out " + tmp.file("o.obj"),
                                  "flow " + good + " --willmore 1.5 --out " + tmp.file("o.obj"),
                                  "flow " + good + " --willmore 0.2 --steps 0 --out " + tmp.file("o.obj"),
                                  "flow " + good + " --willmore 0.2 --minimal --out " + tmp.file("o.obj")}) {
    INFO(args);
    const Run r = run_cli(tmp.path, args);
    CHECK(r.code == 2);
    CHECK_FALSE(r.err.empty());  // a message on stderr
    CHECK_FALSE(fs::exists(tmp.path / "o.obj"));
  }
}

}  // namespace test_flow_cli
