#include "spinmotor/core/memory_budget.hpp"

#include <atomic>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "spinmotor/core/error.hpp"

namespace spinmotor {

namespace {
std::atomic<std::uint64_t> g_limit{0};  // 0: the default
}  // namespace

std::uint64_t available_memory() noexcept {
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  std::uint64_t value = 0;
  while (in >> key >> value) {
    std::getline(in, unit);
    if (key == "MemAvailable:") return mul_sat(value, 1024);  // the file counts kB
  }
  return 0;
}

std::uint64_t memory_limit() noexcept {
  if (const std::uint64_t set = g_limit.load(std::memory_order_relaxed)) return set;
  static const std::uint64_t available = available_memory();  // once: it changes as we allocate
  return available ? available : UINT64_MAX;
}

void set_memory_limit(std::uint64_t bytes) noexcept { g_limit.store(bytes, std::memory_order_relaxed); }

void require_memory(std::uint64_t estimate, std::string_view what) {
  const std::uint64_t limit = memory_limit();
  if (estimate <= limit) return;
  std::ostringstream s;
  s << what << " needs an estimated " << format_bytes(estimate) << " of memory; the limit is "
    << format_bytes(limit)
    << (g_limit.load(std::memory_order_relaxed)
            ? " (set by --max-memory or set_memory_limit)"
            : " (the available memory; --max-memory or set_memory_limit sets it)");
  throw Error(s.str());
}

std::uint64_t parse_memory_size(std::string_view text) {
  auto bad = [&] {
    return Error("memory size '" + std::string(text) +
                 "': expected a positive number with an optional unit K, M, G or T (powers of 1024), "
                 "e.g. 512M or 8G");
  };
  double value = 0;
  const char* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || !(value > 0) || !std::isfinite(value)) throw bad();
  std::string unit(p, end);
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (unit.ends_with("IB"))
    unit.resize(unit.size() - 2);
  else if (unit.size() > 1 && unit.ends_with("B"))
    unit.pop_back();
  else if (unit == "B")
    unit.clear();
  double scale = 1;
  if (unit == "K")
    scale = 0x1p10;
  else if (unit == "M")
    scale = 0x1p20;
  else if (unit == "G")
    scale = 0x1p30;
  else if (unit == "T")
    scale = 0x1p40;
  else if (!unit.empty())
    throw bad();
  const double bytes = value * scale;
  if (bytes < 1 || bytes >= 0x1p64) throw bad();
  return static_cast<std::uint64_t>(bytes);
}

std::string format_bytes(std::uint64_t bytes) {
  if (bytes == UINT64_MAX) return "unlimited";
  const char* units[] = {"bytes", "KB", "MB", "GB", "TB", "PB", "EB"};
  double v = static_cast<double>(bytes);
  int u = 0;
  while (v >= 1024 && u < 6) v /= 1024, ++u;
  char buf[32];
  std::snprintf(buf, sizeof buf, u == 0 || v >= 10 ? "%.0f %s" : "%.1f %s", v, units[u]);
  return buf;
}

}  // namespace spinmotor
