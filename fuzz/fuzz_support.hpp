#pragma once
// What the fuzz targets share (fuzz/README.md): the input bytes as a file, since every reader takes a
// path, and the checks a successful read must pass.
//
// The contract of every target: spinmotor::Error is how a reader refuses input, so the targets catch it
// and return 0. Any other exception (std::bad_alloc, nlohmann::json's, std::out_of_range, ...) escapes
// LLVMFuzzerTestOneInput and aborts, and so does a broken invariant below: libFuzzer reports both.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/mesh/validate.hpp"

namespace spinmotor::fuzz {

/// This process's scratch directory, /tmp/spinmotor-fuzz-<pid>: created on first use, removed at exit.
/// (Held by a pointer that is never freed, so that the exit handler runs before nothing is destroyed.)
inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path* dir = [] {
    auto* d = new std::filesystem::path(std::filesystem::temp_directory_path() /
                                        ("spinmotor-fuzz-" + std::to_string(::getpid())));
    std::filesystem::create_directories(*d);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(scratch_dir(), ec);
    });
    return d;
  }();
  return *dir;
}

/// Writes `size` bytes to scratch_dir()/name (replacing the previous input) and returns its path.
inline std::filesystem::path write_input(const std::uint8_t* data, std::size_t size,
                                         const std::string& name) {
  const std::filesystem::path path = scratch_dir() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!out.flush()) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.string().c_str());
    std::abort();
  }
  return path;
}

/// Called with every refusal: returns 0, and prints the message when SPINMOTOR_FUZZ_VERBOSE is set (to
/// see how far a seed gets: `SPINMOTOR_FUZZ_VERBOSE=1 build/fuzz/fuzz_scene fuzz/corpus/fuzz_scene`).
inline int refused(const std::exception& e) {
  static const bool verbose = std::getenv("SPINMOTOR_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "refused: %s\n", e.what());
  return 0;
}

/// Aborts (a finding) when `ok` is false: a reader returned something its contract rules out.
inline void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "fuzz: broken invariant: %s\n", what);
    std::abort();
  }
}

/// A closed tetrahedron (4 vertices, 4 outward faces): the fixture mesh of the scene and weight targets.
inline Mesh tetrahedron() {
  Mesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.F.resize(4, 3);
  m.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  return m;
}

/// What io.hpp promises of a mesh it returns: 3 columns, at least one face, and UV/FUV either absent or
/// one index per corner into UV. Then validate() (O(m log m), cheap at fuzz sizes), which throws Error
/// only for a malformed mesh: called outside any catch, so such an Error is a finding too.
inline void check_mesh(const Mesh& mesh) {
  check(mesh.V.cols() == 3 && mesh.F.cols() == 3, "V and F have 3 columns");
  check(mesh.F.rows() > 0, "a mesh read from a file has a face");
  check(mesh.FUV.size() == 0 || (mesh.FUV.rows() == mesh.F.rows() && mesh.FUV.cols() == 3),
        "FUV is empty or m x 3");
  check(mesh.UV.size() == 0 || mesh.UV.cols() == 2, "UV is t x 2");
  if (mesh.FUV.size() > 0)
    check(mesh.FUV.minCoeff() >= 0 && mesh.FUV.maxCoeff() < mesh.UV.rows(), "FUV indexes UV");
  const MeshReport report = validate(mesh);
  (void)report.defects_summary();
}

/// The body of the four mesh-format targets: the input as a file named `name`, read by `read`
/// (read_obj, read_off, ...), refused with an Error or checked with check_mesh.
inline int fuzz_mesh_reader(const std::uint8_t* data, std::size_t size, const char* name,
                            Mesh (*read)(const std::filesystem::path&)) {
  const std::filesystem::path path = write_input(data, size, name);
  Mesh mesh;
  try {
    mesh = read(path);
  } catch (const Error& e) {
    return refused(e);  // the expected way out
  }
  check_mesh(mesh);
  return 0;
}

}  // namespace spinmotor::fuzz
