#pragma once
// Transparent huge pages for large buffers.
//
// The first write to each 4 KiB page of a fresh allocation is a page fault, and on the virtual machines
// this project runs on a fault is expensive (perf: about a tenth of the samples of the 80k-vertex
// harmonic bind were in the fault path, most under CHOLMOD zeroing a new factor). Where the kernel's
// transparent huge pages are in "madvise" mode (/sys/kernel/mm/transparent_hugepage/enabled), a range
// marked MADV_HUGEPAGE before it is touched faults in 2 MiB pages instead: 512 times fewer faults.
// With THP "always" the advice is redundant, with "never" (or off Linux) it does nothing; the memory
// stays ordinary malloc memory either way, freed with std::free. docs/performance.md ("Page faults,
// CHOLMOD's OpenMP regions and OpenBLAS's idle workers") has the measurements.
#include <cstddef>

namespace spinmotor {

/// Buffers from this size on are advised (smaller ones would not contain a whole aligned huge page,
/// and advising many small ranges would split the heap's mapping into many).
inline constexpr std::size_t kHugePageAdviceBytes = std::size_t{2} << 20;

/// Marks the whole 2 MiB-aligned huge pages inside [p, p + bytes) MADV_HUGEPAGE, when bytes ≥
/// kHugePageAdviceBytes. Call it on a buffer before its pages are first written. Never fails: the
/// advice is a hint (an error from madvise is ignored).
void advise_huge_pages(void* p, std::size_t bytes) noexcept;

/// std::malloc, then advise_huge_pages. Free the result with std::free.
[[nodiscard]] void* malloc_huge(std::size_t bytes) noexcept;
/// std::calloc, then advise_huge_pages (calloc touches only reused, already resident memory).
[[nodiscard]] void* calloc_huge(std::size_t count, std::size_t size) noexcept;
/// std::realloc, then advise_huge_pages on the result (its tail is not yet touched).
[[nodiscard]] void* realloc_huge(void* p, std::size_t bytes) noexcept;

}  // namespace spinmotor
