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
  /// Appends the issues of `x` (at JSON Pointer `path`) against schema `s` to `out`, in the order of
  /// the phases below; a type, const or enum mismatch ends the check of `x`.
  void check(const nlohmann::json& s, const nlohmann::json& x, const std::string& path,
             std::vector<Issue>& out) const;
  /// "type" (and the int range of "integer"): appends the mismatch to `out`; false if there was one.
  static bool check_type(const nlohmann::json& s, const nlohmann::json& x, const std::string& path,
                         std::vector<Issue>& out);
  /// "const" and "enum": appends the mismatch to `out`; false if there was one.
  static bool check_constant(const nlohmann::json& s, const nlohmann::json& x, const std::string& path,
                             std::vector<Issue>& out);
  /// The bounds of a number (minimum, maximum, exclusiveMinimum, exclusiveMaximum) or a string
  /// (minLength): appends each bound `x` breaks to `out`.
  static void check_bounds(const nlohmann::json& s, const nlohmann::json& x, const std::string& path,
                           std::vector<Issue>& out);
  /// The array `x`: minItems, maxItems, then each element against "items"; issues appended to `out`.
  void check_array(const nlohmann::json& s, const nlohmann::json& x, const std::string& path,
                   std::vector<Issue>& out) const;
  /// The object `x`: missing "required" keys, then each key against "properties" or
  /// "additionalProperties"; issues appended to `out`.
  void check_object(const nlohmann::json& s, const nlohmann::json& x, const std::string& path,
                    std::vector<Issue>& out) const;
  /// "oneOf" and "anyOf": checks `x` against each alternative; appends "matches more than one
  /// alternative" (oneOf) or, when none matches, what report_alternatives finds to `out`.
  void check_combinators(const nlohmann::json& s, const nlohmann::json& x, const std::string& path,
                         std::vector<Issue>& out) const;
  /// No alternative matches `x`: appends to `out` the issues of the most plausible alternative `alt[i]`,
  /// or one merged message when no alternative has the right type or all reject the same constant.
  static void report_alternatives(const nlohmann::json& x, const std::string& path,
                                  const std::vector<std::vector<Issue>>& alt, std::vector<Issue>& out);
  const nlohmann::json& resolve(const std::string& ref) const;
  void lint(const nlohmann::json& s, const std::string& where) const;

  nlohmann::json root_;
};

/// One JSON Pointer reference token: "~" -> "~0", "/" -> "~1".
std::string pointer_token(std::string_view key);

/// "/" for the document itself, else the pointer unchanged.
inline std::string display_path(const std::string& pointer) { return pointer.empty() ? "/" : pointer; }

}  // namespace spinmotor::scene
