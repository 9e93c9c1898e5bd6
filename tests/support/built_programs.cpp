// support/built_programs.hpp: a program of the compiling build tree, in the running one.
#include "built_programs.hpp"

#include <filesystem>
#include <list>
#include <mutex>
#include <string>

namespace spinmotor_test {

const char* in_running_build(const char* built, const char* exe_dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path running = fs::read_symlink("/proc/self/exe", ec).parent_path();
  if (ec || running == fs::path(exe_dir)) return built;
  static std::mutex mutex;
  static std::list<std::string> kept;  // stable addresses for the returned strings
  const std::string mapped =
      (running / fs::path(built).lexically_relative(exe_dir)).lexically_normal().string();
  const std::lock_guard lock(mutex);
  for (const std::string& s : kept) {
    if (s == mapped) return s.c_str();
  }
  return kept.emplace_back(mapped).c_str();
}

}  // namespace spinmotor_test
