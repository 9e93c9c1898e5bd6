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
//
// What huge pages leave (the parts of a buffer outside whole aligned 2 MiB pages, buffers below
// 2 MiB, kernels without THP) is faulted in by populate_pages with one system call per buffer
// (MADV_POPULATE_WRITE, Linux ≥ 5.14) instead of one trap per page: on this project's VMs a trap costs
// tens of times the zeroing of its page. The 80k-vertex harmonic bind took 90k faults for 15 binds
// and ~40 % of its time in them (docs/performance.md, "Harmonic bind: page faults").
#include <cstddef>

namespace spinmotor {

/// Buffers from this size on are advised (smaller ones would not contain a whole aligned huge page,
/// and advising many small ranges would split the heap's mapping into many).
inline constexpr std::size_t kHugePageAdviceBytes = std::size_t{2} << 20;

/// Marks the whole 2 MiB-aligned huge pages inside [p, p + bytes) MADV_HUGEPAGE, when bytes ≥
/// kHugePageAdviceBytes. Call it on a buffer before its pages are first written. Never fails: the
/// advice is a hint (an error from madvise is ignored).
void advise_huge_pages(void* p, std::size_t bytes) noexcept;

/// Buffers from this size on are populated (smaller ones mostly come from the heap's resident part).
inline constexpr std::size_t kPopulateBytes = std::size_t{256} << 10;

/// Faults in, writable, every whole 4 KiB page inside [p, p + bytes) in one madvise call, when bytes ≥
/// kPopulateBytes. Contents are unchanged (a fresh mapping's pages read as zero). For a buffer that
/// is about to be written whole. Never fails: on an older kernel, or when memory runs short, the
/// pages fault one by one later as they would have.
void populate_pages(void* p, std::size_t bytes) noexcept;

/// advise_huge_pages, then populate_pages: for a fresh buffer that will be written whole.
void prepare_fresh(void* p, std::size_t bytes) noexcept;

/// std::malloc, then prepare_fresh. Free the result with std::free.
[[nodiscard]] void* malloc_huge(std::size_t bytes) noexcept;
/// std::calloc, then prepare_fresh (calloc touches only reused, already resident memory; the
/// populated pages of a fresh mapping are zero).
[[nodiscard]] void* calloc_huge(std::size_t count, std::size_t size) noexcept;
/// std::realloc, then advise_huge_pages on the result (its tail is not yet touched).
[[nodiscard]] void* realloc_huge(void* p, std::size_t bytes) noexcept;

}  // namespace spinmotor
