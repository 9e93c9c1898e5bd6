// fuzz_gltf: read_gltf and read_gltf_morph_animation (mesh/gltf.hpp) on glTF JSON (.gltf; buffers as data:
// URIs); see gltf_target.hpp.
#include "gltf_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return spinmotor::fuzz::fuzz_gltf_input(data, size, "input.gltf");
}
