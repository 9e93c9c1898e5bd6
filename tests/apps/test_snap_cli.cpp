// `spinmotor snap` end to end: an exact spin transformation made by `spinmotor spin` is snapped back
// onto itself (JSON checked), a twisted sausage written as a foreign edit snaps to Q_mean near 1, and
// mismatched meshes exit with code 2, name both counts and leave no output.
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
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"

namespace test_snap_cli {

using namespace spinmotor;
namespace fs = std::filesystem;
using spinmotor_test::Run;
using spinmotor_test::run_cli;
using spinmotor_test::TempDir;

TEST_CASE("snap returns an exact spin transformation made by `spin`", "[cli][snap]") {
  TempDir tmp;
  write_mesh(tmp.path / "rest.obj", icosphere(3));
  const Run s = run_cli(
      tmp.path, "spin " + tmp.file("rest.obj") + " --rho-expr '0.1*sin(2*x)' --out " + tmp.file("spin.obj"));
  REQUIRE(s.code == 0);
  const Run r = run_cli(tmp.path, "snap " + tmp.file("rest.obj") + " " + tmp.file("spin.obj") + " --out " +
                                      tmp.file("snap.obj") + " --json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK(j["vertices"] == 642);
  CHECK(j["rms_edit_to_snap"].get<double>() < 1e-3);
  CHECK(j["q_mean_after"].get<double>() < 1.01);
  const Mesh edit = read_mesh(tmp.path / "spin.obj"), snap = read_mesh(tmp.path / "snap.obj");
  CHECK(vertex_distances(edit.V, snap.V).rms == Approx(j["rms_edit_to_snap"].get<double>()).margin(1e-9));
  CHECK(snap.UV.rows() == edit.UV.rows());  // texture coordinates kept
}

TEST_CASE("snap of a twisted sausage from a file, tradeoff and alignment options", "[cli][snap]") {
  TempDir tmp;
  Mesh m = icosphere(3);
  m.V.col(2) *= 3.0;
  Mesh e = m;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    const double a = M_PI / 2 * (m.V(i, 2) + 3.0) / 6.0;
    e.V(i, 0) = std::cos(a) * m.V(i, 0) - std::sin(a) * m.V(i, 1);
    e.V(i, 1) = std::sin(a) * m.V(i, 0) + std::cos(a) * m.V(i, 1);
  }
  write_mesh(tmp.path / "rest.off", m);
  write_mesh(tmp.path / "edit.ply", e);
  double q_prev = 0;
  for (const char* t : {"0", "1"}) {
    const Run r =
        run_cli(tmp.path, "snap " + tmp.file("rest.off") + " " + tmp.file("edit.ply") + " --out " +
                              tmp.file("snap.obj") + " --tradeoff " + t + " --align translation --json");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(j["q_mean_before"].get<double>() > 1.2);
    if (std::string(t) == "1") CHECK(j["q_mean_after"].get<double>() < q_prev);
    q_prev = j["q_mean_after"].get<double>();
  }
  CHECK(q_prev < 1.01);
  const Run h = run_cli(tmp.path, "snap " + tmp.file("rest.off") + " " + tmp.file("edit.ply") + " --out " +
                                      tmp.file("snap2.obj"));
  CHECK(h.code == 0);
  CHECK_THAT(h.out, Catch::Contains("Q_mean before") && Catch::Contains("RMS distance"));
}

TEST_CASE("snap: mismatched or bad input exits 2 and writes nothing", "[cli][snap][errors]") {
  TempDir tmp;
  write_mesh(tmp.path / "a.obj", icosphere(2));
  write_mesh(tmp.path / "b.obj", icosphere(3));
  const Run r = run_cli(
      tmp.path, "snap " + tmp.file("a.obj") + " " + tmp.file("b.obj") + " --out " + tmp.file("o.obj"));
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Catch::Contains("642 vertices") && Catch::Contains("162 vertices"));
  CHECK_FALSE(fs::exists(tmp.path / "o.obj"));
  // Same counts, different faces.
  Mesh c = icosphere(2);
  std::swap(c.F(3, 0), c.F(3, 1));
  write_mesh(tmp.path / "c.obj", c);
  const Run f = run_cli(
      tmp.path, "snap " + tmp.file("a.obj") + " " + tmp.file("c.obj") + " --out " + tmp.file("o.obj"));
  CHECK(f.code == 2);
  CHECK_THAT(f.err, Catch::Contains("face 3"));
  CHECK_FALSE(fs::exists(tmp.path / "o.obj"));
  // Out-of-range tradeoff is a usage error.
  const Run t = run_cli(tmp.path, "snap " + tmp.file("a.obj") + " " + tmp.file("a.obj") + " --out " +
                                      tmp.file("o.obj") + " --tradeoff 2");
  CHECK(t.code == 2);
  CHECK_FALSE(fs::exists(tmp.path / "o.obj"));
  // The generalized problem needs a closed mesh.
  write_mesh(tmp.path / "g.obj", grid(Eigen::Vector2d(1, 1), Eigen::Vector2i(5, 5)));
  const Run g = run_cli(tmp.path, "snap " + tmp.file("g.obj") + " " + tmp.file("g.obj") + " --out " +
                                      tmp.file("o.obj") + " --problem generalized");
  CHECK(g.code == 2);
  CHECK_THAT(g.err, Catch::Contains("closed"));
  CHECK_FALSE(fs::exists(tmp.path / "o.obj"));
}

TEST_CASE("snap --mode shape: an exact spin transformation comes back, and an open mesh is refused",
          "[cli][snap]") {
  // Extrusion toward the edit's curvature (Le Folgoc et al. 2019): an edit that is itself a spin
  // transformation of the rest mesh has a half-density the extrusion can reach.
  TempDir tmp;
  write_mesh(tmp.path / "rest.obj", icosphere(3));
  REQUIRE(run_cli(tmp.path,
                  "spin " + tmp.file("rest.obj") + " --rho-expr '0.1*sin(2*x)' --out " + tmp.file("spin.obj"))
              .code == 0);
  const Run r = run_cli(tmp.path, "snap " + tmp.file("rest.obj") + " " + tmp.file("spin.obj") + " --out " +
                                      tmp.file("shape.obj") + " --mode shape --json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  CHECK(j["mode"] == "shape");
  CHECK(j["rms_edit_to_snap"].get<double>() < 5e-3);
  CHECK(j["q_mean_after"].get<double>() < 1.02);
  CHECK(fs::exists(tmp.path / "shape.obj"));
  // an open mesh (a grid) has no closed curvature-space extrusion: exit 2, no output
  write_mesh(tmp.path / "grid.obj", grid({1.0, 1.0}, {6, 6}));
  const Run o = run_cli(tmp.path, "snap " + tmp.file("grid.obj") + " " + tmp.file("grid.obj") + " --out " +
                                      tmp.file("open.obj") + " --mode shape");
  CHECK(o.code == 2);
  CHECK(!fs::exists(tmp.path / "open.obj"));
}

}  // namespace test_snap_cli
