// `spinmotor check`: every crafted bad file in tests/data/bad/ gives exit code 2 with its specific
// finding (JSON key or read error), defect-free meshes give 0, and the command writes no file.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "shared_data.hpp"

namespace test_cli_check {

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

std::set<std::string> listing(const fs::path& dir) {
  std::set<std::string> s;
  for (const auto& e : fs::recursive_directory_iterator(dir)) s.insert(e.path().string());
  return s;
}

// Runs the CLI with `args` from an empty working directory and checks that the run created no file
// there; stdout and stderr are captured in files outside it.
Run run_cli(const std::string& args) {
  static int counter = 0;
  const fs::path base =
      fs::temp_directory_path() / ("spinmotor_test_cli_check_" + std::to_string(::getpid()));
  const fs::path cwd = base / ("cwd" + std::to_string(counter++));
  fs::create_directories(cwd);
  const fs::path out = base / "out.txt", err = base / "err.txt";
  const std::string cmd = "cd '" + cwd.string() + "' && '" + std::string(SPINMOTOR_CLI) + "' " + args +
                          " > '" + out.string() + "' 2> '" + err.string() + "'";
  const int status = std::system(cmd.c_str());
  Run r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  CHECK(fs::is_empty(cwd));  // `check` writes no file
  fs::remove_all(base);
  return r;
}

const fs::path kData = SPINMOTOR_TEST_DATA_DIR;
const char* const kDefectKeys[] = {"non_manifold_edges",      "non_manifold_vertices", "degenerate_faces",
                                   "duplicate_vertices",      "unreferenced_vertices", "nonfinite_vertices",
                                   "inconsistent_orientation"};

}  // namespace

TEST_CASE("check --json: each crafted defect gives exit 2 and exactly its finding", "[cli][check]") {
  const std::set<std::string> before = listing(kData);
  const std::pair<const char*, std::pair<const char*, long>> cases[] = {
      {"nan_vertex.obj", {"nonfinite_vertices", 1}},
      {"nonmanifold_edge.obj", {"non_manifold_edges", 1}},
      {"nonmanifold_vertex.obj", {"non_manifold_vertices", 1}},
      {"degenerate_face.obj", {"degenerate_faces", 1}},
      {"duplicate_vertex.obj", {"duplicate_vertices", 1}},
      {"flipped_face.obj", {"inconsistent_orientation", 3}},
      {"unreferenced_vertex.obj", {"unreferenced_vertices", 1}},
  };
  for (const auto& [file, finding] : cases) {
    INFO(file);
    const Run r = run_cli("check --json '" + (kData / "bad" / file).string() + "'");
    CHECK(r.code == 2);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["ok"] == false);
    for (const char* key : kDefectKeys) {
      INFO(key);
      CHECK(j[key] == (std::string(key) == finding.first ? finding.second : 0));
    }
    CHECK(j.contains("defects"));
    CHECK_THAT(r.err, Catch::Contains("has defects"));
  }
  CHECK(listing(kData) == before);
}

TEST_CASE("check: unreadable files give exit 2, a clear error and no output", "[cli][check]") {
  const std::pair<const char*, const char*> cases[] = {
      {"empty.obj", "empty.obj: the file is empty"},
      {"truncated.obj", "truncated.obj:9: face needs at least 3 vertices, got 2"},
      {"truncated.ply", "unexpected end of file (truncated?) in element 'face' 2 of 4"},
      {"wrong_extension.xyz", "unsupported mesh format '.xyz'"},
      {"does_not_exist.obj", "cannot open"},
  };
  for (const auto& [file, message] : cases) {
    INFO(file);
    for (const char* flag : {"--json ", ""}) {
      const Run r = run_cli(std::string("check ") + flag + "'" + (kData / "bad" / file).string() + "'");
      CHECK(r.code == 2);
      CHECK(r.out.empty());
      CHECK_THAT(r.err, Catch::StartsWith("spinmotor: error: ") && Catch::Contains(message));
    }
  }
}

TEST_CASE("check: defect-free meshes give exit 0, boundaries and genus are properties", "[cli][check]") {
  SPINMOTOR_REQUIRE_MESHES();
  const Run t = run_cli("check --json '" + (kData / "tetrahedron.obj").string() + "'");
  CHECK(t.code == 0);
  CHECK(t.err.empty());
  const auto j = nlohmann::json::parse(t.out);
  CHECK(j["ok"] == true);
  CHECK(j["vertices"] == 4);
  CHECK(j["faces"] == 4);
  CHECK(j["components"] == 1);
  CHECK(j["boundary_loops"] == 0);
  CHECK(j["genus"] == 0);
  for (const char* key : kDefectKeys) CHECK(j[key] == 0);

  const Run a = run_cli("check --json '" + (fs::path(SPINMOTOR_MESHES_DIR) / "alligator.obj").string() + "'");
  CHECK(a.code == 0);  // open, 433 boundary edges: not a defect
  const auto ja = nlohmann::json::parse(a.out);
  CHECK(ja["boundary_edges"] == 433);
  CHECK(ja["closed"] == false);
  CHECK(ja["genus"] == 0);

  const Run c = run_cli("check --json '" + (fs::path(SPINMOTOR_MESHES_DIR) / "cow.obj").string() + "'");
  CHECK(c.code == 2);
  const auto jc = nlohmann::json::parse(c.out);
  CHECK(jc["genus"].is_null());  // not defined on a non-manifold
  CHECK(jc["first"]["non_manifold_vertex"] == 253);
}

TEST_CASE("check: the table marks defects, usage errors exit 2", "[cli][check]") {
  const Run t = run_cli("check '" + (kData / "bad" / "nonmanifold_edge.obj").string() + "'");
  CHECK(t.code == 2);
  CHECK_THAT(t.out,
             Catch::Contains("non_manifold_edges         1          <- defect") &&
                 Catch::Contains(
                     "defects (0-based indices): 1 non-manifold edge: edge (0, 1) is shared by 3 faces"));
  const Run ok = run_cli("check '" + (kData / "tetrahedron.obj").string() + "'");
  CHECK(ok.code == 0);
  CHECK_THAT(ok.out, Catch::Contains("ok: no defects (closed, one component)"));
  CHECK(run_cli("check").code == 2);
}

}  // namespace test_cli_check
