// fuzz_obj: read_obj (mesh/io.hpp) on Wavefront OBJ (v, vt, f with every index form), then the mesh checks of
// fuzz_support.hpp (io.hpp's promises and validate()).
#include "fuzz_support.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = spinmotor::fuzz::write_input(data, size, "input.obj");
  spinmotor::Mesh mesh;
  try {
    mesh = spinmotor::read_obj(path);
  } catch (const spinmotor::Error& e) {
    return spinmotor::fuzz::refused(e);  // the expected way out
  }
  spinmotor::fuzz::check_mesh(mesh);
  return 0;
}
