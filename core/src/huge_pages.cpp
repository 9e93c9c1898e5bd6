#include "spinmotor/core/huge_pages.hpp"

#include <cstdint>
#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace spinmotor {

namespace {
constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;
constexpr std::uintptr_t kPage = 4096;  // the smallest page: a populated range is rounded inwards to it

/// madvise(advice) on the whole `align`-sized pages inside [p, p + bytes), if any. An error is ignored:
/// every advice here is a hint (EINVAL for MADV_POPULATE_WRITE before Linux 5.14; ENOMEM or EFAULT
/// when memory runs out, the pages then fault one by one and an out-of-memory shows where they are
/// written).
void advise_inside([[maybe_unused]] void* p, [[maybe_unused]] std::size_t bytes,
                   [[maybe_unused]] std::uintptr_t align, [[maybe_unused]] int advice) noexcept {
#if defined(__linux__)
  const auto begin = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = (begin + align - 1) & ~(align - 1);
  const std::uintptr_t last = (begin + bytes) & ~(align - 1);
  if (last > first) (void)madvise(reinterpret_cast<void*>(first), last - first, advice);
#endif
}
}  // namespace

void advise_huge_pages(void* p, std::size_t bytes) noexcept {
#if defined(MADV_HUGEPAGE)
  if (p != nullptr && bytes >= kHugePageAdviceBytes) advise_inside(p, bytes, kHugePage, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

void populate_pages(void* p, std::size_t bytes) noexcept {
#if defined(MADV_POPULATE_WRITE)
  if (p != nullptr && bytes >= kPopulateBytes) advise_inside(p, bytes, kPage, MADV_POPULATE_WRITE);
#else
  (void)p;
  (void)bytes;
#endif
}

void prepare_fresh(void* p, std::size_t bytes) noexcept {
  advise_huge_pages(p, bytes);
  populate_pages(p, bytes);
}

void* malloc_huge(std::size_t bytes) noexcept {
  void* p = std::malloc(bytes);
  prepare_fresh(p, bytes);
  return p;
}

void* calloc_huge(std::size_t count, std::size_t size) noexcept {
  // calloc leaves a fresh mapping untouched (its pages are zero) and zeroes only reused memory, whose
  // pages are already resident: advised afterwards, the untouched pages still fault as huge pages.
  if (size != 0 && count > SIZE_MAX / size) return nullptr;  // (ASan's calloc aborts on it)
  void* p = std::calloc(count, size);
  if (p) prepare_fresh(p, count * size);  // populated pages of a fresh mapping read as zero
  return p;
}

void* realloc_huge(void* p, std::size_t bytes) noexcept {
  void* q = std::realloc(p, bytes);
  advise_huge_pages(q, bytes);
  return q;
}

}  // namespace spinmotor
