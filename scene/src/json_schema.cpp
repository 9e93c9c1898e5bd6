#include "spinmotor/scene/json_schema.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <sstream>
#include <tuple>

#include "spinmotor/core/error.hpp"

namespace spinmotor::scene {

using nlohmann::json;

std::string pointer_token(std::string_view key) {
  std::string t;
  for (char c : key) {
    if (c == '~')
      t += "~0";
    else if (c == '/')
      t += "~1";
    else
      t += c;
  }
  return t;
}

/// An error plus what the oneOf ranking needs to know about it.
struct JsonSchema::Issue {
  enum class Kind { Type, Constant, Key, Value };
  std::string path, message;
  Kind kind;
  std::string expected = {};  ///< Constant: the allowed value(s), for merging oneOf alternatives
};

namespace {

const std::set<std::string>& supported_keywords() {
  static const std::set<std::string> k = {"type",
                                          "const",
                                          "enum",
                                          "properties",
                                          "required",
                                          "additionalProperties",
                                          "items",
                                          "minItems",
                                          "maxItems",
                                          "minimum",
                                          "maximum",
                                          "exclusiveMinimum",
                                          "exclusiveMaximum",
                                          "minLength",
                                          "oneOf",
                                          "anyOf",
                                          "$ref",
                                          "definitions",
                                          "$defs",
                                          "$schema",
                                          "$id",
                                          "title",
                                          "description",
                                          "default",
                                          "$comment"};
  return k;
}

int depth(const std::string& pointer) {
  return static_cast<int>(std::count(pointer.begin(), pointer.end(), '/'));
}

std::string type_name(const json& x) {
  switch (x.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::boolean:
      return "a boolean";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
      return "an integer";
    case json::value_t::number_float:
      return "a number";
    case json::value_t::string:
      return "a string";
    case json::value_t::array:
      return "an array";
    case json::value_t::object:
      return "an object";
    default:
      return "an unsupported value";
  }
}

bool has_type(const json& x, const std::string& t) {
  if (t == "object") return x.is_object();
  if (t == "array") return x.is_array();
  if (t == "string") return x.is_string();
  if (t == "boolean") return x.is_boolean();
  if (t == "null") return x.is_null();
  if (t == "number") return x.is_number();
  if (t == "integer") {
    if (x.is_number_integer()) return true;
    if (!x.is_number_float()) return false;
    const double v = x.get<double>();
    return std::isfinite(v) && v == std::floor(v);
  }
  return false;
}

bool fits_int(const json& x) {
  constexpr double lo = std::numeric_limits<int>::min(), hi = std::numeric_limits<int>::max();
  if (x.is_number_unsigned()) return x.get<std::uint64_t>() <= static_cast<std::uint64_t>(hi);
  if (x.is_number_integer()) return x.get<std::int64_t>() >= lo && x.get<std::int64_t>() <= hi;
  const double v = x.get<double>();
  return v >= lo && v <= hi;
}

std::string article(const std::string& t) {
  if (t == "null") return "null";
  if (t == "integer" || t == "array" || t == "object") return "an " + t;
  return "a " + t;
}

/// Short text of a value for messages (strings quoted, long values cut).
std::string show(const json& v) {
  std::string s = v.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

JsonSchema::JsonSchema(json schema) : root_(std::move(schema)) { lint(root_, ""); }

void JsonSchema::lint(const json& s, const std::string& where) const {
  if (s.is_boolean()) return;
  if (!s.is_object()) throw Error("scene schema: " + display_path(where) + " is not a schema");
  for (const auto& [key, value] : s.items()) {
    if (!supported_keywords().count(key))
      throw Error("scene schema: " + display_path(where) + " uses the unsupported keyword '" + key + "'");
    const std::string at = where + "/" + pointer_token(key);
    if (key == "properties" || key == "definitions" || key == "$defs") {
      for (const auto& [name, sub] : value.items()) lint(sub, at + "/" + pointer_token(name));
    } else if (key == "items" || (key == "additionalProperties" && value.is_object())) {
      lint(value, at);
    } else if (key == "oneOf" || key == "anyOf") {
      for (std::size_t i = 0; i < value.size(); ++i) lint(value[i], at + "/" + std::to_string(i));
    } else if (key == "$ref") {
      resolve(value.get<std::string>());
    }
  }
}

const json& JsonSchema::resolve(const std::string& ref) const {
  if (ref.rfind("#/", 0) != 0)
    throw Error("scene schema: unsupported $ref '" + ref + "' (only #/... pointers)");
  try {
    const json& target = root_.at(json::json_pointer(ref.substr(1)));
    return target;
  } catch (const json::exception&) {
    throw Error("scene schema: $ref '" + ref + "' does not resolve");
  }
}

void JsonSchema::check(const json& s, const json& x, const std::string& path, std::vector<Issue>& out) const {
  if (s.is_boolean()) {
    if (!s.get<bool>()) out.push_back({path, "is not allowed here", Issue::Kind::Key});
    return;
  }
  if (auto it = s.find("$ref"); it != s.end()) return check(resolve(it->get<std::string>()), x, path, out);
  if (!check_type(s, x, path, out) || !check_constant(s, x, path, out)) return;
  check_bounds(s, x, path, out);
  if (x.is_array()) check_array(s, x, path, out);
  if (x.is_object()) check_object(s, x, path, out);
  check_combinators(s, x, path, out);
}

bool JsonSchema::check_type(const json& s, const json& x, const std::string& path, std::vector<Issue>& out) {
  using K = Issue::Kind;
  if (auto it = s.find("type"); it != s.end()) {
    std::vector<std::string> types;
    if (it->is_string())
      types.push_back(it->get<std::string>());
    else
      for (const auto& t : *it) types.push_back(t.get<std::string>());
    if (std::none_of(types.begin(), types.end(), [&](const std::string& t) { return has_type(x, t); })) {
      std::string want;
      for (std::size_t i = 0; i < types.size(); ++i) want += (i ? " or " : "") + article(types[i]);
      out.push_back({path, "expected " + want + ", got " + type_name(x), K::Type});
      return false;
    }
    // The loader reads every "integer" as an int: 1e300 (integral, so an integer above) or 2^40 would
    // not convert (undefined behaviour for a float, found by fuzz_scene; a silent wrap for an integer).
    const bool integer = std::find(types.begin(), types.end(), "integer") != types.end() &&
                         std::find(types.begin(), types.end(), "number") == types.end();
    if (integer && x.is_number() && !fits_int(x)) {
      out.push_back(
          {path, "integer " + show(x) + " out of range (at most 2147483647 in magnitude)", K::Value});
      return false;
    }
  }
  return true;
}

bool JsonSchema::check_constant(const json& s, const json& x, const std::string& path,
                                std::vector<Issue>& out) {
  using K = Issue::Kind;
  if (auto it = s.find("const"); it != s.end() && x != *it) {
    out.push_back({path, "expected " + show(*it) + ", got " + show(x), K::Constant, it->dump()});
    return false;
  }
  if (auto it = s.find("enum"); it != s.end()) {
    if (std::find(it->begin(), it->end(), x) == it->end()) {
      std::string list;
      for (std::size_t i = 0; i < it->size(); ++i) list += (i ? ", " : "") + (*it)[i].dump();
      out.push_back({path, "expected one of " + list + ", got " + show(x), K::Constant, list});
      return false;
    }
  }
  return true;
}

void JsonSchema::check_bounds(const json& s, const json& x, const std::string& path,
                              std::vector<Issue>& out) {
  using K = Issue::Kind;
  if (x.is_number()) {
    const double v = x.get<double>();
    if (auto it = s.find("minimum"); it != s.end() && !(v >= it->get<double>()))
      out.push_back({path, "must be ≥ " + number_text(it->get<double>()) + ", got " + show(x), K::Value});
    if (auto it = s.find("maximum"); it != s.end() && !(v <= it->get<double>()))
      out.push_back({path, "must be ≤ " + number_text(it->get<double>()) + ", got " + show(x), K::Value});
    if (auto it = s.find("exclusiveMinimum"); it != s.end() && !(v > it->get<double>()))
      out.push_back({path, "must be > " + number_text(it->get<double>()) + ", got " + show(x), K::Value});
    if (auto it = s.find("exclusiveMaximum"); it != s.end() && !(v < it->get<double>()))
      out.push_back({path, "must be < " + number_text(it->get<double>()) + ", got " + show(x), K::Value});
  }
  if (x.is_string()) {
    if (auto it = s.find("minLength"); it != s.end() && x.get<std::string>().size() < it->get<std::size_t>())
      out.push_back({path,
                     it->get<std::size_t>() == 1 ? std::string("must not be empty")
                                                 : "must have at least " + it->dump() + " characters",
                     K::Value});
  }
}

void JsonSchema::check_array(const json& s, const json& x, const std::string& path,
                             std::vector<Issue>& out) const {
  using K = Issue::Kind;
  if (auto it = s.find("minItems"); it != s.end() && x.size() < it->get<std::size_t>())
    out.push_back(
        {path, "expected at least " + it->dump() + " items, got " + std::to_string(x.size()), K::Value});
  if (auto it = s.find("maxItems"); it != s.end() && x.size() > it->get<std::size_t>())
    out.push_back(
        {path, "expected at most " + it->dump() + " items, got " + std::to_string(x.size()), K::Value});
  if (auto it = s.find("items"); it != s.end())
    for (std::size_t i = 0; i < x.size(); ++i) check(*it, x[i], path + "/" + std::to_string(i), out);
}

void JsonSchema::check_object(const json& s, const json& x, const std::string& path,
                              std::vector<Issue>& out) const {
  using K = Issue::Kind;
  const auto props = s.find("properties");
  if (auto it = s.find("required"); it != s.end())
    for (const auto& key : *it)
      if (!x.contains(key.get<std::string>()))
        out.push_back({path, "missing required key '" + key.get<std::string>() + "'", K::Key});
  const auto extra = s.find("additionalProperties");
  for (const auto& [key, value] : x.items()) {
    const std::string at = path + "/" + pointer_token(key);
    if (props != s.end() && props->contains(key)) {
      check((*props)[key], value, at, out);
    } else if (extra != s.end()) {
      if (extra->is_boolean() && !extra->get<bool>()) {
        std::string allowed;
        if (props != s.end())
          for (const auto& [name, _] : props->items()) allowed += (allowed.empty() ? "" : ", ") + name;
        out.push_back(
            {at, "unknown key '" + key + "'" + (allowed.empty() ? "" : " (allowed here: " + allowed + ")"),
             K::Key});
      } else {
        check(*extra, value, at, out);
      }
    }
  }
}

void JsonSchema::check_combinators(const json& s, const json& x, const std::string& path,
                                   std::vector<Issue>& out) const {
  for (const char* combinator : {"oneOf", "anyOf"}) {
    const auto it = s.find(combinator);
    if (it == s.end()) continue;
    const bool one = combinator[0] == 'o';
    std::vector<std::vector<Issue>> alt(it->size());
    int matches = 0;
    for (std::size_t i = 0; i < it->size(); ++i) {
      check((*it)[i], x, path, alt[i]);
      if (alt[i].empty()) ++matches;
    }
    if (one && matches > 1)
      out.push_back({path, "matches more than one alternative", Issue::Kind::Value});
    else if (matches == 0)
      report_alternatives(x, path, alt, out);
  }
}

void JsonSchema::report_alternatives(const json& x, const std::string& path,
                                     const std::vector<std::vector<Issue>>& alt, std::vector<Issue>& out) {
  using K = Issue::Kind;
  // The most plausible alternative: rank by the worst kind of error at (or just below) this level,
  // then by the depth of the deepest error, then by the number of errors.
  const int base = depth(path);
  auto score = [&](const std::vector<Issue>& e) {
    int rank = 0, deepest = 0;
    for (const Issue& i : e) {
      const int d = depth(i.path) - base;
      if (i.kind == K::Type && d == 0) rank = std::max(rank, 3);
      if (i.kind == K::Constant && d <= 1) rank = std::max(rank, 2);
      if (i.kind == K::Key && d <= 1) rank = std::max(rank, 1);
      deepest = std::max(deepest, d);
    }
    return std::make_tuple(rank, -deepest, e.size());
  };
  std::size_t best = 0;
  for (std::size_t i = 1; i < alt.size(); ++i)
    if (score(alt[i]) < score(alt[best])) best = i;
  if (std::get<0>(score(alt[best])) == 3) {  // no alternative even has the right type
    std::set<std::string> kinds;
    std::string want;
    for (const auto& a : alt)
      for (const Issue& i : a)
        if (i.kind == K::Type && depth(i.path) == base) {
          const std::string w = i.message.substr(9, i.message.find(", got") - 9);
          if (kinds.insert(w).second) want += (want.empty() ? "" : " or ") + w;
        }
    out.push_back({path, "expected " + want + ", got " + type_name(x), K::Type});
  } else if (std::get<0>(score(alt[best])) == 2) {
    // Every alternative rejects the same discriminating constant (e.g. /deformer/type): one message
    // listing all the allowed values instead of the first alternative's.
    std::string at, values;
    bool same = true;
    for (const auto& a : alt) {
      if (std::get<0>(score(a)) == 3) continue;  // wrong type altogether (e.g. a string alternative)
      const auto c = std::find_if(a.begin(), a.end(), [&](const Issue& i) {
        return i.kind == K::Constant && depth(i.path) - base <= 1;
      });
      if (c == a.end() || (!at.empty() && c->path != at)) {
        same = false;
        break;
      }
      at = c->path;
      values += (values.empty() ? "" : ", ") + c->expected;
    }
    if (same) {
      const json* bad = &x;
      if (at != path) bad = &x.at(json::json_pointer("/" + at.substr(path.size() + 1)));
      out.push_back({at, "expected one of " + values + ", got " + show(*bad), K::Constant, values});
    } else {
      out.insert(out.end(), alt[best].begin(), alt[best].end());
    }
  } else {
    out.insert(out.end(), alt[best].begin(), alt[best].end());
  }
}

std::vector<SchemaError> JsonSchema::validate(const json& instance) const {
  std::vector<Issue> issues;
  check(root_, instance, "", issues);
  std::vector<SchemaError> errors;
  for (Issue& i : issues) errors.push_back({std::move(i.path), std::move(i.message)});
  return errors;
}

}  // namespace spinmotor::scene
