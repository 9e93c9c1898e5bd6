// The memory budget (core/memory_budget.hpp): sizes parsed and printed, the limit set and reset, and
// refusals that name the work, the estimate and the limit.
#include <catch2/catch.hpp>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/memory_budget.hpp"

namespace test_memory_budget {

using namespace spinmotor;

namespace {
/// Restores the default limit when a test case ends, whatever happened.
struct LimitGuard {
  ~LimitGuard() { set_memory_limit(0); }
};
std::string message_of(std::uint64_t estimate, const char* what) {
  try {
    require_memory(estimate, what);
  } catch (const Error& e) {
    CHECK(e.kind() == Error::Kind::BadInput);
    return e.what();
  }
  return {};
}
}  // namespace

TEST_CASE("memory sizes: units are powers of 1024, B / iB optional, anything else refused", "[memory]") {
  CHECK(parse_memory_size("2048") == 2048);
  CHECK(parse_memory_size("1K") == 1024);
  CHECK(parse_memory_size("512M") == 512ull << 20);
  CHECK(parse_memory_size("8G") == 8ull << 30);
  CHECK(parse_memory_size("8GB") == 8ull << 30);
  CHECK(parse_memory_size("8GiB") == 8ull << 30);
  CHECK(parse_memory_size("1.5g") == 3ull << 29);
  CHECK(parse_memory_size("2T") == 2ull << 40);
  for (const char* bad : {"", "G", "-1G", "0", "0.1", "8X", "8 G", "1e30T", "nan", "inf"}) {
    INFO(bad);
    CHECK_THROWS_AS(parse_memory_size(bad), Error);
  }
  CHECK(format_bytes(512) == "512 bytes");
  CHECK(format_bytes(1536) == "1.5 KB");
  CHECK(format_bytes(812ull << 20) == "812 MB");
  CHECK(format_bytes((32ull << 30) + (1ull << 29)) == "32 GB");
  CHECK(format_bytes(UINT64_MAX) == "unlimited");
  CHECK(mul_sat(1ull << 40, 1ull << 40) == UINT64_MAX);
  CHECK(add_sat(UINT64_MAX - 1, 5) == UINT64_MAX);
  CHECK(mul_sat(0, UINT64_MAX) == 0);
}

TEST_CASE("memory limit: the available memory by default, set and reset, refusals name both figures",
          "[memory]") {
  LimitGuard guard;
  const std::uint64_t avail = available_memory();
  // /proc/meminfo exists on every machine this runs on (Linux); the default is what it says.
  REQUIRE(avail > 0);
  CHECK(memory_limit() > 0);
  set_memory_limit(100ull << 20);
  CHECK(memory_limit() == 100ull << 20);
  CHECK_NOTHROW(require_memory(100ull << 20, "exactly the limit"));
  const std::string m = message_of(300ull << 20, "the big thing");
  CHECK(m ==
        "the big thing needs an estimated 300 MB of memory; the limit is 100 MB (set by --max-memory or "
        "set_memory_limit)");
  set_memory_limit(0);
  CHECK(memory_limit() != 100ull << 20);
  const std::string d = message_of(UINT64_MAX - 1, "everything");
  CHECK(d.find("everything needs an estimated") == 0);
  CHECK(d.find("(the available memory; --max-memory or set_memory_limit sets it)") != std::string::npos);
}

}  // namespace test_memory_budget
