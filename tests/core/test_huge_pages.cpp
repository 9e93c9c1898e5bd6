// Huge-page advice for large buffers (core/huge_pages.hpp): the allocation contracts (calloc's zeros
// and overflow, realloc keeping the contents), and, where the kernel's transparent huge pages are in
// "madvise" mode, that an advised buffer really is backed by huge pages once written.
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "shared_data.hpp"
#include "spinmotor/core/huge_pages.hpp"

namespace test_huge_pages {

using namespace spinmotor;

namespace {

/// The kernel's THP mode: "always", "madvise", "never", or "" where it cannot be read.
std::string thp_mode() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  std::getline(in, line);
  const auto a = line.find('['), b = line.find(']');
  return a == std::string::npos || b == std::string::npos ? std::string() : line.substr(a + 1, b - a - 1);
}

/// AnonHugePages (kB) of the mapping of /proc/self/smaps that contains p, or -1 if not found.
long anon_huge_kb(const void* p) {
  const auto addr = reinterpret_cast<std::uintptr_t>(p);
  std::ifstream in("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream s(line);
    if (s >> std::hex >> lo >> dash >> hi && dash == '-') {
      inside = lo <= addr && addr < hi;
      continue;
    }
    if (inside && line.rfind("AnonHugePages:", 0) == 0) return std::stol(line.substr(14));
  }
  return -1;
}

}  // namespace

TEST_CASE("huge pages: calloc_huge zeroes, refuses an overflowing size, realloc_huge keeps the contents",
          "[memory]") {
  for (const std::size_t bytes : {std::size_t{100}, kHugePageAdviceBytes + 12345}) {
    INFO(bytes);
    // Dirty a block of that size first, so that a reused one would show stale bytes.
    auto* dirty = static_cast<unsigned char*>(std::malloc(bytes));
    REQUIRE(dirty);
    std::memset(dirty, 0xAB, bytes);
    std::free(dirty);
    auto* p = static_cast<unsigned char*>(calloc_huge(bytes, 1));
    REQUIRE(p);
    std::size_t nonzero = 0;
    for (std::size_t i = 0; i < bytes; ++i) nonzero += p[i] != 0;
    CHECK(nonzero == 0);
    std::memset(p, 7, bytes);
    p = static_cast<unsigned char*>(realloc_huge(p, 2 * bytes));
    REQUIRE(p);
    CHECK(p[0] == 7);
    CHECK(p[bytes - 1] == 7);
    std::free(p);
  }
  CHECK(calloc_huge(SIZE_MAX / 2, 4) == nullptr);
  void* none = calloc_huge(0, 16);  // glibc's calloc for zero bytes: a unique pointer to free
  CHECK(none != nullptr);
  std::free(none);
  // Null and small ranges are ignored.
  advise_huge_pages(nullptr, kHugePageAdviceBytes);
  char small[64];
  advise_huge_pages(small, sizeof small);
}

TEST_CASE("huge pages: an advised 16 MiB buffer is backed by huge pages where THP is in madvise mode",
          "[memory]") {
#if defined(__SANITIZE_ADDRESS__)
  spinmotor::test::skip("ASan's allocator maps its own regions");
#endif
  const std::string mode = thp_mode();
  if (mode != "madvise") spinmotor::test::skip("transparent huge pages are '" + mode + "', not 'madvise'");
  constexpr std::size_t bytes = std::size_t{16} << 20;
  auto* p = static_cast<unsigned char*>(malloc_huge(bytes));
  REQUIRE(p);
  std::memset(p, 1, bytes);
  const long kb = anon_huge_kb(p + bytes / 2);
  INFO("AnonHugePages of the buffer's mapping: " << kb << " kB");
  // At least the whole 2 MiB pages inside the buffer, less what the kernel could not find at once.
  CHECK(kb >= 8 * 1024);
  std::free(p);
}

}  // namespace test_huge_pages
