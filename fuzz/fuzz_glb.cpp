// fuzz_glb: read_gltf and read_gltf_morph_animation (mesh/gltf.hpp) on binary glTF (.glb: header, JSON chunk,
// BIN chunk); see gltf_target.hpp.
#include "gltf_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return spinmotor::fuzz::fuzz_gltf_input(data, size, "input.glb");
}
