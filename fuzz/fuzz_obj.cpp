// fuzz_obj: read_obj (mesh/io.hpp) on Wavefront OBJ (v, vt, f with every index form), then the mesh checks of
// fuzz_support.hpp (io.hpp's promises and validate()).
#include "fuzz_support.hpp"
#include "spinmotor/mesh/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return spinmotor::fuzz::fuzz_mesh_reader(data, size, "input.obj", &spinmotor::read_obj);
}
