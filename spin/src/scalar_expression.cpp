#include "spinmotor/spin/scalar_expression.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>

#include "spinmotor/core/error.hpp"

namespace spinmotor {

namespace {

// Bounds on what the parser accepts, so that no input can overflow the stack: evaluation and
// destruction recurse once per tree level (a chain "x+x+...+x" is as deep as it is long), parsing once
// per nesting level ('(', unary sign, '^', function call) through five functions.
constexpr int kMaxTreeDepth = 1000;
constexpr int kMaxNesting = 100;

// Expression tree; evaluation is a recursive walk (the expressions are tiny).
struct Node {
  enum class Op { Num, X, Y, Z, R, Add, Sub, Mul, Div, Pow, Neg, Fun } op;
  int depth = 1;  // levels of the tree below and including this node
  double value = 0;
  double (*fun)(double) = nullptr;
  std::unique_ptr<Node> a, b;
  double eval(const Eigen::Vector3d& p) const {
    switch (op) {
      case Op::Num:
        return value;
      case Op::X:
        return p.x();
      case Op::Y:
        return p.y();
      case Op::Z:
        return p.z();
      case Op::R:
        return p.norm();
      case Op::Add:
        return a->eval(p) + b->eval(p);
      case Op::Sub:
        return a->eval(p) - b->eval(p);
      case Op::Mul:
        return a->eval(p) * b->eval(p);
      case Op::Div:
        return a->eval(p) / b->eval(p);
      case Op::Pow:
        return std::pow(a->eval(p), b->eval(p));
      case Op::Neg:
        return -a->eval(p);
      case Op::Fun:
        return fun(a->eval(p));
    }
    return 0;
  }
};
using NodePtr = std::unique_ptr<Node>;

NodePtr make(Node::Op op, NodePtr a = nullptr, NodePtr b = nullptr) {
  auto n = std::make_unique<Node>();
  n->op = op;
  n->a = std::move(a);
  n->b = std::move(b);
  n->depth = 1 + std::max(n->a ? n->a->depth : 0, n->b ? n->b->depth : 0);
  return n;
}

class Parser {
 public:
  explicit Parser(const std::string& s) : s_(s) {}
  NodePtr parse() {
    NodePtr e = expr();
    skip();
    if (i_ != s_.size()) fail("unexpected '" + std::string(1, s_[i_]) + "'");
    return e;
  }

 private:
  const std::string& s_;
  std::size_t i_ = 0;
  int nesting_ = -1;  // levels entered by unary(); the outermost expression is level 0

  [[noreturn]] void fail(const std::string& what) const {
    std::ostringstream m;
    m << "scalar expression '" << s_ << "' at " << i_ + 1 << ": " << what;
    throw Error(m.str());
  }
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool accept(char c) {
    skip();
    if (i_ < s_.size() && s_[i_] == c) return ++i_, true;
    return false;
  }
  // make() with the tree-depth bound.
  NodePtr node(Node::Op op, NodePtr a, NodePtr b = nullptr) {
    NodePtr n = make(op, std::move(a), std::move(b));
    if (n->depth > kMaxTreeDepth)
      fail("more than " + std::to_string(kMaxTreeDepth) +
           " levels of operations (the expression is too long)");
    return n;
  }
  NodePtr expr() {
    NodePtr e = term();
    for (;;) {
      if (accept('+'))
        e = node(Node::Op::Add, std::move(e), term());
      else if (accept('-'))
        e = node(Node::Op::Sub, std::move(e), term());
      else
        return e;
    }
  }
  NodePtr term() {
    NodePtr e = unary();
    for (;;) {
      if (accept('*'))
        e = node(Node::Op::Mul, std::move(e), unary());
      else if (accept('/'))
        e = node(Node::Op::Div, std::move(e), unary());
      else
        return e;
    }
  }
  // Every nesting level passes here once: the recursion bound.
  NodePtr unary() {
    if (++nesting_ > kMaxNesting)
      fail("nested more than " + std::to_string(kMaxNesting) +
           " levels deep (parentheses, signs, '^', functions)");
    NodePtr e;
    if (accept('-'))
      e = node(Node::Op::Neg, unary());
    else if (accept('+'))
      e = unary();
    else
      e = power();
    --nesting_;
    return e;
  }
  NodePtr power() {
    NodePtr base = atom();
    if (accept('^')) return node(Node::Op::Pow, std::move(base), unary());
    return base;
  }
  NodePtr atom() {
    skip();
    if (i_ >= s_.size()) fail("unexpected end, expected a number, variable, function or '('");
    const char c = s_[i_];
    if (accept('(')) {
      NodePtr e = expr();
      if (!accept(')')) fail("expected ')'");
      return e;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const char* start = s_.c_str() + i_;
      char* end = nullptr;
      const double v = std::strtod(start, &end);
      if (end == start) fail("bad number");
      i_ += static_cast<std::size_t>(end - start);
      auto n = make(Node::Op::Num);
      n->value = v;
      return n;
    }
    if (std::isalpha(static_cast<unsigned char>(c))) {
      const std::size_t start = i_;
      while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_')) ++i_;
      const std::string name = s_.substr(start, i_ - start);
      if (name == "x") return make(Node::Op::X);
      if (name == "y") return make(Node::Op::Y);
      if (name == "z") return make(Node::Op::Z);
      if (name == "r") return make(Node::Op::R);
      if (name == "pi" || name == "e") {
        auto n = make(Node::Op::Num);
        n->value = name == "pi" ? M_PI : M_E;
        return n;
      }
      static const std::map<std::string, double (*)(double)> funs = {
          {"sin", [](double v) { return std::sin(v); }},   {"cos", [](double v) { return std::cos(v); }},
          {"tan", [](double v) { return std::tan(v); }},   {"asin", [](double v) { return std::asin(v); }},
          {"acos", [](double v) { return std::acos(v); }}, {"atan", [](double v) { return std::atan(v); }},
          {"sinh", [](double v) { return std::sinh(v); }}, {"cosh", [](double v) { return std::cosh(v); }},
          {"tanh", [](double v) { return std::tanh(v); }}, {"exp", [](double v) { return std::exp(v); }},
          {"log", [](double v) { return std::log(v); }},   {"sqrt", [](double v) { return std::sqrt(v); }},
          {"abs", [](double v) { return std::abs(v); }},
      };
      const auto f = funs.find(name);
      if (f == funs.end()) {
        i_ = start;
        fail("unknown name '" + name +
             "' (variables x, y, z, r; constants pi, e; functions sin, cos, tan, asin, "
             "acos, atan, sinh, cosh, tanh, exp, log, sqrt, abs)");
      }
      if (!accept('(')) fail("expected '(' after " + name);
      auto n = node(Node::Op::Fun, expr());
      n->fun = f->second;
      if (!accept(')')) fail("expected ')'");
      return n;
    }
    fail("unexpected '" + std::string(1, c) + "'");
  }
};

}  // namespace

std::function<double(const Eigen::Vector3d&)> parse_scalar_expression(const std::string& text) {
  std::shared_ptr<const Node> root = Parser(text).parse();
  return [root](const Eigen::Vector3d& p) { return root->eval(p); };
}

}  // namespace spinmotor
