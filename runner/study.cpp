// Parses a study file with toml++ and validates every key and value against the case registry,
// collecting all errors with their line numbers before giving up.
#include "study.hpp"

#include "diagnostics.hpp"
#include "job_key.hpp"
#include "params.hpp"
#include "report_figures_toml.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <map>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

namespace sph::runner {

const Tier* Study::find_tier(const std::string& n) const {
  for (const auto& t : tiers)
    if (t.name == n)
      return &t;
  return nullptr;
}

std::vector<std::string> Study::tier_names() const {
  std::vector<std::string> names;
  for (const auto& t : tiers)
    names.push_back(t.name);
  return names;
}

namespace {

int line_of(const toml::node& n) {
  return static_cast<int>(n.source().begin.line);
}
int column_of(const toml::node& n) {
  return static_cast<int>(n.source().begin.column);
}

// Entries of a table in file order (toml++ keeps tables sorted by key).
std::vector<std::pair<std::string, const toml::node*>> ordered(const toml::table& t) {
  std::vector<std::pair<std::string, const toml::node*>> items;
  for (auto&& [k, v] : t)
    items.emplace_back(std::string(k.str()), &v);
  std::stable_sort(items.begin(), items.end(), [](const auto& a, const auto& b) {
    auto sa = a.second->source().begin, sb = b.second->source().begin;
    return sa.line != sb.line ? sa.line < sb.line : sa.column < sb.column;
  });
  return items;
}

std::string node_kind(const toml::node& n) {
  switch (n.type()) {
  case toml::node_type::table:
    return "a table";
  case toml::node_type::array:
    return "a list";
  case toml::node_type::string:
    return "a string";
  case toml::node_type::integer:
    return "an integer";
  case toml::node_type::floating_point:
    return "a real number";
  case toml::node_type::boolean:
    return "a boolean";
  default:
    return "a date/time";
  }
}

class StudyParser {
public:
  explicit StudyParser(const std::string& file) : diag_(file) { study_.file = file; }

  Study parse(const std::string& text) {
    toml::table root;
    try {
      root = toml::parse(text, study_.file);
    } catch (const toml::parse_error& e) {
      diag_.error(static_cast<int>(e.source().begin.line),
                  "TOML syntax error: " + std::string(e.description()),
                  static_cast<int>(e.source().begin.column));
      diag_.throw_if_any();
    }
    study_.definition_sha256 = sha256_hex(text);

    static const std::vector<std::string> top = {"study", "params",  "sweep", "zip",   "figures",
                                                 "cases", "derived", "tiers", "search"};
    for (auto&& [k, v] : root) {
      std::string key(k.str());
      if (std::find(top.begin(), top.end(), key) == top.end())
        diag_.error(line_of(v),
                    "unknown top-level " +
                        std::string(v.is_table() ? "table [" + key + "]" : "key '" + key + "'") +
                        did_you_mean(key, top) +
                        "; expected [study], [params], [sweep], [[zip]], [[cases]], "
                        "[derived], [search] or [tiers.NAME]");
    }

    const toml::table* st = root["study"].as_table();
    if (!st) {
      diag_.error(0, "missing [study] table (with name = \"...\" and case = \"...\")");
      diag_.throw_if_any();
    }
    parse_study_table(*st);
    // Without a known case nothing else can be checked.
    diag_.throw_if_any();

    if (auto n = root.get("params"))
      for (auto& a : parse_assignments(*n, "[params]"))
        study_.params.push_back(std::move(a));
    if (auto n = root.get("sweep"))
      study_.sweep = parse_sweep(*n, "[sweep]");
    if (auto n = root.get("zip"))
      study_.zip = parse_zips(*n, "[[zip]]");
    if (auto n = root.get("cases"))
      study_.cases = parse_cases(*n, "[[cases]]");
    if (auto n = root.get("derived"))
      parse_derived(*n);
    if (auto n = root.get("tiers"))
      parse_tiers(*n);
    if (auto n = root.get("search"))
      parse_search(*n);
    if (auto n = root.get("figures")) // [[figures]]: what `runner report` draws (docs/report.md)
      parse_figures_node(*n, study_.specs, study_.file, diag_);
    check_conflicts();
    diag_.throw_if_any();
    return std::move(study_);
  }

private:
  Diagnostics diag_;
  Study study_;
  int scheme_line_ = 0;

  void parse_study_table(const toml::table& st) {
    static const std::vector<std::string> keys = {"name", "case", "scheme", "description",
                                                  "exclude"};
    for (auto&& [k, v] : st) {
      std::string key(k.str());
      if (std::find(keys.begin(), keys.end(), key) == keys.end())
        diag_.error(line_of(v), "[study] unknown key '" + key + "'" + did_you_mean(key, keys) +
                                    "; expected " + quoted_list(keys));
    }
    auto str = [&](const char* key, bool required) -> std::optional<std::string> {
      const toml::node* n = st.get(key);
      if (!n) {
        if (required)
          diag_.error(line_of(st), std::string("[study] missing key '") + key + "'");
        return std::nullopt;
      }
      if (!n->is_string()) {
        diag_.error(line_of(*n),
                    std::string("[study] ") + key + ": expected a string, got " + node_kind(*n));
        return std::nullopt;
      }
      return n->as_string()->get();
    };
    if (auto name = str("name", true)) {
      bool ok = !name->empty() && std::isalnum(static_cast<unsigned char>((*name)[0]));
      for (char c : *name)
        ok =
            ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.');
      if (!ok)
        diag_.error(line_of(*st.get("name")),
                    "[study] name: \"" + *name +
                        "\" must start with a letter or digit and contain only letters, digits, "
                        "'_', '-' and '.' (it names a results directory)");
      else if (name->size() > max_study_name)
        diag_.error(line_of(*st.get("name")),
                    "[study] name: " + std::to_string(name->size()) + " characters; at most " +
                        std::to_string(max_study_name) +
                        " are allowed (it names a results directory, and file names are limited "
                        "to 255 bytes)");
      study_.name = *name;
    }
    if (auto d = str("description", false))
      study_.description = *d;
    if (auto c = str("case", true)) {
      study_.case_name = *c;
      study_.case_line = line_of(*st.get("case"));
      study_.info = find_case(*c);
      if (!study_.info) {
        std::vector<std::string> known;
        for (const auto& ci : case_registry())
          known.push_back(ci.name);
        diag_.error(study_.case_line, "[study] case: unknown case \"" + *c + "\"" +
                                          did_you_mean(*c, known) +
                                          "; known cases: " + quoted_list(known));
      } else {
        study_.specs = study_specs(*study_.info);
      }
    }
    if (auto s = str("scheme", false); s && study_.info) {
      scheme_line_ = line_of(*st.get("scheme"));
      if (study_.info->schemes.empty()) {
        diag_.error(scheme_line_, "[study] scheme: case '" + study_.case_name +
                                      "' takes no scheme; remove the key");
      } else {
        ParamValue v = *s;
        if (auto err = check_value(*find_spec(study_.specs, scheme_param), v))
          diag_.error(scheme_line_, "[study] scheme: " + *err);
        study_.params.push_back({scheme_param, v, scheme_line_});
      }
    }
    if (const toml::node* ex = st.get("exclude"); ex && study_.info)
      study_.exclude = parse_excludes(*ex, "[study] exclude");
  }

  // A known parameter spec, or an error naming the place and suggesting a close name.
  const ParamSpec* spec_for(const std::string& name, int line, const std::string& where) {
    if (auto s = find_spec(study_.specs, name))
      return s;
    auto names = spec_names(study_.specs);
    diag_.error(line, where + " " + name + ": unknown parameter of case '" + study_.case_name +
                          "'" + did_you_mean(name, names) +
                          "; known parameters: " + quoted_list(names));
    return nullptr;
  }

  std::optional<ParamValue> scalar(const toml::node& n) {
    if (auto b = n.as_boolean())
      return ParamValue(b->get());
    if (auto i = n.as_integer())
      return ParamValue(static_cast<std::int64_t>(i->get()));
    if (auto d = n.as_floating_point())
      return ParamValue(d->get());
    if (auto s = n.as_string())
      return ParamValue(s->get());
    return std::nullopt;
  }

  // A checked, coerced value for `spec`, or nullopt after reporting the error.
  std::optional<ParamValue> value_for(const ParamSpec& spec, const toml::node& n,
                                      const std::string& where) {
    auto v = scalar(n);
    if (!v) {
      diag_.error(line_of(n),
                  where + ": expected " + type_phrase(spec.type) + ", got " + node_kind(n),
                  column_of(n));
      return std::nullopt;
    }
    if (auto err = check_value(spec, *v)) {
      diag_.error(line_of(n), where + ": " + *err, column_of(n));
      return std::nullopt;
    }
    return v;
  }

  const toml::table* table_or_error(const toml::node& n, const std::string& where,
                                    const std::string& example) {
    if (auto t = n.as_table())
      return t;
    diag_.error(line_of(n), where + ": expected a table, got " + node_kind(n) + example);
    return nullptr;
  }

  std::vector<Assignment> parse_assignments(const toml::node& n, const std::string& where) {
    std::vector<Assignment> out;
    auto t = table_or_error(n, where, "");
    if (!t)
      return out;
    for (auto& [name, node] : ordered(*t)) {
      auto spec = spec_for(name, line_of(*node), where);
      if (!spec)
        continue;
      if (node->is_array()) {
        diag_.error(line_of(*node), where + " " + name + ": expected a single value, got a list" +
                                        (where == "[params]" ? "; put lists under [sweep]" : ""));
        continue;
      }
      if (auto v = value_for(*spec, *node, where + " " + name))
        out.push_back({name, *v, line_of(*node)});
    }
    return out;
  }

  std::optional<Axis> parse_axis(const std::string& name, const toml::node& node,
                                 const std::string& where) {
    auto spec = spec_for(name, line_of(node), where);
    if (!spec)
      return std::nullopt;
    auto arr = node.as_array();
    if (!arr) {
      diag_.error(line_of(node), where + " " + name + ": expected a list of values, got " +
                                     node_kind(node) + " (write " + name + " = [ ... ])");
      return std::nullopt;
    }
    if (arr->empty()) {
      diag_.error(line_of(node), where + " " + name +
                                     ": empty list; a sweep axis needs at least "
                                     "one value");
      return std::nullopt;
    }
    Axis axis{name, {}, line_of(node)};
    bool ok = true;
    std::size_t i = 0;
    for (const auto& el : *arr) {
      auto v = value_for(*spec, el, where + " " + name + "[" + std::to_string(i++) + "]");
      if (v)
        axis.values.push_back(*v);
      else
        ok = false;
    }
    if (!ok)
      return std::nullopt;
    return axis;
  }

  std::vector<Axis> parse_sweep(const toml::node& n, const std::string& where) {
    std::vector<Axis> out;
    auto t = table_or_error(n, where, "");
    if (!t)
      return out;
    for (auto& [name, node] : ordered(*t))
      if (auto a = parse_axis(name, *node, where))
        out.push_back(std::move(*a));
    return out;
  }

  std::vector<const toml::table*> array_of_tables(const toml::node& n, const std::string& where) {
    std::vector<const toml::table*> out;
    auto arr = n.as_array();
    if (!arr) {
      diag_.error(line_of(n), where + ": expected an array of tables, got " + node_kind(n));
      return out;
    }
    for (const auto& el : *arr) {
      if (auto t = el.as_table())
        out.push_back(t);
      else
        diag_.error(line_of(el), where + ": expected a table, got " + node_kind(el));
    }
    return out;
  }

  std::vector<ZipGroup> parse_zips(const toml::node& n, const std::string& where) {
    std::vector<ZipGroup> out;
    for (const toml::table* t : array_of_tables(n, where)) {
      ZipGroup g;
      g.line = line_of(*t);
      for (auto& [name, node] : ordered(*t))
        if (auto a = parse_axis(name, *node, where))
          g.axes.push_back(std::move(*a));
      if (t->empty()) {
        diag_.error(g.line, where + ": empty zip group");
        continue;
      }
      bool same = true;
      for (const auto& a : g.axes)
        same = same && a.values.size() == g.length();
      if (!same) {
        std::string lens;
        for (const auto& a : g.axes)
          lens += (lens.empty() ? "" : ", ") + a.name + " has " + std::to_string(a.values.size()) +
                  " (line " + std::to_string(a.line) + ")";
        diag_.error(g.line,
                    where + ": the lists of a zip group must have the same length; " + lens);
        continue;
      }
      out.push_back(std::move(g));
    }
    return out;
  }

  std::vector<ExplicitCase> parse_cases(const toml::node& n, const std::string& where) {
    std::vector<ExplicitCase> out;
    for (const toml::table* t : array_of_tables(n, where)) {
      ExplicitCase c{parse_assignments(*t, where), line_of(*t)};
      out.push_back(std::move(c));
    }
    return out;
  }

  std::vector<Exclude> parse_excludes(const toml::node& n, const std::string& where) {
    std::vector<Exclude> out;
    for (const toml::table* t : array_of_tables(n, where)) {
      Exclude e{parse_assignments(*t, where), line_of(*t)};
      if (t->empty())
        diag_.error(e.line, where + ": an empty exclusion would drop every job");
      out.push_back(std::move(e));
    }
    return out;
  }

  void parse_derived(const toml::node& n) {
    const std::string where = "[derived]";
    auto t = table_or_error(n, where, "");
    if (!t)
      return;
    for (auto& [name, node] : ordered(*t)) {
      auto spec = spec_for(name, line_of(*node), where);
      if (!spec)
        continue;
      if (spec->type != ParamType::Real && spec->type != ParamType::Int) {
        diag_.error(line_of(*node), where + " " + name +
                                        ": only numeric parameters can be "
                                        "derived; '" +
                                        name + "' is " + type_phrase(spec->type));
        continue;
      }
      if (!node->is_string()) {
        diag_.error(line_of(*node), where + " " + name +
                                        ": expected an expression string such "
                                        "as \"0.1 * dx\", got " +
                                        node_kind(*node));
        continue;
      }
      const std::string& text = node->as_string()->get();
      try {
        Derived d{name, Expr::parse(text), line_of(*node)};
        study_.derived.push_back(std::move(d));
      } catch (const ExprError& e) {
        diag_.error(line_of(*node),
                    where + " " + name + ": " + e.what() + " in \"" + text + "\" at character " +
                        std::to_string(e.position() + 1),
                    column_of(*node) + 1 + static_cast<int>(e.position()));
      }
    }
    // Names used must be numeric parameters (possibly derived ones).
    for (const auto& d : study_.derived) {
      for (const auto& ref : d.expr.names()) {
        auto spec = find_spec(study_.specs, ref);
        if (!spec) {
          auto names = spec_names(study_.specs);
          diag_.error(d.line, where + " " + d.name + ": unknown name '" + ref + "' in \"" +
                                  d.expr.text() + "\"" + did_you_mean(ref, names) +
                                  "; known parameters: " + quoted_list(names));
        } else if (spec->type != ParamType::Real && spec->type != ParamType::Int) {
          diag_.error(d.line, where + " " + d.name + ": '" + ref + "' is " +
                                  type_phrase(spec->type) + ", not a number");
        }
      }
    }
  }

  void parse_tiers(const toml::node& n) {
    auto t = table_or_error(n, "[tiers]", "; write [tiers.quick]");
    if (!t)
      return;
    static const std::vector<std::string> keys = {"description", "params", "sweep",
                                                  "zip",         "cases",  "exclude"};
    for (auto& [name, node] : ordered(*t)) {
      std::string where = "[tiers." + name + "]";
      if (name == full_tier) {
        diag_.error(line_of(*node), where + ": the tier name 'full' is reserved for the whole "
                                            "study; choose another name");
        continue;
      }
      auto tt = table_or_error(*node, where, "");
      if (!tt)
        continue;
      Tier tier;
      tier.name = name;
      tier.line = line_of(*node);
      for (auto& [k, v] : ordered(*tt)) {
        if (k == "description") {
          if (v->is_string())
            tier.description = v->as_string()->get();
          else
            diag_.error(line_of(*v), where + " description: expected a string");
        } else if (k == "params") {
          tier.params = parse_assignments(*v, where + " params");
        } else if (k == "sweep") {
          tier.sweep = parse_sweep(*v, where + " sweep");
        } else if (k == "zip") {
          tier.zip = parse_zips(*v, where + " zip");
        } else if (k == "cases") {
          tier.cases = parse_cases(*v, where + " cases");
        } else if (k == "exclude") {
          tier.exclude = parse_excludes(*v, where + " exclude");
        } else {
          diag_.error(line_of(*v), where + ": unknown key '" + k + "'" + did_you_mean(k, keys) +
                                       "; expected " + quoted_list(keys));
        }
      }
      study_.tiers.push_back(std::move(tier));
    }
  }

  // A parameter may be set in one place only: [params], a sweep axis, a zip group or [derived].
  // [search] param = "dt_star", lo = 0.01, hi = 0.2, until = 0.05, scale = "log",
  // unstable_above = { cl_rms = 5.0 }, unstable_below = { ... }.
  void parse_search(const toml::node& n) {
    const std::string where = "[search]";
    auto t = table_or_error(n, where, " (param = \"dt_star\", lo = ..., hi = ..., until = 0.05)");
    if (!t)
      return;
    static const std::vector<std::string> keys = {
        "param", "lo", "hi", "until", "scale", "unstable_above", "unstable_below"};
    for (auto&& [k, v] : *t) {
      std::string key(k.str());
      if (std::find(keys.begin(), keys.end(), key) == keys.end())
        diag_.error(line_of(v), where + " unknown key '" + key + "'" + did_you_mean(key, keys) +
                                    "; expected " + quoted_list(keys));
    }
    Search s;
    s.line = line_of(n);
    auto number = [&](const char* key, bool required) -> std::optional<double> {
      const toml::node* v = t->get(key);
      if (!v) {
        if (required)
          diag_.error(s.line, where + " missing key '" + key + "'");
        return std::nullopt;
      }
      if (auto i = v->as_integer())
        return static_cast<double>(i->get());
      if (auto d = v->as_floating_point(); d && std::isfinite(d->get()))
        return d->get();
      diag_.error(line_of(*v),
                  where + " " + key + ": expected a finite number, got " + node_kind(*v));
      return std::nullopt;
    };
    const toml::node* p = t->get("param");
    if (!p || !p->is_string()) {
      diag_.error(p ? line_of(*p) : s.line,
                  where + " param: expected the name of the searched parameter, e.g. \"dt_star\"");
    } else if (auto spec = spec_for(p->as_string()->get(), line_of(*p), where + " param:")) {
      s.param = spec->name;
      if (spec->type != ParamType::Real && spec->type != ParamType::Int)
        diag_.error(line_of(*p), where + " param: '" + s.param + "' is " + type_phrase(spec->type) +
                                     "; only a numeric parameter can be searched");
    }
    const auto lo = number("lo", true), hi = number("hi", true);
    if (lo && hi) {
      s.lo = *lo, s.hi = *hi;
      if (s.lo == s.hi)
        diag_.error(s.line,
                    where + " lo and hi are equal; lo is the stable end, hi the unstable one");
    }
    if (auto u = number("until", false)) {
      if (!(*u > 0 && *u < 1))
        diag_.error(line_of(*t->get("until")),
                    where +
                        " until: expected the final bracket's relative width in (0, 1), e.g. 0.05");
      s.until = *u;
    }
    if (const toml::node* sc = t->get("scale")) {
      const auto* str = sc->as_string();
      if (!str || (str->get() != "log" && str->get() != "linear"))
        diag_.error(line_of(*sc), where + " scale: expected \"log\" or \"linear\"");
      else
        s.log = str->get() == "log";
      if (s.log && lo && hi && !(s.lo > 0 && s.hi > 0))
        diag_.error(line_of(*sc), where + " scale = \"log\" needs lo and hi > 0");
    }
    for (const char* key : {"unstable_above", "unstable_below"}) {
      const toml::node* b = t->get(key);
      if (!b)
        continue;
      auto bt = table_or_error(*b, where + " " + key, " ({ metric = bound })");
      if (!bt)
        continue;
      for (auto& [m, v] : ordered(*bt)) {
        double x = 0;
        if (auto i = v->as_integer())
          x = static_cast<double>(i->get());
        else if (auto d = v->as_floating_point())
          x = d->get();
        else {
          diag_.error(line_of(*v), where + " " + key + " " + m + ": expected a number");
          continue;
        }
        (std::string(key) == "unstable_above" ? s.unstable_above : s.unstable_below)
            .emplace_back(m, x);
      }
    }
    study_.search = std::move(s);
  }

  void check_conflicts() {
    struct Seen {
      std::string where;
      int line;
    };
    std::map<std::string, Seen> seen;
    auto claim = [&](const std::string& name, const std::string& where, int line) {
      auto [it, fresh] = seen.emplace(name, Seen{where, line});
      if (!fresh)
        diag_.error(line, "'" + name + "' is set in " + where + " and also in " + it->second.where +
                              " (line " + std::to_string(it->second.line) +
                              "); a parameter is either fixed, swept, zipped or derived");
    };
    for (const auto& a : study_.params)
      claim(a.name, a.name == scheme_param && a.line == scheme_line_ ? "[study]" : "[params]",
            a.line);
    for (const auto& a : study_.sweep)
      claim(a.name, "[sweep]", a.line);
    for (const auto& g : study_.zip)
      for (const auto& a : g.axes)
        claim(a.name, "[[zip]]", a.line);
    for (const auto& d : study_.derived)
      claim(d.name, "[derived]", d.line);
    for (const auto& c : study_.cases)
      for (const auto& a : c.overrides)
        for (const auto& d : study_.derived)
          if (a.name == d.name)
            diag_.error(a.line, "[[cases]] " + a.name + ": '" + a.name + "' is derived (line " +
                                    std::to_string(d.line) + "); it cannot be overridden");
    for (const auto& t : study_.tiers) {
      std::map<std::string, int> tier_seen;
      for (const auto& a : t.params)
        tier_seen[a.name] = a.line;
      for (const auto& a : t.sweep)
        if (auto it = tier_seen.find(a.name); it != tier_seen.end())
          diag_.error(a.line, "[tiers." + t.name + "] '" + a.name + "' is both in params (line " +
                                  std::to_string(it->second) + ") and in sweep");
      for (const auto& a : t.params)
        for (const auto& d : study_.derived)
          if (a.name == d.name)
            diag_.error(a.line, "[tiers." + t.name + "] params " + a.name + ": '" + a.name +
                                    "' is derived (line " + std::to_string(d.line) + ")");
    }
    if (study_.search && !study_.search->param.empty()) {
      const std::string& sp = study_.search->param;
      auto it = seen.find(sp);
      if (it != seen.end() && it->second.where != "[params]" && it->second.where != "[study]")
        diag_.error(study_.search->line, "[search] param: '" + sp + "' is in " + it->second.where +
                                             " (line " + std::to_string(it->second.line) +
                                             "); the searched parameter is set by the search only");
      for (const auto& c : study_.cases)
        for (const auto& a : c.overrides)
          if (a.name == sp)
            diag_.error(a.line,
                        "[[cases]] " + sp + ": the searched parameter is set by the search");
      for (const auto& t : study_.tiers) {
        for (const auto& a : t.sweep)
          if (a.name == sp)
            diag_.error(a.line, "[tiers." + t.name + "] sweep " + sp +
                                    ": the searched parameter is set by the search");
      }
    }
  }
};

} // namespace

Study parse_study(const std::string& text, const std::string& file) {
  StudyParser p(file);
  return p.parse(text);
}

Study load_study(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw StudyError({{path.string(), 0, 0, "cannot read study file: it is a directory"}});
  auto refuse = [&](const std::string& why) {
    throw StudyError({{path.string(), 0, 0, "cannot read study file: " + why}});
  };
  // Opened without blocking (a FIFO with no writer would hang), then checked to be a regular
  // file (not a FIFO, a device like /dev/zero, a socket) of bounded size, read with a bound.
  int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    int err = errno;
    refuse(std::strerror(err ? err : ENOENT));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    refuse(std::string("not a regular file (") +
           (S_ISFIFO(st.st_mode)   ? "a FIFO"
            : S_ISCHR(st.st_mode)  ? "a character device"
            : S_ISBLK(st.st_mode)  ? "a block device"
            : S_ISSOCK(st.st_mode) ? "a socket"
                                   : "not a file") +
           "); a study file is a TOML text file");
  }
  if (static_cast<std::uintmax_t>(st.st_size) > max_study_file_bytes) {
    ::close(fd);
    refuse(std::to_string(st.st_size) + " bytes; a study file may have at most " +
           std::to_string(max_study_file_bytes) + " bytes");
  }
  std::string text;
  char buf[65536];
  for (;;) {
    ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR)
      continue;
    if (n < 0) {
      int err = errno;
      ::close(fd);
      refuse(std::string("read error: ") + std::strerror(err));
    }
    if (n == 0)
      break;
    text.append(buf, static_cast<std::size_t>(n));
    if (text.size() > max_study_file_bytes) {
      ::close(fd);
      refuse("more than " + std::to_string(max_study_file_bytes) + " bytes");
    }
  }
  ::close(fd);
  return parse_study(text, path.string());
}

} // namespace sph::runner
