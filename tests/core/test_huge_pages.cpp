// Huge-page advice for large buffers (core/huge_pages.hpp): the allocation contracts (calloc's zeros
// and overflow, realloc keeping the contents), and, where the kernel's transparent huge pages are in
// "madvise" mode, that an advised buffer really is backed by huge pages once written; populate_pages
// faulting a buffer in ahead of its writes.
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/utsname.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdio>
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

/// Minor page faults of this process so far.
long minor_faults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

/// Whether the running kernel is at least major.minor (uname), e.g. for an madvise advice.
bool kernel_at_least(int major, int minor) {
  utsname u{};
  if (uname(&u) != 0) return false;
  int a = 0, b = 0;
  if (std::sscanf(u.release, "%d.%d", &a, &b) != 2) return false;
  return a > major || (a == major && b >= minor);
}

/// Minor faults taken while writing one byte of every 4 KiB page of a fresh 1 MiB anonymous mapping,
/// after `prepare(p, bytes)`; the rest of each page is then checked to be zero. (The reads come after
/// the writes: a read of an untouched page takes the fault itself.)
template <class Prepare>
long faults_writing_fresh_mapping(Prepare&& prepare) {
  constexpr std::size_t bytes = std::size_t{1} << 20;  // no whole 2 MiB page: 4 KiB pages only
  void* m = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  REQUIRE(m != MAP_FAILED);
  auto* p = static_cast<unsigned char*>(m);
  prepare(p, bytes);
  const long before = minor_faults();
  for (std::size_t k = 0; k < bytes; k += 4096) p[k] = 1;
  const long taken = minor_faults() - before;
  bool zero = true;
  for (std::size_t k = 0; k < bytes; k += 4096) zero = zero && p[k + 1] == 0 && p[k + 4095] == 0;
  CHECK(zero);
  munmap(m, bytes);
  return taken;
}

}  // namespace

TEST_CASE("huge pages: populate_pages faults a fresh buffer in ahead of its writes", "[memory]") {
  if (!kernel_at_least(5, 14)) spinmotor::test::skip("MADV_POPULATE_WRITE needs Linux 5.14");
  // Without it every page faults on its first write; populated, the writes find their pages.
  const long plain = faults_writing_fresh_mapping([](void*, std::size_t) {});
  const long populated = faults_writing_fresh_mapping([](void* p, std::size_t n) { populate_pages(p, n); });
  INFO("faults writing 256 pages: plain " << plain << ", populated " << populated);
  CHECK(plain >= 200);
  CHECK(populated <= 8);
  // Below kPopulateBytes nothing is done: the small-buffer case keeps its faults.
  const long small =
      faults_writing_fresh_mapping([](void* p, std::size_t) { populate_pages(p, kPopulateBytes - 1); });
  CHECK(small >= 200);
}

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
