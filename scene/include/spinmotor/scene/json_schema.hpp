#pragma once
// A small JSON Schema validator for the subset of draft-07 that the scene schema uses (Debian ships no
// C++ JSON Schema validator). Supported keywords:
//   type (string or list; "integer" accepts integral floats, and only within the range of int, which
//   is how the loader reads them), const, enum, properties, required,
//   additionalProperties (false or a schema), items (one schema for every element), minItems,
//   maxItems, minimum, maximum, exclusiveMinimum, exclusiveMaximum (numbers), minLength, oneOf,
//   anyOf, $ref ("#/definitions/..." or "#/$defs/..."), and the annotations $schema, $id, title,
//   description, default, $comment (ignored).
// Any other keyword in the schema is rejected when the validator is constructed, so a schema that
// relies on an unsupported keyword fails loudly instead of validating less than it says.
//
// Errors name the JSON Pointer of the offending value ("/handles/1/select/box/min"). For oneOf/anyOf
// with no matching alternative the errors of the most plausible alternative are reported: one whose
// type matches, whose discriminating constants (e.g. "type": "spline") match, without unknown or
// missing keys at its own level, then the one whose first error is deepest.
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace spinmotor::scene {

struct SchemaError {
  std::string path;     ///< JSON Pointer of the bad value ("" = the document)
  std::string message;  ///< what is wrong, e.g. "expected at least 3 items, got 2"
};

class JsonSchema {
 public:
  /// Throws spinmotor::Error if the schema uses a keyword outside the supported subset (naming the
  /// schema path) or a $ref that does not resolve.
  explicit JsonSchema(nlohmann::json schema);

  /// All errors of `instance` (empty when valid).
  std::vector<SchemaError> validate(const nlohmann::json& instance) const;

  const nlohmann::json& schema() const { return root_; }

 private:
  struct Issue;
  void check(const nlohmann::json& s, const nlohmann::json& x, const std::string& path,
             std::vector<Issue>& out) const;
  const nlohmann::json& resolve(const std::string& ref) const;
  void lint(const nlohmann::json& s, const std::string& where) const;

  nlohmann::json root_;
};

/// One JSON Pointer reference token: "~" -> "~0", "/" -> "~1".
std::string pointer_token(std::string_view key);

/// "/" for the document itself, else the pointer unchanged.
inline std::string display_path(const std::string& pointer) { return pointer.empty() ? "/" : pointer; }

}  // namespace spinmotor::scene
