// The parameter contract between the solver and whoever runs it (the runner, a test, a user's
// program): a parameter's name, type, default, range or choices and one-line documentation
// (ParamSpec), resolved values (Params) and typed access to them. ParamTable<O> binds each
// parameter once to the member of an options struct it sets, so that a scheme states a parameter
// in one place: its name, range and doc in the table, its default as the member's initialiser.
//
// The solver knows nothing of TOML or SQLite: the runner validates a study against these specs,
// fills defaults, computes the job key from the resolved set and hands the values to the solver.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace sph {

// A parameter value. Int and Real are distinct: a Real parameter given as 1 is stored as 1.0.
using ParamValue = std::variant<bool, std::int64_t, double, std::string>;
using Params = std::map<std::string, ParamValue>;

enum class ParamType { Bool, Int, Real, String };

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::Real;
  ParamValue default_value = 0.0;   // every parameter has a default
  std::string doc;                  // one line, with units
  std::optional<double> min;        // Int/Real: inclusive lower bound
  std::optional<double> max;        // Int/Real: inclusive upper bound
  bool min_exclusive = false;       // min is exclusive (e.g. dx > 0)
  std::vector<std::string> choices; // String: allowed values (empty: any)
  // false: does not enter the job's identity (threads, output options).
  bool identity = true;
  // true: at its default value the parameter does not enter the job key either, so a parameter
  // added to a case with a default that reproduces the old behaviour keeps the keys (and the
  // finished results) of the jobs that do not set it. Other values enter the key as usual.
  bool neutral_default = false;
};

// Typed access to resolved parameters (the runner guarantees presence and type).
double get_real(const Params& p, const std::string& key);
std::int64_t get_int(const Params& p, const std::string& key);
bool get_bool(const Params& p, const std::string& key);
const std::string& get_string(const Params& p, const std::string& key);

// A range for ParamTable: [min, max], min exclusive when `open_min`.
struct Range {
  std::optional<double> min, max;
  bool open_min = false;
};

// The parameters of an options struct O, each bound once to the member it sets:
//
//   static const ParamTable<Options> table = ParamTable<Options>()
//       .real("cfl_ad", &Options::cfl_ad, "advection CFL number (eq. 9)", {0.0, 1.0, true})
//       .choice("tvf", &Options::tvf, {{"none", Tvf::None}, {"limited", Tvf::Limited}}, "...");
//   Options o = table.apply(params);   // every bound member set from the job's parameters
//   table.specs();                     // name, type, default, range, doc for the runner
// A parameter added later is followed by .neutral() (its default leaves old job keys as they were).
//
// The default of a parameter is the member's value in a default-constructed O.
template <class O>
class ParamTable {
public:
  ParamTable& real(std::string name, double O::*m, std::string doc, Range r = {}) {
    add({name, ParamType::Real, O{}.*m, std::move(doc), r.min, r.max, r.open_min},
        [m, name](O& o, const Params& p) { o.*m = get_real(p, name); });
    return *this;
  }
  ParamTable& integer(std::string name, int O::*m, std::string doc, Range r = {}) {
    add({name, ParamType::Int, std::int64_t{O{}.*m}, std::move(doc), r.min, r.max, r.open_min},
        [m, name](O& o, const Params& p) { o.*m = static_cast<int>(get_int(p, name)); });
    return *this;
  }
  ParamTable& boolean(std::string name, bool O::*m, std::string doc) {
    add({name, ParamType::Bool, O{}.*m, std::move(doc)},
        [m, name](O& o, const Params& p) { o.*m = get_bool(p, name); });
    return *this;
  }
  // A string parameter with any value, or one of `choices` when given.
  ParamTable& string(std::string name, std::string O::*m, std::string doc,
                     std::vector<std::string> choices = {}) {
    ParamSpec s{name, ParamType::String, O{}.*m, std::move(doc)};
    s.choices = std::move(choices);
    add(std::move(s), [m, name](O& o, const Params& p) { o.*m = get_string(p, name); });
    return *this;
  }
  // A string parameter naming one value of an enumeration (its default: the member's value).
  template <class E>
  ParamTable& choice(std::string name, E O::*m, std::vector<std::pair<std::string, E>> values,
                     std::string doc) {
    ParamSpec s{name, ParamType::String, std::string(), std::move(doc)};
    for (const auto& [text, v] : values) {
      s.choices.push_back(text);
      if (v == O{}.*m)
        s.default_value = text;
    }
    add(std::move(s), [m, name, values](O& o, const Params& p) {
      const std::string& t = get_string(p, name);
      for (const auto& [text, v] : values)
        if (text == t) {
          o.*m = v;
          return;
        }
      throw std::invalid_argument("parameter '" + name + "': unknown value '" + t + "'");
    });
    return *this;
  }

  // Marks the parameter declared last as neutral at its default (ParamSpec::neutral_default): one
  // added to a scheme later, whose default reproduces the old behaviour, so the jobs that do not
  // set it keep their keys.
  ParamTable& neutral() {
    specs_.back().neutral_default = true;
    return *this;
  }

  const std::vector<ParamSpec>& specs() const { return specs_; }
  // O with every bound member set from the resolved parameters p (other members as in `o`).
  O apply(const Params& p, O o = O{}) const {
    for (const auto& set : setters_)
      set(o, p);
    return o;
  }

private:
  std::vector<ParamSpec> specs_;
  std::vector<std::function<void(O&, const Params&)>> setters_;
  void add(ParamSpec s, std::function<void(O&, const Params&)> set) {
    specs_.push_back(std::move(s));
    setters_.push_back(std::move(set));
  }
};

} // namespace sph
