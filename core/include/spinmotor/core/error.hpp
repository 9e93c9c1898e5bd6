#pragma once
// spinmotor::Error — the one exception type of the project.
//
// Every public entry point validates its input and throws Error with a message that names the bad
// element (file and line, vertex or face index, JSON path, connected component). The kind tells a
// caller (and the CLI's exit code) whether the input was bad or the numerics failed on good input.
#include <stdexcept>
#include <string>

namespace spinmotor {

class Error : public std::runtime_error {
 public:
  enum class Kind {
    BadInput,   ///< malformed file, invalid mesh, bad parameter: CLI exit code 2
    Numerical,  ///< factorization or iteration failed on valid input: CLI exit code 3
  };

  explicit Error(const std::string& what, Kind kind = Kind::BadInput)
      : std::runtime_error(what), kind_(kind) {}

  Kind kind() const noexcept { return kind_; }

  /// The exit code the command-line tool uses for this error.
  int exit_code() const noexcept { return kind_ == Kind::BadInput ? 2 : 3; }

 private:
  Kind kind_;
};

/// Shorthand for a numerical failure.
inline Error numerical_error(const std::string& what) { return Error(what, Error::Kind::Numerical); }

}  // namespace spinmotor
