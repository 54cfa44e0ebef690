// Derived-parameter expressions: precedence, functions, names, errors with positions.
#include "expr.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

using sph::runner::Expr;
using sph::runner::ExprError;

namespace {
double eval(const std::string& text, std::map<std::string, double> vars = {}) {
  return Expr::parse(text).eval([&](const std::string& n) -> std::optional<double> {
    auto it = vars.find(n);
    if (it == vars.end())
      return std::nullopt;
    return it->second;
  });
}
} // namespace

TEST(Expr, PrecedenceAndAssociativity) {
  EXPECT_DOUBLE_EQ(eval("1 + 2 * 3"), 7);
  EXPECT_DOUBLE_EQ(eval("(1 + 2) * 3"), 9);
  EXPECT_DOUBLE_EQ(eval("2 ^ 3 ^ 2"), 512); // right-associative
  EXPECT_DOUBLE_EQ(eval("-2 ^ 2"), -4);
  EXPECT_DOUBLE_EQ(eval("2 ^ -1"), 0.5);
  EXPECT_DOUBLE_EQ(eval("8 / 4 / 2"), 1);
  EXPECT_DOUBLE_EQ(eval("1e-3 * 2.5e2"), 0.25);
}

TEST(Expr, FunctionsAndNames) {
  EXPECT_DOUBLE_EQ(eval("sqrt(16) + abs(-2) + min(3, 4) + max(3, 4) + pow(2, 3)"),
                   4 + 2 + 3 + 4 + 8);
  EXPECT_DOUBLE_EQ(eval("0.1 * dx", {{"dx", 0.5}}), 0.05);
  EXPECT_DOUBLE_EQ(eval("floor(t / dt)", {{"t", 1.0}, {"dt", 0.3}}), 3);
  EXPECT_NEAR(eval("pi"), M_PI, 1e-15);
  auto e = Expr::parse("a * b + a");
  ASSERT_EQ(e.names().size(), 2u);
  EXPECT_EQ(e.names()[0], "a");
  EXPECT_EQ(e.names()[1], "b");
}

TEST(Expr, Errors) {
  EXPECT_THROW(Expr::parse("1 +"), ExprError);
  EXPECT_THROW(Expr::parse("(1 + 2"), ExprError);
  EXPECT_THROW(Expr::parse("foo(1)"), ExprError);
  EXPECT_THROW(Expr::parse("min(1)"), ExprError);
  EXPECT_THROW(Expr::parse("1 $ 2"), ExprError);
  try {
    Expr::parse("1 + * 2");
    FAIL();
  } catch (const ExprError& e) {
    EXPECT_EQ(e.position(), 4u);
  }
  EXPECT_THROW(eval("dx * 2"), ExprError); // unknown name at evaluation
}
