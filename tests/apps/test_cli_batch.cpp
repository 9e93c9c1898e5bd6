// `spinmotor batch`: one process per mesh, failures isolated (exit code = the worst), outputs only for
// the meshes that succeeded, and a second run skips the outputs that exist (resumable); a SIGTERM to
// the batch alone stops it and the command it runs, with nothing half-written left behind.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "cli_support.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"

namespace test_cli_batch {

namespace fs = std::filesystem;
using nlohmann::json;

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

Run run_cli(const fs::path& cwd, const std::string& args) {
  const std::string cmd = "cd '" + cwd.string() + "' && '" + std::string(SPINMOTOR_CLI) + "' " + args +
                          " > stdout.txt 2> stderr.txt";
  const int status = std::system(cmd.c_str());
  Run r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(cwd / "stdout.txt");
  r.err = slurp(cwd / "stderr.txt");
  return r;
}

}  // namespace

TEST_CASE("batch runs one process per mesh, isolates failures and resumes", "[cli][batch]") {
  const fs::path dir = fs::temp_directory_path() / ("spinmotor_test_batch_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "in");
  spinmotor::write_mesh(dir / "in" / "sphere.obj", spinmotor::icosphere(2));
  spinmotor::write_mesh(dir / "in" / "capsule.obj", spinmotor::capsule(0.5, 2.0, 16, 12));
  spinmotor::write_mesh(dir / "in" / "torus.obj", spinmotor::torus(1.0, 0.4, 24, 12));
  std::ofstream(dir / "in" / "broken.obj") << "v 0 0 0\nf 1 2 3\n";
  const std::string run = "--run \"spin {in} --rho-expr '0.5*z' --out {out}\" --out-dir out -j 2 --json";

  const Run first = run_cli(dir, "batch " + run + " in/broken.obj in/capsule.obj in/sphere.obj in/torus.obj");
  INFO(first.out << first.err);
  CHECK(first.code == 2);  // the broken mesh is a bad input; the others still ran
  const json j = json::parse(first.out);
  CHECK(j["ok"] == 3);
  CHECK(j["failed"] == 1);
  CHECK(j["skipped"] == 0);
  for (const char* f : {"capsule.obj", "sphere.obj", "torus.obj"}) CHECK(fs::exists(dir / "out" / f));
  CHECK(!fs::exists(dir / "out" / "broken.obj"));
  CHECK_THAT(slurp(dir / "out" / "logs" / "broken.log"), Catch::Contains("vertex index 2 out of range"));
  CHECK_THAT(first.err, Catch::Contains("1 of 4 runs failed"));

  // resumable: remove one output, run the good meshes again: 1 ran, 2 skipped
  fs::remove(dir / "out" / "sphere.obj");
  const Run second = run_cli(dir, "batch " + run + " in/capsule.obj in/sphere.obj in/torus.obj");
  CHECK(second.code == 0);
  const json k = json::parse(second.out);
  CHECK(k["ok"] == 1);
  CHECK(k["skipped"] == 2);
  CHECK(fs::exists(dir / "out" / "sphere.obj"));

  // usage errors: no {out}, same stem twice, unterminated quote
  CHECK(run_cli(dir, "batch --run \"check {in}\" --out-dir out in/sphere.obj").code == 2);
  CHECK(run_cli(dir, "batch --run \"spin {in} --out {out}\" --out-dir out in/sphere.obj in/../in/sphere.obj")
            .code == 2);
  CHECK(run_cli(dir, "batch --run \"spin {in} --rho-expr '0.5 --out {out}\" --out-dir out in/sphere.obj")
            .code == 2);
  fs::remove_all(dir);
}

namespace {

/// The first child of `pid` (from /proc), or 0.
pid_t first_child(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children");
  long child = 0;
  return in >> child ? static_cast<pid_t>(child) : 0;
}

/// argv[1] of process `pid` (from /proc), or "".
std::string subcommand(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/cmdline");
  std::string arg;
  std::getline(in, arg, '\0');
  std::getline(in, arg, '\0');
  return in ? arg : std::string();
}

/// True once the batch `pid` is in its run loop (its InterruptGuard catches SIGTERM) and `child`, the
/// command it runs, takes SIGTERM on its signal thread (its main thread blocks it: take_stop_signals).
/// The child must be `flow` already: between posix_spawn's fork and its exec the child is a copy of the
/// batch with every signal blocked, and the batch waits in posix_spawn until it has exec'ed.
bool both_ready(pid_t batch, pid_t child) {
  return spinmotor_test::signal_mask_has(batch, "SigCgt:", SIGTERM) && subcommand(child) == "flow" &&
         spinmotor_test::signal_mask_has(child, "SigBlk:", SIGTERM);
}

}  // namespace

TEST_CASE("batch stopped by SIGTERM: the running command is stopped too, exit 143, nothing half-written",
          "[cli][batch][interrupt]") {
  spinmotor_test::TempDir tmp;
  const fs::path& dir = tmp.path;
  fs::create_directories(dir / "in");
  for (const char* name : {"a.obj", "b.obj", "c.obj"})
    spinmotor::write_mesh(dir / "in" / name, spinmotor::icosphere(3));
  // one at a time, each run far longer than the test waits
  std::vector<std::string> argv = {SPINMOTOR_CLI, "batch",
                                   "-j",          "1",
                                   "--out-dir",   (dir / "out").string(),
                                   "--run",       "flow {in} --willmore 0.01 --steps 1000000 --out {out}"};
  for (const char* name : {"a.obj", "b.obj", "c.obj"}) argv.push_back((dir / "in" / name).string());
  const pid_t batch = spinmotor_test::spawn(argv, dir / "stdout.txt", dir / "stderr.txt");
  const auto t0 = std::chrono::steady_clock::now();
  pid_t child = 0;
  while (!((child = first_child(batch)) && both_ready(batch, child)) && !spinmotor_test::has_exited(batch) &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  REQUIRE(child != 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // a few steps in
  REQUIRE(::kill(batch, SIGTERM) == 0);                         // the batch alone, as a scheduler does
  const int code = spinmotor_test::wait_exit_within(batch, 60);
  const std::string err = slurp(dir / "stderr.txt");
  INFO(err << slurp(dir / "stdout.txt"));
  CHECK(code == 143);
  CHECK_THAT(err, Catch::Contains("interrupted by SIGTERM: batch stopped with 0 of 3 outputs written"));
  CHECK_THAT(slurp(dir / "stdout.txt"), Catch::Contains("1 interrupted, 2 not run"));
  CHECK(::kill(child, 0) != 0);  // the command it ran is gone (and reaped by the batch)
  // nothing but the logs in the output folder: no mesh, no temporary
  for (const auto& e : fs::directory_iterator(dir / "out")) CHECK(e.path().filename() == "logs");
}

TEST_CASE("batch --grace: a command still running after the grace period is killed, said so, exit 143",
          "[cli][batch][interrupt]") {
  spinmotor_test::TempDir tmp;
  const fs::path& dir = tmp.path;
  fs::create_directories(dir / "in");
  for (const char* name : {"a.obj", "b.obj"})
    spinmotor::write_mesh(dir / "in" / name, spinmotor::icosphere(3));
  std::vector<std::string> argv = {SPINMOTOR_CLI, "batch",
                                   "-j",          "1",
                                   "--grace",     "0.5",
                                   "--out-dir",   (dir / "out").string(),
                                   "--run",       "flow {in} --willmore 0.01 --steps 1000000 --out {out}"};
  for (const char* name : {"a.obj", "b.obj"}) argv.push_back((dir / "in" / name).string());
  const pid_t batch = spinmotor_test::spawn(argv, dir / "stdout.txt", dir / "stderr.txt");
  const auto t0 = std::chrono::steady_clock::now();
  pid_t child = 0;
  while (!((child = first_child(batch)) && both_ready(batch, child)) && !spinmotor_test::has_exited(batch) &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  REQUIRE(child != 0);
  // A command that does not stop on the signal: stopped (SIGSTOP), it cannot act on SIGTERM. What it
  // had in flight: a temporary of its output, named as AtomicFile names them.
  REQUIRE(::kill(child, SIGSTOP) == 0);
  const fs::path temporary = dir / "out" / (".a.obj." + std::to_string(child) + ".0.1.tmp");
  std::ofstream(temporary) << "v 0 0 0\n";
  const auto signalled = std::chrono::steady_clock::now();
  REQUIRE(::kill(batch, SIGTERM) == 0);
  const int code = spinmotor_test::wait_exit_within(batch, 60);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
  const std::string err = slurp(dir / "stderr.txt"), out = slurp(dir / "stdout.txt");
  INFO(err << out);
  CHECK(code == 143);
  CHECK(waited >= 0.5);  // the grace period first
  CHECK(waited < 2.5);   // then the kill, at once
  CHECK_THAT(out,
             Catch::Contains("0 interrupted, 1 killed (still running 0.5 s after the signal), 1 not run"));
  CHECK_THAT(out, Catch::Contains("killed (exit 137): " + (dir / "in" / "a.obj").string()));
  CHECK_THAT(err, Catch::Contains("interrupted by SIGTERM: batch stopped with 0 of 2 outputs written (1 "
                                  "command killed, still running 0.5 s after the signal)"));
  CHECK(::kill(child, 0) != 0);  // killed and reaped
  for (const auto& e : fs::directory_iterator(dir / "out")) CHECK(e.path().filename() == "logs");
}

}  // namespace test_cli_batch
