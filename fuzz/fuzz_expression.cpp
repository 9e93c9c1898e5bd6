// fuzz_expression: parse_scalar_expression (spin/scalar_expression.hpp) on the input as text, then the
// function at a few points. Evaluation never throws (its contract), so only the parse may throw Error.
#include <string>

#include "fuzz_support.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/spin/scalar_expression.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::function<double(const Eigen::Vector3d&)> g;
  try {
    g = spinmotor::parse_scalar_expression(std::string(reinterpret_cast<const char*>(data), size));
  } catch (const spinmotor::Error& e) {
    return spinmotor::fuzz::refused(e);
  }
  spinmotor::fuzz::check(static_cast<bool>(g), "a parsed expression is callable");
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, -2, 0.5),
                                   Eigen::Vector3d(-1e3, 1e-3, 7), Eigen::Vector3d(1e300, -1e300, 0)})
    (void)g(p);  // any value, NaN and Inf included (the callers reject those per face)
  return 0;
}
