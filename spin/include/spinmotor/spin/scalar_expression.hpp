#pragma once
// A scalar expression of position, e.g. "5 * sin(3*x) * cos(2*y) - 0.5*z^2", for painting the curvature
// change ρ (curvature_change.hpp) from the command line or a scene file.
//
// Grammar (usual precedence, ^ right-associative and above unary minus: -x^2 = -(x^2)):
//   expr   = term { ('+' | '-') term }
//   term   = unary { ('*' | '/') unary }
//   unary  = ('-' | '+') unary | power
//   power  = atom [ '^' unary ]
//   atom   = number | variable | function '(' expr ')' | '(' expr ')'
// Variables: x, y, z (the position), r = |p|. Constants: pi, e. Functions: sin, cos, tan, asin, acos,
// atan, sinh, cosh, tanh, exp, log, sqrt, abs. Numbers: decimal with optional exponent (1e-3).
// Limits (so that no text can overflow the stack): at most 100 nesting levels (parentheses, signs, '^',
// function calls) and a tree at most 1000 operations deep (e.g. a sum of at most 1000 terms).
#include <Eigen/Core>
#include <functional>
#include <string>

namespace spinmotor {

/// Parses `text`. Output: a function of the position. Throws Error naming the offending character
/// position and token (e.g. "scalar expression 'sin(x' at 5: expected ')'"). Evaluation itself never
/// throws; it can return NaN/Inf (e.g. log(-1)), which the callers reject per face.
std::function<double(const Eigen::Vector3d&)> parse_scalar_expression(const std::string& text);

}  // namespace spinmotor
