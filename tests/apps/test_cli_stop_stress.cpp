// Stop requests at many moments of long runs: SIGTERM and SIGINT, alternately, sent to `spinmotor
// flow`, `spin`, `snap`, `deform` and `batch` at moments spread over the run — while METIS orders
// (every spin transformation orders its vertex graph with METIS, on these 10k- and 40k-vertex meshes
// every flow step does), while CHOLMOD factorizes, solves, writes — end each run with the documented
// status within 2 s and leave no temporary file: flow, spin and snap end by the signal (a shell reports
// 128 + signal) with no output mesh; deform exits with 128 + signal after the frame in progress (by the
// signal while it binds), the frames on disk complete; batch exits with 128 + signal once its commands
// have stopped, with no output. Each case prints its counts. SPINMOTOR_STOP_STRESS=quick (CI's
// sanitizer run, CMakePresets.json) tries 4 moments per command (deform: 4 in its bind, 4 in its
// frames) and smaller meshes for spin, snap and deform.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_support.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"

namespace test_cli_stop_stress {

using namespace spinmotor;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using spinmotor_test::TempDir;

namespace {

constexpr double kStopWithin = 2.0;  // seconds from the signal to the exit

bool quick() {
  const char* s = std::getenv("SPINMOTOR_STOP_STRESS");
  return s && std::string(s) == "quick";
}

/// `count` moments from `first` on, `step` apart; 4 of them spread over the same span when quick().
std::vector<double> moments(double first, double step, int count) {
  std::vector<double> at;
  const int n = quick() ? 4 : count;
  for (int k = 0; k < n; ++k) at.push_back(first + step * (count - 1) * k / std::max(1, n - 1));
  return at;
}

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// An ellipsoid (semi-axes 1, 0.7, 0.5) of icosphere(level): 10,242 vertices at level 5, 40,962 at 6.
Mesh ellipsoid(int level) {
  Mesh m = icosphere(level);
  m.V.col(1) *= 0.7;
  m.V.col(2) *= 0.5;
  return m;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Every file under `dir` whose name ends in ".tmp" (AtomicFile's temporaries).
std::vector<fs::path> temporaries(const fs::path& dir) {
  std::vector<fs::path> found;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec))
    if (it->path().extension() == ".tmp") found.push_back(it->path());
  return found;
}

/// One stop: the run's status as a shell reports it (exit code, or 128 + the signal that ended it),
/// whether a signal ended it, and the seconds from the signal to the exit.
struct Stop {
  bool finished_first = false;  // the run had ended before the moment came (not a try)
  int status = -1;              // -1: still running 10 s after the signal, then killed (SIGKILL)
  bool by_signal = false;
  double seconds = 0;
};

constexpr double kGiveUp = 10;  // seconds: a run still going then is killed, so it cannot outlive the test

/// Starts `argv` with stdout and stderr in dir, waits until ready(pid) (at most 60 s), then `delay`
/// seconds, sends `sig` and waits for the exit.
Stop stop_at(const std::vector<std::string>& argv, const fs::path& dir, double delay, int sig,
             const std::function<bool(pid_t)>& ready = {}) {
  const pid_t pid = spinmotor_test::spawn(argv, dir / "stdout.txt", dir / "stderr.txt");
  const auto t0 = Clock::now();
  while (ready && !ready(pid) && !spinmotor_test::has_exited(pid) && seconds_since(t0) < 60)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  const auto t1 = Clock::now();
  while (seconds_since(t1) < delay && !spinmotor_test::has_exited(pid))
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  Stop s;
  s.finished_first = spinmotor_test::has_exited(pid);
  const auto signalled = Clock::now();
  if (!s.finished_first) ::kill(pid, sig);
  while (!spinmotor_test::has_exited(pid) && seconds_since(signalled) < kGiveUp)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  s.seconds = seconds_since(signalled);
  const bool hung = !spinmotor_test::has_exited(pid);
  if (hung) ::kill(pid, SIGKILL);
  int raw = 0;
  while (waitpid(pid, &raw, 0) < 0 && errno == EINTR) {
  }
  s.by_signal = !hung && WIFSIGNALED(raw);
  s.status = hung ? -1 : WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  return s;
}

/// Counts for one command, printed at the end of its case.
struct Tally {
  std::string command;
  int tried = 0, stopped = 0, finished_first = 0, by_signal = 0;
  double slowest = 0;
  void print() const {
    std::cout << "stop stress: " << command << ": " << tried << " moments tried, " << stopped
              << " stopped as documented within " << kStopWithin << " s (" << by_signal
              << " by the signal itself), slowest " << slowest << " s";
    if (finished_first) std::cout << "; " << finished_first << " moments after the run had ended";
    std::cout << '\n';
  }
};

/// Checks one stop of a run that documents its end by the signal (flow, spin, snap) or by the exit code
/// 128 + signal (deform, batch: `by_exit` true; deform may also end by the signal while it binds), and
/// that no temporary is left; the caller checks the outputs.
void check_stop(Tally& t, const Stop& s, int sig, bool by_exit, const fs::path& dir) {
  if (s.finished_first) {
    ++t.finished_first;
    return;
  }
  ++t.tried;
  t.slowest = std::max(t.slowest, s.seconds);
  t.by_signal += s.by_signal;
  CHECK(s.status == 128 + sig);
  if (!by_exit) CHECK(s.by_signal);
  CHECK(s.seconds < kStopWithin);
  const std::vector<fs::path> left = temporaries(dir);
  CHECK(left.empty());
  t.stopped += s.status == 128 + sig && s.seconds < kStopWithin && left.empty() && (by_exit || s.by_signal);
}

/// The moments of a one-shot command (spin, snap): spread over the first 60 % of an undisturbed run of
/// it, which must succeed.
std::vector<double> one_shot_moments(const std::vector<std::string>& argv, const fs::path& dir,
                                     const fs::path& out, int count) {
  const pid_t pid = spinmotor_test::spawn(argv, dir / "stdout.txt", dir / "stderr.txt");
  const auto t0 = Clock::now();
  REQUIRE(spinmotor_test::wait_exit_within(pid, 120) == 0);
  const double T = seconds_since(t0);
  REQUIRE(fs::exists(out));
  fs::remove(out);
  std::vector<double> at;
  for (int k = 0; k < count; ++k) at.push_back(T * (0.02 + 0.58 * k / std::max(1, count - 1)));
  return at;
}

/// Runs the one-shot command `argv` (its output `out`) stopped at `count` moments.
void stress_one_shot(const std::string& name, const std::vector<std::string>& argv, const fs::path& dir,
                     const fs::path& out, int count) {
  Tally t{name};
  const std::vector<double> at = one_shot_moments(argv, dir, out, count);
  for (std::size_t k = 0; k < at.size(); ++k) {
    const int sig = k % 2 ? SIGINT : SIGTERM;
    INFO(name << " at " << at[k] << " s, signal " << sig);
    const Stop s = stop_at(argv, dir, at[k], sig);
    check_stop(t, s, sig, false, dir);
    if (!s.finished_first) CHECK_FALSE(fs::exists(out));
    fs::remove(out);
  }
  t.print();
  CHECK(t.tried >= static_cast<int>(at.size()) - 1);  // an undisturbed run took as long
  CHECK(t.stopped == t.tried);
}

}  // namespace

TEST_CASE("stop stress: flow stopped at many moments ends by the signal within 2 s, no output",
          "[cli][interrupt][stress]") {
  TempDir tmp;
  write_mesh(tmp.path / "ell.obj", ellipsoid(5));
  const fs::path out = tmp.path / "out" / "flowed.obj";
  const std::vector<std::string> argv = {SPINMOTOR_CLI, "flow",  (tmp.path / "ell.obj").string(),
                                         "--willmore",  "0.01",  "--steps",
                                         "100000",      "--out", out.string()};
  Tally t{"flow"};
  const std::vector<double> at = moments(0.1, 0.083, 16);  // ~0.2 s a step: every phase, several steps in
  for (std::size_t k = 0; k < at.size(); ++k) {
    const int sig = k % 2 ? SIGINT : SIGTERM;
    INFO("flow at " << at[k] << " s, signal " << sig);
    check_stop(t, stop_at(argv, tmp.path, at[k], sig), sig, false, tmp.path);
    CHECK_FALSE(fs::exists(out));
  }
  t.print();
  CHECK(t.tried == static_cast<int>(at.size()));
  CHECK(t.stopped == t.tried);
}

TEST_CASE("stop stress: spin stopped at many moments ends by the signal within 2 s, no output",
          "[cli][interrupt][stress]") {
  TempDir tmp;
  write_mesh(tmp.path / "ell.obj", ellipsoid(quick() ? 5 : 6));
  const fs::path out = tmp.path / "spun.obj";
  stress_one_shot("spin",
                  {SPINMOTOR_CLI, "spin", (tmp.path / "ell.obj").string(), "--rho-expr", "0.5*z", "--out",
                   out.string(), "-q"},
                  tmp.path, out, quick() ? 4 : 12);
}

TEST_CASE("stop stress: snap stopped at many moments ends by the signal within 2 s, no output",
          "[cli][interrupt][stress]") {
  TempDir tmp;
  const Mesh rest = ellipsoid(quick() ? 5 : 6);
  Mesh posed = rest;
  for (Eigen::Index i = 0; i < posed.V.rows(); ++i) {  // twisted about z
    const double a = 0.8 * rest.V(i, 2), x = rest.V(i, 0), y = rest.V(i, 1);
    posed.V(i, 0) = x * std::cos(a) - y * std::sin(a);
    posed.V(i, 1) = x * std::sin(a) + y * std::cos(a);
  }
  write_mesh(tmp.path / "rest.obj", rest);
  write_mesh(tmp.path / "posed.obj", posed);
  const fs::path out = tmp.path / "snapped.obj";
  stress_one_shot("snap",
                  {SPINMOTOR_CLI, "snap", (tmp.path / "rest.obj").string(), (tmp.path / "posed.obj").string(),
                   "--out", out.string(), "-q"},
                  tmp.path, out, quick() ? 4 : 12);
}

TEST_CASE("stop stress: deform stopped at many moments exits 128 + signal within 2 s, frames complete",
          "[cli][interrupt][stress]") {
  TempDir tmp;
  // A 9,602-vertex capsule (2,402 when quick: a frame must take well under 2 s in the sanitizer build
  // too), its tip bending back and forth over 2000 frames, each frame snapped: the bind orders with
  // METIS, the frames solve.
  nlohmann::json doc = nlohmann::json::parse(R"({
    "mesh": {"generate": "capsule", "radius": 0.5, "length": 3, "rings": 100, "sides": 96},
    "handles": [{"name": "base", "select": {"box": {"min": [-1, -1, -1], "max": [1, 1, -0.2]}}},
                {"name": "tip", "select": {"box": {"min": [-1, -1, 3.2], "max": [1, 1, 4]}}}],
    "deformer": {"type": "surface-harmonic"},
    "snap": {"enabled": true},
    "output": {"mesh": "out/c.obj"}})");
  if (quick()) doc["mesh"]["rings"] = 50, doc["mesh"]["sides"] = 48;
  for (int k = 0; k < 2000; ++k) {
    nlohmann::json tip = nlohmann::json::parse(R"({"rotate": {"axis": [1, 0, 0], "about": [0, 0, 3]}})");
    tip["rotate"]["degrees"] = 30.0 * (k % 20) / 20;
    doc["frames"].push_back({{"tip", tip}});
  }
  std::ofstream(tmp.path / "long.json") << doc.dump();
  const fs::path run = tmp.path / "run";
  const std::vector<std::string> argv = {SPINMOTOR_CLI, "deform",     (tmp.path / "long.json").string(),
                                         "--out-dir",   run.string(), "-q"};
  Tally t{"deform"};
  // The bind first (its METIS ordering ~0.1 s in here; no frame yet: ended by the signal), then frames.
  std::vector<double> at = moments(0.05, 0.025, 6), frames_at = moments(0.3, 0.45, 5);
  at.insert(at.end(), frames_at.begin(), frames_at.end());
  for (std::size_t k = 0; k < at.size(); ++k) {
    const int sig = k % 2 ? SIGINT : SIGTERM;
    INFO("deform at " << at[k] << " s, signal " << sig);
    const Stop s = stop_at(argv, tmp.path, at[k], sig);
    check_stop(t, s, sig, true, tmp.path);
    int frames = 0;
    if (fs::exists(run / "out"))
      for (const auto& e : fs::directory_iterator(run / "out")) frames += e.path().extension() == ".obj";
    std::smatch m;
    const std::string err = slurp(tmp.path / "stderr.txt");
    if (std::regex_search(err, m, std::regex("deform stopped after ([0-9]+) of 2000 frames")))
      CHECK(frames == std::stoi(m[1]));  // exactly the frames it says are complete
    else
      CHECK(frames == 0);  // ended by the signal before its first frame
    fs::remove_all(run);
  }
  t.print();
  CHECK(t.tried == static_cast<int>(at.size()));
  CHECK(t.stopped == t.tried);
}

TEST_CASE("stop stress: batch stopped at many moments exits 128 + signal within 2 s, no output",
          "[cli][interrupt][stress][batch]") {
  TempDir tmp;
  fs::create_directories(tmp.path / "in");
  for (const char* name : {"a.obj", "b.obj", "c.obj"}) write_mesh(tmp.path / "in" / name, ellipsoid(5));
  const fs::path out = tmp.path / "out";
  std::vector<std::string> argv = {
      SPINMOTOR_CLI, "batch",      "-j",    "2",
      "--out-dir",   out.string(), "--run", "flow {in} --willmore 0.01 --steps 100000 --out {out}"};
  for (const char* name : {"a.obj", "b.obj", "c.obj"}) argv.push_back((tmp.path / "in" / name).string());
  // From the moment the batch runs its commands (its InterruptGuard is installed).
  const auto running = [](pid_t pid) { return spinmotor_test::signal_mask_has(pid, "SigCgt:", SIGTERM); };
  Tally t{"batch"};
  const std::vector<double> at = moments(0.05, 0.17, 8);  // the commands start, read, order, factorize
  for (std::size_t k = 0; k < at.size(); ++k) {
    const int sig = k % 2 ? SIGINT : SIGTERM;
    INFO("batch at " << at[k] << " s, signal " << sig);
    const Stop s = stop_at(argv, tmp.path, at[k], sig, running);
    check_stop(t, s, sig, true, tmp.path);
    CHECK_FALSE(s.by_signal);  // the batch reports, then exits 128 + signal
    CHECK_THAT(slurp(tmp.path / "stderr.txt"), Catch::Contains("batch stopped with 0 of 3 outputs written"));
    for (const auto& e : fs::directory_iterator(out)) CHECK(e.path().filename() == "logs");
    fs::remove_all(out);
  }
  t.print();
  CHECK(t.tried == static_cast<int>(at.size()));
  CHECK(t.stopped == t.tried);
}

}  // namespace test_cli_stop_stress
