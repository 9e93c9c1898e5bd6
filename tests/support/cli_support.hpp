#pragma once
// Shared by the CLI tests: run the built `spinmotor` (SPINMOTOR_CLI) with stdout captured and stderr
// read back from a file, and a per-process scratch directory removed at the end of the test case.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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
