// The programs the tests run (the CLI, the viewer), found in the build tree of the running test
// executable. Force-included into every test file (tests/CMakeLists.txt), so a test writes
// SPINMOTOR_CLI / SPINMOTOR_VIEWER (a `std::string`) and `#ifdef SPINMOTOR_VIEWER` as before.
//
// Why not the path CMake knows: CI's sanitizer build links the test objects compiled by README's Release
// build (SPINMOTOR_TEST_OBJECTS_FROM), whose path names the Release CLI; the sanitizer run must start the
// sanitized one. A program path of the build tree the object was compiled in is therefore taken relative
// to that tree's test-executable folder (SPINMOTOR_TEST_EXE_DIR) and resolved against the folder of
// /proc/self/exe; when the two folders are the same (the usual case) the path is returned as it is.
#pragma once
#include <string>

namespace spinmotor_test {

/// `built`, a path of the compiling build tree whose test executables go to `exe_dir`, in the running
/// executable's build tree.
[[nodiscard]] std::string in_running_build(const char* built, const char* exe_dir);

}  // namespace spinmotor_test

#ifdef SPINMOTOR_CLI_BUILT
#define SPINMOTOR_CLI ::spinmotor_test::in_running_build(SPINMOTOR_CLI_BUILT, SPINMOTOR_TEST_EXE_DIR)
#endif
#ifdef SPINMOTOR_VIEWER_BUILT
#define SPINMOTOR_VIEWER ::spinmotor_test::in_running_build(SPINMOTOR_VIEWER_BUILT, SPINMOTOR_TEST_EXE_DIR)
#endif
