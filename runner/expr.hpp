// Arithmetic expressions for derived parameters ("0.1 * dx", "sqrt(h_over_dx) ^ 2"):
// + - * / ^ (right-associative), unary minus, parentheses, numbers, parameter names, the constant
// pi and the functions sqrt, abs, exp, log, floor, ceil, round, min, max, pow.
// A small recursive-descent parser builds a tree once; evaluation looks names up through a
// callback.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph::runner {

class ExprError : public std::runtime_error {
public:
  ExprError(const std::string& message, std::size_t position)
      : std::runtime_error(message), position_(position) {}
  std::size_t position() const { return position_; } // 0-based offset in the expression text

private:
  std::size_t position_;
};

class Expr {
public:
  struct Node;
  // Throws ExprError on a syntax error or an unknown function.
  static Expr parse(const std::string& text);

  // Looks a name up; nullopt means unknown (evaluation then throws ExprError).
  using Lookup = std::function<std::optional<double>(const std::string&)>;
  double eval(const Lookup& lookup) const;

  // Parameter names the expression refers to, in order of first use.
  const std::vector<std::string>& names() const { return names_; }
  const std::string& text() const { return text_; }

private:
  std::shared_ptr<const Node> root_;
  std::vector<std::string> names_;
  std::string text_;
};

} // namespace sph::runner
