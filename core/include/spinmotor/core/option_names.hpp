#pragma once
// One name table per option enum: the strings that the CLI, scene files, the viewer's widgets, the JSON
// schema and the Python module use for its values, written once, next to the enum.
//
//   enum class Blend { Log, PivotLog, Linear };
//   inline constexpr OptionNames<Blend, 3> kBlendNames{"blend", {{{Blend::Log, "log"}, ...}}};
//   constexpr const auto& option_names(Blend) { return kBlendNames; }  // found by ADL
//
//   parse_option<Blend>("pivot-log")   -> Blend::PivotLog
//   parse_option<Blend>("lgo")         -> Error "unknown blend 'lgo' (one of: log, pivot-log, dlb)"
//   option_name(Blend::DLB)         -> "dlb"
//   option_values<Blend>()             -> {"log", "pivot-log", "dlb"} (the schema's enum)
//
// Defaults are not here: they are the member initialisers of each Options struct.
#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "spinmotor/core/error.hpp"

namespace spinmotor {

template <class E, std::size_t N>
struct OptionNames {
  std::string_view option;  ///< what the values are of, for messages ("blend", "weights")
  std::array<std::pair<E, std::string_view>, N> entries;
};

/// The name of a value (throws Error for a value outside the table: an enum cast from an integer).
template <class E>
[[nodiscard]] std::string_view option_name(E value) {
  const auto& t = option_names(value);
  for (const auto& [v, name] : t.entries)
    if (v == value) return name;
  throw Error(std::string(t.option) + ": value " + std::to_string(static_cast<int>(value)) + " has no name");
}

/// Every name of the table, in table order.
template <class E>
[[nodiscard]] std::vector<std::string> option_values() {
  std::vector<std::string> out;
  for (const auto& e : option_names(E{}).entries) out.emplace_back(e.second);
  return out;
}

/// The value called `name`; throws Error "unknown <option> '<name>' (one of: a, b, c)", prefixed with
/// `where` ("scene.json: /deformer/blend: ") when given.
template <class E>
[[nodiscard]] E parse_option(std::string_view name, std::string_view where = {}) {
  const auto& t = option_names(E{});
  std::string all;
  for (const auto& [v, n] : t.entries) {
    if (n == name) return v;
    all += (all.empty() ? "" : ", ") + std::string(n);
  }
  throw Error(std::string(where) + "unknown " + std::string(t.option) + " '" + std::string(name) +
              "' (one of: " + all + ")");
}

}  // namespace spinmotor
