// Parameter values against their specs: coercion, checks, printing and JSON conversion.
#include "params.hpp"

#include "diagnostics.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace sph::runner {

std::string type_name(ParamType t) {
  switch (t) {
  case ParamType::Bool:
    return "bool";
  case ParamType::Int:
    return "int";
  case ParamType::Real:
    return "real";
  case ParamType::String:
    return "string";
  }
  return "?";
}

std::string type_phrase(ParamType t) {
  switch (t) {
  case ParamType::Bool:
    return "a boolean (true/false)";
  case ParamType::Int:
    return "an integer";
  case ParamType::Real:
    return "a real number";
  case ParamType::String:
    return "a string";
  }
  return "?";
}

std::string value_type_phrase(const ParamValue& v) {
  switch (v.index()) {
  case 0:
    return "a boolean";
  case 1:
    return "an integer";
  case 2:
    return "a real number";
  default:
    return "a string";
  }
}

std::string format_real(double x) {
  if (std::isnan(x))
    return "nan";
  if (std::isinf(x))
    return x > 0 ? "inf" : "-inf";
  char buf[64];
  auto res = std::to_chars(buf, buf + sizeof buf, x);
  std::string s(buf, res.ptr);
  if (s.find_first_of(".en") == std::string::npos)
    s += ".0";
  return s;
}

std::string format_value_plain(const ParamValue& v) {
  if (auto b = std::get_if<bool>(&v))
    return *b ? "true" : "false";
  if (auto i = std::get_if<std::int64_t>(&v))
    return std::to_string(*i);
  if (auto d = std::get_if<double>(&v))
    return format_real(*d);
  return std::get<std::string>(v);
}

std::string format_value(const ParamValue& v) {
  if (auto s = std::get_if<std::string>(&v))
    return "\"" + *s + "\"";
  return format_value_plain(v);
}

std::string constraint_text(const ParamSpec& spec) {
  if (!spec.choices.empty())
    return "one of " + quoted_list(spec.choices);
  auto num = [&](double x) {
    if (spec.type == ParamType::Int && std::abs(x) < 9e15)
      return std::to_string(static_cast<std::int64_t>(x));
    return format_real(x);
  };
  if (spec.min && spec.max)
    return std::string(spec.min_exclusive ? "(" : "[") + num(*spec.min) + ", " + num(*spec.max) +
           "]";
  if (spec.min)
    return std::string(spec.min_exclusive ? "> " : ">= ") + num(*spec.min);
  if (spec.max)
    return "<= " + num(*spec.max);
  return "";
}

std::optional<std::string> check_value(const ParamSpec& spec, ParamValue& v) {
  auto got = [&] { return ", got " + format_value(v) + " (" + value_type_phrase(v) + ")"; };
  switch (spec.type) {
  case ParamType::Bool:
    if (!std::holds_alternative<bool>(v))
      return "expected " + type_phrase(spec.type) + got();
    return std::nullopt;
  case ParamType::String: {
    auto s = std::get_if<std::string>(&v);
    if (!s)
      return "expected " + type_phrase(spec.type) + got();
    if (!spec.choices.empty()) {
      for (const auto& c : spec.choices)
        if (c == *s)
          return std::nullopt;
      return "\"" + *s + "\" is not one of " + quoted_list(spec.choices) +
             did_you_mean(*s, spec.choices);
    }
    return std::nullopt;
  }
  case ParamType::Int:
    if (!std::holds_alternative<std::int64_t>(v))
      return "expected " + type_phrase(spec.type) + got();
    break;
  case ParamType::Real:
    if (auto i = std::get_if<std::int64_t>(&v))
      v = static_cast<double>(*i);
    if (!std::holds_alternative<double>(v))
      return "expected " + type_phrase(spec.type) + got();
    if (!std::isfinite(std::get<double>(v)))
      return "expected a finite real number" + got();
    break;
  }
  double x = spec.type == ParamType::Int ? static_cast<double>(std::get<std::int64_t>(v))
                                         : std::get<double>(v);
  bool low = spec.min && (spec.min_exclusive ? !(x > *spec.min) : !(x >= *spec.min));
  bool high = spec.max && !(x <= *spec.max);
  if (low || high)
    return format_value(v) + " is out of range: expected " + constraint_text(spec);
  return std::nullopt;
}

nlohmann::json value_to_json(const ParamValue& v) {
  return std::visit([](const auto& x) { return nlohmann::json(x); }, v);
}

ParamValue value_from_json(const ParamSpec& spec, const nlohmann::json& j) {
  auto fail = [&] {
    throw std::invalid_argument("parameter '" + spec.name + "': expected " +
                                type_phrase(spec.type) + ", got JSON " + j.dump());
  };
  switch (spec.type) {
  case ParamType::Bool:
    if (!j.is_boolean())
      fail();
    return j.get<bool>();
  case ParamType::Int:
    if (!j.is_number_integer())
      fail();
    return j.get<std::int64_t>();
  case ParamType::Real:
    if (!j.is_number())
      fail();
    return j.get<double>();
  case ParamType::String:
    if (!j.is_string())
      fail();
    return j.get<std::string>();
  }
  fail();
  return {};
}

namespace {
ParamSpec scheme_spec(const CaseInfo& info) {
  ParamSpec s;
  s.name = scheme_param;
  s.type = ParamType::String;
  s.default_value = info.schemes.front(); // the case's first scheme is its default
  s.doc = "numerical scheme";
  s.choices = info.schemes;
  return s;
}
void add_missing(std::vector<ParamSpec>& specs, const std::vector<ParamSpec>& more) {
  for (const auto& p : more)
    if (!find_spec(specs, p.name))
      specs.push_back(p);
}
} // namespace

std::vector<ParamSpec> study_specs(const CaseInfo& info) {
  std::vector<ParamSpec> specs = info.params;
  for (const auto& name : info.schemes)
    if (const SchemeInfo* s = find_scheme(name))
      add_missing(specs, s->params);
  if (!info.schemes.empty())
    specs.push_back(scheme_spec(info));
  return specs;
}

std::vector<ParamSpec> job_specs(const CaseInfo& info, const std::string& scheme) {
  std::vector<ParamSpec> specs = info.params;
  if (const SchemeInfo* s = find_scheme(scheme))
    add_missing(specs, s->params);
  if (!info.schemes.empty())
    specs.push_back(scheme_spec(info));
  return specs;
}

std::string scheme_owning(const CaseInfo& info, const std::string& name) {
  for (const auto& p : info.params)
    if (p.name == name)
      return "";
  for (const auto& sn : info.schemes)
    if (const SchemeInfo* s = find_scheme(sn))
      for (const auto& p : s->params)
        if (p.name == name)
          return sn;
  return "";
}

const ParamSpec* find_spec(const std::vector<ParamSpec>& specs, const std::string& name) {
  for (const auto& s : specs)
    if (s.name == name)
      return &s;
  return nullptr;
}

std::vector<std::string> spec_names(const std::vector<ParamSpec>& specs) {
  std::vector<std::string> names;
  for (const auto& s : specs)
    names.push_back(s.name);
  return names;
}

} // namespace sph::runner
