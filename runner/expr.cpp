// Recursive-descent parser and evaluator for derived-parameter expressions.
#include "expr.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>

namespace sph::runner {

struct Expr::Node {
  enum Kind { Number, Name, Neg, Add, Sub, Mul, Div, Pow, Call } kind;
  double number = 0;
  std::string name; // Name, Call
  std::size_t pos = 0;
  std::vector<std::shared_ptr<const Node>> args;
};

namespace {

using NodeP = std::shared_ptr<const Expr::Node>;

struct Function {
  const char* name;
  int arity;
};
constexpr Function functions[] = {{"sqrt", 1}, {"abs", 1},   {"exp", 1}, {"log", 1}, {"floor", 1},
                                  {"ceil", 1}, {"round", 1}, {"min", 2}, {"max", 2}, {"pow", 2}};

class Parser {
public:
  Parser(const std::string& s, std::vector<std::string>& names) : s_(s), names_(names) {}

  NodeP parse() {
    auto n = expr();
    skip();
    if (i_ != s_.size())
      fail("unexpected '" + std::string(1, s_[i_]) + "'");
    return n;
  }

private:
  const std::string& s_;
  std::vector<std::string>& names_;
  std::size_t i_ = 0;

  [[noreturn]] void fail(const std::string& msg) { throw ExprError(msg, i_); }
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_])))
      ++i_;
  }
  bool eat(char c) {
    skip();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  static NodeP make(Expr::Node::Kind k, std::size_t pos, std::vector<NodeP> args = {}) {
    auto n = std::make_shared<Expr::Node>();
    n->kind = k;
    n->pos = pos;
    n->args = std::move(args);
    return n;
  }

  NodeP expr() {
    auto lhs = term();
    for (;;) {
      skip();
      auto pos = i_;
      if (eat('+'))
        lhs = make(Expr::Node::Add, pos, {lhs, term()});
      else if (eat('-'))
        lhs = make(Expr::Node::Sub, pos, {lhs, term()});
      else
        return lhs;
    }
  }
  NodeP term() {
    auto lhs = unary();
    for (;;) {
      skip();
      auto pos = i_;
      if (eat('*'))
        lhs = make(Expr::Node::Mul, pos, {lhs, unary()});
      else if (eat('/'))
        lhs = make(Expr::Node::Div, pos, {lhs, unary()});
      else
        return lhs;
    }
  }
  // Nesting (parentheses, unary signs, powers, calls) is bounded, so that a hostile expression
  // cannot overflow the stack of the parser, the evaluator or the tree's destructor.
  static constexpr int max_depth = 100;
  struct Depth {
    Parser& p;
    explicit Depth(Parser& parser) : p(parser) {
      if (++p.depth_ > max_depth)
        p.fail("expression nested more than " + std::to_string(max_depth) +
               " levels deep (parentheses, signs, powers, calls)");
    }
    ~Depth() { --p.depth_; }
  };
  int depth_ = 0;

  NodeP unary() {
    Depth guard(*this);
    skip();
    auto pos = i_;
    if (eat('-'))
      return make(Expr::Node::Neg, pos, {unary()});
    if (eat('+'))
      return unary();
    return power();
  }
  NodeP power() {
    auto base = primary();
    skip();
    auto pos = i_;
    if (eat('^'))
      return make(Expr::Node::Pow, pos, {base, unary()});
    return base;
  }
  NodeP primary() {
    skip();
    auto pos = i_;
    if (i_ >= s_.size())
      fail("unexpected end of expression");
    char c = s_[i_];
    if (eat('(')) {
      auto n = expr();
      if (!eat(')'))
        fail("expected ')'");
      return n;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const char* begin = s_.c_str() + i_;
      char* end = nullptr;
      double x = std::strtod(begin, &end);
      if (end == begin)
        fail("bad number");
      i_ += static_cast<std::size_t>(end - begin);
      auto n = make(Expr::Node::Number, pos);
      std::const_pointer_cast<Expr::Node>(n)->number = x;
      return n;
    }
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      std::size_t j = i_;
      while (j < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[j])) || s_[j] == '_'))
        ++j;
      std::string name = s_.substr(i_, j - i_);
      i_ = j;
      if (eat('('))
        return call(name, pos);
      if (name == "pi") {
        auto n = make(Expr::Node::Number, pos);
        std::const_pointer_cast<Expr::Node>(n)->number = M_PI;
        return n;
      }
      auto n = std::make_shared<Expr::Node>();
      n->kind = Expr::Node::Name;
      n->name = name;
      n->pos = pos;
      bool seen = false;
      for (const auto& x : names_)
        seen = seen || x == name;
      if (!seen)
        names_.push_back(name);
      return n;
    }
    fail("unexpected '" + std::string(1, c) + "'");
  }
  NodeP call(const std::string& name, std::size_t pos) {
    const Function* f = nullptr;
    for (const auto& fn : functions)
      if (name == fn.name)
        f = &fn;
    if (!f) {
      i_ = pos;
      fail("unknown function '" + name +
           "' (known: sqrt, abs, exp, log, floor, ceil, round, min, "
           "max, pow)");
    }
    std::vector<NodeP> args;
    if (!eat(')')) {
      do
        args.push_back(expr());
      while (eat(','));
      if (!eat(')'))
        fail("expected ')' or ','");
    }
    if (static_cast<int>(args.size()) != f->arity) {
      i_ = pos;
      fail(name + "() takes " + std::to_string(f->arity) + " argument" +
           (f->arity == 1 ? "" : "s") + ", got " + std::to_string(args.size()));
    }
    auto n = std::make_shared<Expr::Node>();
    n->kind = Expr::Node::Call;
    n->name = name;
    n->pos = pos;
    n->args = std::move(args);
    return n;
  }
};

double eval_node(const Expr::Node& n, const Expr::Lookup& lookup) {
  auto arg = [&](std::size_t k) { return eval_node(*n.args[k], lookup); };
  switch (n.kind) {
  case Expr::Node::Number:
    return n.number;
  case Expr::Node::Name: {
    auto v = lookup(n.name);
    if (!v)
      throw ExprError("unknown name '" + n.name + "'", n.pos);
    return *v;
  }
  case Expr::Node::Neg:
    return -arg(0);
  case Expr::Node::Add:
    return arg(0) + arg(1);
  case Expr::Node::Sub:
    return arg(0) - arg(1);
  case Expr::Node::Mul:
    return arg(0) * arg(1);
  case Expr::Node::Div:
    return arg(0) / arg(1);
  case Expr::Node::Pow:
    return std::pow(arg(0), arg(1));
  case Expr::Node::Call: {
    const auto& f = n.name;
    if (f == "sqrt")
      return std::sqrt(arg(0));
    if (f == "abs")
      return std::abs(arg(0));
    if (f == "exp")
      return std::exp(arg(0));
    if (f == "log")
      return std::log(arg(0));
    if (f == "floor")
      return std::floor(arg(0));
    if (f == "ceil")
      return std::ceil(arg(0));
    if (f == "round")
      return std::round(arg(0));
    if (f == "min")
      return std::min(arg(0), arg(1));
    if (f == "max")
      return std::max(arg(0), arg(1));
    if (f == "pow")
      return std::pow(arg(0), arg(1));
    throw ExprError("unknown function '" + f + "'", n.pos);
  }
  }
  return 0;
}

} // namespace

Expr Expr::parse(const std::string& text) {
  // A long chain (1+1+...+1) nests the tree without nesting the text: bounded by the length.
  constexpr std::size_t max_length = 4000;
  if (text.size() > max_length)
    throw ExprError("expression of " + std::to_string(text.size()) + " characters; at most " +
                        std::to_string(max_length) + " are allowed",
                    max_length);
  Expr e;
  e.text_ = text;
  Parser p(e.text_, e.names_);
  e.root_ = p.parse();
  return e;
}

double Expr::eval(const Lookup& lookup) const {
  if (!root_)
    throw ExprError("empty expression", 0);
  return eval_node(*root_, lookup);
}

} // namespace sph::runner
