// The main of the fuzz targets in builds without libFuzzer (every build but SPINMOTOR_FUZZ's): runs the
// target's LLVMFuzzerTestOneInput (renamed spinmotor_fuzz_<name> in these builds, fuzz/CMakeLists.txt)
// once on each file given, and on each file of each directory given (sorted, so the order is stable).
// ctest uses it to replay the seed corpora and the saved crash inputs; a crash or an escaping exception
// aborts, which fails the test. Exit 1 when there is no input at all, so that a wrong path cannot pass
// as an empty run.
//
//   fuzz_<name> [--mutate SECONDS [--seed N] [--keep FILE]] FILE|DIR...
//
// --mutate: for SECONDS, random mutations of the inputs given (1 to 16 stacked edits of one input:
// bit flips, special bytes, inserted, erased and repeated runs, splices with another input), each run
// once; no coverage guidance (that is libFuzzer's, scripts/fuzz), but no extra build either: CI runs
// it in the sanitizer build. Each input is written to --keep (default ./fuzz-mutate-<pid>.bin) before
// it runs, so a crash leaves it on disk; an input running over 10 s ends the process (SIGALRM).
#include "replay_main.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace {

/// The target this process replays (replay_main's argument).
spinmotor::fuzz::Entry one_input = nullptr;

using Bytes = std::vector<std::uint8_t>;

Bytes read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void run(const std::filesystem::path& file) {
  std::printf("running %s\n", file.string().c_str());
  std::fflush(stdout);  // the name of the input is out before a crash
  const Bytes bytes = read_bytes(file);
  one_input(bytes.data(), bytes.size());
}

/// One random edit of `b` (which stays under 64 KiB); `other` is another input, for splices.
void mutate_once(Bytes& b, const Bytes& other, std::mt19937_64& rng) {
  auto pick = [&](std::size_t n) { return n == 0 ? std::size_t{0} : static_cast<std::size_t>(rng() % n); };
  static const std::uint8_t kSpecial[] = {0,   1,   0x7f, 0x80, 0xff, '0', '9', '-',
                                          '.', 'e', ' ',  '\n', '"',  '[', '{'};
  switch (rng() % 6) {
    case 0:  // flip a bit
      if (!b.empty()) b[pick(b.size())] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
      break;
    case 1:  // a special byte
      if (!b.empty()) b[pick(b.size())] = kSpecial[pick(sizeof kSpecial)];
      break;
    case 2: {  // insert random bytes
      const std::size_t at = pick(b.size() + 1), n = 1 + pick(8);
      Bytes r(n);
      for (auto& x : r) x = static_cast<std::uint8_t>(rng());
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), r.begin(), r.end());
      break;
    }
    case 3: {  // erase a run
      if (b.empty()) break;
      const std::size_t at = pick(b.size()), n = 1 + pick(std::min<std::size_t>(b.size() - at, 64));
      b.erase(b.begin() + static_cast<std::ptrdiff_t>(at), b.begin() + static_cast<std::ptrdiff_t>(at + n));
      break;
    }
    case 4: {  // repeat a run
      if (b.empty()) break;
      const std::size_t at = pick(b.size()), n = 1 + pick(std::min<std::size_t>(b.size() - at, 256));
      const Bytes run(b.begin() + static_cast<std::ptrdiff_t>(at),
                      b.begin() + static_cast<std::ptrdiff_t>(at + n));
      b.insert(b.begin() + static_cast<std::ptrdiff_t>(pick(b.size() + 1)), run.begin(), run.end());
      break;
    }
    default: {  // splice: our head, the other input's tail
      const std::size_t at = pick(b.size() + 1), from = pick(other.size() + 1);
      b.resize(at);
      b.insert(b.end(), other.begin() + static_cast<std::ptrdiff_t>(from), other.end());
      break;
    }
  }
  if (b.size() > 65536) b.resize(65536);
}

int mutate(const std::vector<std::filesystem::path>& files, double seconds, std::uint64_t seed,
           const std::filesystem::path& keep) {
  std::vector<Bytes> seeds;
  for (const auto& f : files) seeds.push_back(read_bytes(f));
  std::mt19937_64 rng(seed);
  std::printf("mutating %zu inputs for %g s, seed %llu; the input in progress is kept in %s\n", seeds.size(),
              seconds, static_cast<unsigned long long>(seed), keep.string().c_str());
  std::fflush(stdout);
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  std::size_t runs = 0;
  while (std::chrono::steady_clock::now() < end) {
    Bytes b = seeds[rng() % seeds.size()];
    const int edits = 1 + static_cast<int>(rng() % 16);
    for (int e = 0; e < edits; ++e) mutate_once(b, seeds[rng() % seeds.size()], rng);
    {
      std::ofstream out(keep, std::ios::binary | std::ios::trunc);
      out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    }
    alarm(10);
    one_input(b.data(), b.size());
    alarm(0);
    ++runs;
  }
  std::filesystem::remove(keep);
  std::printf("%zu mutated inputs, no crash (seed %llu)\n", runs, static_cast<unsigned long long>(seed));
  return 0;
}

}  // namespace

int spinmotor::fuzz::replay_main(int argc, char** argv, Entry entry) {
  one_input = entry;
  std::vector<std::filesystem::path> files;
  double mutate_seconds = 0;
  std::uint64_t seed =
      static_cast<std::uint64_t>(std::chrono::system_clock::now().time_since_epoch().count());
  std::filesystem::path keep = "fuzz-mutate-" + std::to_string(::getpid()) + ".bin";
  for (int i = 1; i < argc; ++i) {
    const std::string opt = argv[i];
    if ((opt == "--mutate" || opt == "--seed" || opt == "--keep") && i + 1 < argc) {
      const char* v = argv[++i];
      if (opt == "--mutate")
        mutate_seconds = std::atof(v);
      else if (opt == "--seed")
        seed = std::strtoull(v, nullptr, 10);
      else
        keep = v;
      continue;
    }
    const std::filesystem::path arg = argv[i];
    if (std::filesystem::is_directory(arg)) {
      std::vector<std::filesystem::path> in_dir;
      for (const auto& e : std::filesystem::directory_iterator(arg))
        if (e.is_regular_file()) in_dir.push_back(e.path());
      std::sort(in_dir.begin(), in_dir.end());
      files.insert(files.end(), in_dir.begin(), in_dir.end());
    } else if (std::filesystem::is_regular_file(arg)) {
      files.push_back(arg);
    } else {
      std::fprintf(stderr, "%s: no such file or directory\n", argv[i]);
      return 1;
    }
  }
  if (files.empty()) {
    std::fprintf(stderr, "no input files\n");
    return 1;
  }
  if (mutate_seconds > 0) return mutate(files, mutate_seconds, seed, keep);
  for (const auto& f : files) run(f);
  std::printf("%zu inputs, no crash\n", files.size());
  return 0;
}
