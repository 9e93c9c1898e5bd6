#pragma once
// The memory budget: work whose memory can be estimated before it starts is refused at once, with the
// estimate and the limit, instead of running for minutes until an allocation fails (issue 19).
//
//   require_memory(estimate_bytes, "harmonic_cage_coordinates: grid 512 (137M nodes)");
//
// The limit is process-wide: the tools' `--max-memory SIZE` sets it; by default it is the memory the
// machine has available when first asked (MemAvailable in /proc/meminfo; unlimited where that cannot
// be read). Estimates are of the dominant allocations (factors, dense blocks, per-node arrays), meant
// to be right within a small factor, not exact: they refuse what cannot fit, not what might be tight.
#include <cstdint>
#include <string>
#include <string_view>

namespace spinmotor {

/// The machine's available memory in bytes (MemAvailable from /proc/meminfo), or 0 if unknown.
[[nodiscard]] std::uint64_t available_memory() noexcept;

/// The current limit in bytes: the one set by set_memory_limit, else available_memory() (read once),
/// else UINT64_MAX.
[[nodiscard]] std::uint64_t memory_limit() noexcept;

/// Sets the limit (bytes > 0), or returns to the default (bytes = 0). Thread-safe.
void set_memory_limit(std::uint64_t bytes) noexcept;

/// Throws Error (BadInput; exit code 2 in the tools) "<what> needs an estimated X GB of memory; the
/// limit is Y GB (--max-memory; default: the available memory)" when estimate > memory_limit().
void require_memory(std::uint64_t estimate, std::string_view what);

/// "512M", "8G", "1.5GB", "2048" (bytes), "16GiB": K/M/G/T are powers of 1024, a trailing B or iB is
/// optional. Throws Error naming `text` for anything else, zero or a negative size.
[[nodiscard]] std::uint64_t parse_memory_size(std::string_view text);

/// A byte count for messages: "812 MB", "3.2 GB" (powers of 1024, 2 significant digits above 10).
[[nodiscard]] std::string format_bytes(std::uint64_t bytes);

/// Saturating size arithmetic for estimates: a·b and a + b, clamped at UINT64_MAX.
[[nodiscard]] constexpr std::uint64_t mul_sat(std::uint64_t a, std::uint64_t b) noexcept {
  return (a != 0 && b > UINT64_MAX / a) ? UINT64_MAX : a * b;
}
[[nodiscard]] constexpr std::uint64_t add_sat(std::uint64_t a, std::uint64_t b) noexcept {
  return b > UINT64_MAX - a ? UINT64_MAX : a + b;
}

}  // namespace spinmotor
