// fuzz_off: read_off (mesh/io.hpp) on OFF (the OFF/COFF/NOFF/... headers), then the mesh checks of
// fuzz_support.hpp (io.hpp's promises and validate()).
#include "fuzz_support.hpp"
#include "spinmotor/mesh/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return spinmotor::fuzz::fuzz_mesh_reader(data, size, "input.off", &spinmotor::read_off);
}
