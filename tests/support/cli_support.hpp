#pragma once
// Shared by the CLI tests: run the built `spinmotor` (SPINMOTOR_CLI) with stdout captured and stderr
// read back from a file, start a tool in the background (to signal it), and a per-process scratch
// directory removed at the end of the test case.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace spinmotor_test {

/// 's' in single quotes for the shell. (Built by appending: GCC 12's -Wrestrict reports a false
/// positive, GCC bug 105329, for "'" + std::string&&.)
inline std::string quoted(const std::string& s) {
  std::string q;
  q.reserve(s.size() + 2);
  q += '\'';
  q += s;
  q += '\'';
  return q;
}

struct Run {
  int code;
  std::string out, err;
};

/// Runs `spinmotor ARGS` (ARGS already shell-quoted); stderr goes to DIR/stderr.txt.
inline Run run_cli(const std::filesystem::path& dir, const std::string& args) {
  const std::filesystem::path err_file = dir / "stderr.txt";
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

/// Starts `argv` (argv[0]: the program's path) in the background with stdout and stderr written to
/// files, and without DISPLAY (the viewer then renders offscreen); returns its pid. posix_spawn, not a
/// shell: the pid is the tool's own, so a test can signal it.
inline pid_t spawn(const std::vector<std::string>& argv, const std::filesystem::path& out,
                   const std::filesystem::path& err) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::vector<char*> env;
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind("DISPLAY=", 0) != 0) env.push_back(*e);
  env.push_back(nullptr);
  posix_spawn_file_actions_t io;
  posix_spawn_file_actions_init(&io);
  posix_spawn_file_actions_addopen(&io, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&io, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, args[0], &io, nullptr, args.data(), env.data());
  posix_spawn_file_actions_destroy(&io);
  REQUIRE(rc == 0);
  return pid;
}

/// Waits for `pid`: its exit code, or −signal if a signal killed it.
inline int wait_exit(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1000;
  return WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? -WTERMSIG(status) : -1000;
}

/// True once `pid` has exited (without reaping it: wait_exit still gives its status).
inline bool has_exited(pid_t pid) {
  siginfo_t info{};
  return waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == pid;
}

/// wait_exit, for at most `seconds`: a process still running then is killed (SIGKILL) and reaped, and
/// the result is −1001, so that a hang fails the test instead of outliving it (ctest's TIMEOUT ends
/// the test, not the programs it started).
inline int wait_exit_within(pid_t pid, double seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  while (!has_exited(pid) &&
         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < seconds)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  if (has_exited(pid)) return wait_exit(pid);
  kill(pid, SIGKILL);
  wait_exit(pid);
  return -1001;
}

/// Whether signal `sig` is in the mask `field` ("SigCgt:" caught, "SigBlk:" blocked by the main thread)
/// of /proc/PID/status. A spinmotor program is ready to stop cleanly once its main thread blocks the
/// stop signals (take_stop_signals: its signal thread takes them); its InterruptGuard shows in SigCgt.
inline bool signal_mask_has(pid_t pid, const char* field, int sig) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  const std::string key = field;
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key, 0) == 0) return (std::stoull(line.substr(key.size()), nullptr, 16) >> (sig - 1)) & 1;
  return false;
}

/// A scratch directory named after the process (ctest runs every test case in its own process).
struct TempDir {
  std::filesystem::path path;
  TempDir()
      : path(std::filesystem::temp_directory_path() / ("spinmotor_cli_test_" + std::to_string(getpid()))) {
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  /// 'PATH/name', quoted for the shell.
  std::string file(const std::string& name) const { return quoted((path / name).string()); }
};

}  // namespace spinmotor_test
