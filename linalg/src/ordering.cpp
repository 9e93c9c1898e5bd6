#include "spinmotor/linalg/ordering.hpp"

#include <algorithm>

#include "spinmotor/core/error.hpp"

namespace spinmotor {

namespace {

// "a, b, c": the names of `supported`, for the messages below.
std::string joined_names(std::span<const Ordering> supported) {
  std::string all;
  for (Ordering o : supported) all += (all.empty() ? "" : ", ") + std::string(option_name(o));
  return all;
}

}  // namespace

void require_ordering(Ordering ordering, std::span<const Ordering> supported, std::string_view who) {
  if (std::find(supported.begin(), supported.end(), ordering) != supported.end()) return;
  throw Error(std::string(who) + ": ordering '" + std::string(option_name(ordering)) +
              "' is not supported here (one of: " + joined_names(supported) + ")");
}

Ordering parse_ordering(std::string_view name, std::span<const Ordering> supported, std::string_view who) {
  for (Ordering o : supported)
    if (option_name(o) == name) return o;
  throw Error(std::string(who) + ": unknown ordering '" + std::string(name) +
              "' (one of: " + joined_names(supported) + ")");
}

std::vector<std::string> ordering_values(std::span<const Ordering> supported) {
  std::vector<std::string> out;
  for (Ordering o : supported) out.emplace_back(option_name(o));
  return out;
}

}  // namespace spinmotor
