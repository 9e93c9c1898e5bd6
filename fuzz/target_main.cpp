// The main of one replay program, fuzz_<name> (fuzz/CMakeLists.txt defines SPINMOTOR_FUZZ_ENTRY as
// spinmotor_fuzz_<name>, the target's LLVMFuzzerTestOneInput renamed in replay_targets.cpp).
#include <cstddef>
#include <cstdint>

#include "replay_main.hpp"

extern "C" int SPINMOTOR_FUZZ_ENTRY(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) { return spinmotor::fuzz::replay_main(argc, argv, &SPINMOTOR_FUZZ_ENTRY); }
