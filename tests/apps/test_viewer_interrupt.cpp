// spinmotor-viewer's headless frame loop stopped by SIGINT or SIGTERM: exit 128 + signal, one line on
// stderr with the frames done, and no screenshot (nor its temporary) on disk.
#include <signal.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "cli_support.hpp"

namespace test_viewer_interrupt {

using nlohmann::json;
namespace fs = std::filesystem;
using spinmotor_test::TempDir;

#ifdef SPINMOTOR_VIEWER
namespace {

/// True once `pid` catches both SIGINT and SIGTERM (the SigCgt mask of /proc/PID/status): its frame
/// loop's InterruptGuard is installed, so a signal now stops the loop instead of killing the process.
bool catches_int_and_term(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("SigCgt:", 0) == 0) {
      const unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
      const unsigned long long want = (1ull << (SIGINT - 1)) | (1ull << (SIGTERM - 1));
      return (mask & want) == want;
    }
  return false;
}

void interrupt_and_check(int sig) {
  TempDir tmp;
  const json doc = json::parse(R"({
    "mesh": {"generate": "capsule", "radius": 0.5, "length": 3, "rings": 8, "sides": 8},
    "handles": [{"name": "base", "select": {"box": {"min": [-1, -1, -1], "max": [1, 1, -0.2]}}},
                {"name": "tip", "select": {"box": {"min": [-1, -1, 3.2], "max": [1, 1, 4]}}}],
    "deformer": {"type": "surface-harmonic"}})");
  const fs::path scene = tmp.path / "capsule.json", shot = tmp.path / "shot" / "out.png";
  std::ofstream(scene) << doc.dump();
  fs::create_directories(shot.parent_path());
  const pid_t pid = spinmotor_test::spawn({SPINMOTOR_VIEWER, scene.string(), "--screenshot", shot.string(),
                                           "--size", "32x32", "--frames", "100000000"},
                                          tmp.path / "stdout.txt", tmp.path / "stderr.txt");
  const auto t0 = std::chrono::steady_clock::now();
  while (!catches_int_and_term(pid) && !spinmotor_test::has_exited(pid) &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // a few frames in
  REQUIRE(kill(pid, sig) == 0);
  const int code = spinmotor_test::wait_exit(pid);
  std::ifstream in(tmp.path / "stderr.txt");
  std::stringstream err;
  err << in.rdbuf();
  CAPTURE(err.str());
  CHECK(code == 128 + sig);
  CHECK(std::regex_search(err.str(), std::regex(std::string("spinmotor-viewer: interrupted by ") +
                                                (sig == SIGINT ? "SIGINT" : "SIGTERM") +
                                                " after [0-9]+ of 100000000 frames; no screenshot written")));
  CHECK(fs::is_empty(shot.parent_path()));  // no picture, no temporary
}

}  // namespace

TEST_CASE("spinmotor-viewer --frames stopped by SIGINT: exit 130, no screenshot", "[viewer][interrupt]") {
  interrupt_and_check(SIGINT);
}

TEST_CASE("spinmotor-viewer --frames stopped by SIGTERM: exit 143, no screenshot", "[viewer][interrupt]") {
  interrupt_and_check(SIGTERM);
}
#endif

}  // namespace test_viewer_interrupt
