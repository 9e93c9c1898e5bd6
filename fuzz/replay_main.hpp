#pragma once
// The replay main of the fuzz targets (replay_main.cpp), for builds without libFuzzer.
#include <cstddef>
#include <cstdint>

namespace spinmotor::fuzz {

/// A target's entry point: LLVMFuzzerTestOneInput's signature.
using Entry = int (*)(const std::uint8_t* data, std::size_t size);

/// Runs `entry` on the inputs named on the command line, or mutates them (--mutate); replay_main.cpp
/// documents the arguments. Returns the process's exit code.
int replay_main(int argc, char** argv, Entry entry);

}  // namespace spinmotor::fuzz
