#include "spinmotor/core/huge_pages.hpp"

#include <cstdint>
#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace spinmotor {

namespace {
constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;
}  // namespace

void advise_huge_pages(void* p, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (p == nullptr || bytes < kHugePageAdviceBytes) return;
  const auto begin = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHugePage - 1);
  if (last > first) (void)madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

void* malloc_huge(std::size_t bytes) noexcept {
  void* p = std::malloc(bytes);
  advise_huge_pages(p, bytes);
  return p;
}

void* calloc_huge(std::size_t count, std::size_t size) noexcept {
  // calloc leaves a fresh mapping untouched (its pages are zero) and zeroes only reused memory, whose
  // pages are already resident: advised afterwards, the untouched pages still fault as huge pages.
  if (size != 0 && count > SIZE_MAX / size) return nullptr;  // (ASan's calloc aborts on it)
  void* p = std::calloc(count, size);
  if (p) advise_huge_pages(p, count * size);
  return p;
}

void* realloc_huge(void* p, std::size_t bytes) noexcept {
  void* q = std::realloc(p, bytes);
  advise_huge_pages(q, bytes);
  return q;
}

}  // namespace spinmotor
