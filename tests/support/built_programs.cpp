// support/built_programs.hpp: a program of the compiling build tree, in the running one.
#include "built_programs.hpp"

#include <filesystem>

namespace spinmotor_test {

std::string in_running_build(const char* built, const char* exe_dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path running = fs::read_symlink("/proc/self/exe", ec).parent_path();
  if (ec || running == fs::path(exe_dir)) return built;
  return (running / fs::path(built).lexically_relative(exe_dir)).lexically_normal().string();
}

}  // namespace spinmotor_test
