#pragma once
// Tests of the real data in ../shared (meshes/, rigs/): on a clone without that folder they are
// reported by CTest as skipped ("skipped: <dir> not found"), never failed, and where it exists (as in
// CI) they all run.
//
//   TEST_CASE("spot: ...") {
//     SPINMOTOR_REQUIRE_MESHES();   // first statement of every test case that reads a real mesh
//     ...
//
// CTest runs one test case per process (catch_discover_tests), so ending the process with
// kSkipExitCode skips exactly that case: every discovered test has SKIP_RETURN_CODE kSkipExitCode
// (tests/CMakeLists.txt), and support/catch_main.cpp maps every Catch failure to exit code 1, so a
// failing test can never be mistaken for a skipped one.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace spinmotor::test {

inline constexpr int kSkipExitCode = 77;

/// Ends the test process with kSkipExitCode, printing "skipped: <why>" (a case that cannot run here).
[[noreturn]] inline void skip(const std::string& why) {
  std::printf("skipped: %s\n", why.c_str());
  std::fflush(stdout);
  std::_Exit(kSkipExitCode);
}

/// True when the shared data folder `dir` exists.
inline bool shared_available(const char* dir) { return std::filesystem::is_directory(dir); }

/// Ends the test process with kSkipExitCode when `dir` is missing.
inline void require_shared(const char* dir) {
  if (shared_available(dir)) return;
  std::printf("skipped: %s not found\n", dir);
  std::fflush(stdout);
  std::_Exit(kSkipExitCode);
}

}  // namespace spinmotor::test

#define SPINMOTOR_REQUIRE_MESHES() ::spinmotor::test::require_shared(SPINMOTOR_MESHES_DIR)
#define SPINMOTOR_REQUIRE_RIGS() ::spinmotor::test::require_shared(SPINMOTOR_RIGS_DIR)
