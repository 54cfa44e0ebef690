// Parsing and validation of the [[figures]] tables of a study file (docs/report.md).
#include "report_figures.hpp"
#include "commands.hpp"

#include "job_file.hpp"
#include "params.hpp"
#include "report_figures_toml.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <set>
#include <sstream>

namespace sph::runner {

namespace {

int line_of(const toml::node& n) {
  return static_cast<int>(n.source().begin.line);
}

const std::vector<std::string> figure_keys = {
    "name",        "title",      "kind",         "x",         "y",     "file",
    "group",       "where",      "agg",          "spread",    "log_x", "log_y",
    "x_label",     "y_label",    "fit",          "fit_range", "mark",  "reference",
    "convergence", "resolution", "formal_order", "ignore"};
const std::vector<std::string> reference_keys = {"label", "citation", "expr", "csv",
                                                 "x",     "y",        "style"};
const std::vector<std::string> kinds = {"metric", "series", "convergence"};
const std::vector<std::string> convergence_kinds = {"self", "error"};
const std::vector<std::string> resolutions = {"auto", "spacing", "count"};
const std::vector<std::string> aggs = {"mean", "median", "min", "max"};
const std::vector<std::string> fits = {"none", "power", "linear"};
const std::vector<std::string> markable = {"diverged", "failed", "timeout"};

class FigureParser {
public:
  FigureParser(const std::vector<ParamSpec>& specs, const std::string& file, Diagnostics& diag)
      : specs_(specs), file_(file), diag_(diag) {}

  std::vector<FigureSpec> parse(const toml::node& n) {
    std::vector<FigureSpec> out;
    auto arr = n.as_array();
    if (!arr || !arr->is_array_of_tables()) {
      diag_.error(line_of(n), "[[figures]]: expected an array of tables (write [[figures]] "
                              "blocks)");
      return out;
    }
    std::set<std::string> names;
    for (const auto& el : *arr) {
      auto fig = figure(*el.as_table());
      if (!fig)
        continue;
      if (!names.insert(fig->name).second) {
        diag_.error(fig->line, "[[figures]] name: \"" + fig->name +
                                   "\" is used by another figure; names must be unique");
        continue;
      }
      out.push_back(std::move(*fig));
    }
    return out;
  }

private:
  const std::vector<ParamSpec>& specs_;
  std::string file_;
  Diagnostics& diag_;

  std::optional<std::string> str(const toml::table& t, const char* key, const std::string& where) {
    const toml::node* n = t.get(key);
    if (!n)
      return std::nullopt;
    if (!n->is_string()) {
      diag_.error(line_of(*n), where + " " + key + ": expected a string");
      return std::nullopt;
    }
    return n->as_string()->get();
  }

  std::optional<bool> boolean(const toml::table& t, const char* key, const std::string& where) {
    const toml::node* n = t.get(key);
    if (!n)
      return std::nullopt;
    if (!n->is_boolean()) {
      diag_.error(line_of(*n), where + " " + key + ": expected true or false");
      return std::nullopt;
    }
    return n->as_boolean()->get();
  }

  // A string or a list of strings.
  std::vector<std::string> strings(const toml::table& t, const char* key,
                                   const std::string& where) {
    std::vector<std::string> out;
    const toml::node* n = t.get(key);
    if (!n)
      return out;
    if (n->is_string())
      return {n->as_string()->get()};
    auto arr = n->as_array();
    bool ok = arr != nullptr;
    if (arr)
      for (const auto& el : *arr) {
        if (el.is_string())
          out.push_back(el.as_string()->get());
        else
          ok = false;
      }
    if (!ok) {
      diag_.error(line_of(*n), where + " " + key + ": expected a string or a list of strings");
      out.clear();
    }
    return out;
  }

  void one_of(const std::string& value, const std::vector<std::string>& allowed, int line,
              const std::string& what) {
    if (std::find(allowed.begin(), allowed.end(), value) == allowed.end())
      diag_.error(line, what + ": \"" + value + "\" is not one of " + quoted_list(allowed) +
                            did_you_mean(value, allowed));
  }

  const ParamSpec* param(const std::string& name, int line, const std::string& what) {
    if (auto s = find_spec(specs_, name))
      return s;
    auto names = spec_names(specs_);
    diag_.error(line, what + ": unknown parameter '" + name + "'" + did_you_mean(name, names) +
                          "; known parameters: " + quoted_list(names));
    return nullptr;
  }

  static std::optional<ParamValue> scalar(const toml::node& n) {
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

  std::optional<FigureSpec> figure(const toml::table& t) {
    FigureSpec f;
    f.line = line_of(t);
    std::size_t errors = diag_.size();
    for (auto&& [k, v] : t) {
      std::string key(k.str());
      if (std::find(figure_keys.begin(), figure_keys.end(), key) == figure_keys.end())
        diag_.error(line_of(v), "[[figures]] unknown key '" + key + "'" +
                                    did_you_mean(key, figure_keys) + "; expected " +
                                    quoted_list(figure_keys));
    }
    std::string where = "[[figures]]";
    if (auto name = str(t, "name", where)) {
      bool ok = !name->empty();
      for (char c : *name)
        ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-');
      if (!ok)
        diag_.error(line_of(*t.get("name")), where + " name: \"" + *name +
                                                 "\" must be letters, digits, '_' or '-' (it "
                                                 "names the image file)");
      f.name = *name;
      where = "[[figures]] " + f.name + ":";
    } else if (!t.get("name")) {
      diag_.error(f.line, where + ": missing key 'name'");
    }
    if (auto s = str(t, "title", where))
      f.title = *s;
    if (auto s = str(t, "kind", where)) {
      f.kind = *s;
      one_of(f.kind, kinds, line_of(*t.get("kind")), where + " kind");
    }
    // kind = "convergence": a metric figure of one metric against a resolution, with the table of
    // `runner converge` (order, extrapolated value, GCI per group) beneath it.
    if (f.kind == "convergence") {
      f.kind = "metric";
      f.convergence = "self";
      if (auto s = str(t, "convergence", where)) {
        f.convergence = *s;
        one_of(*s, convergence_kinds, line_of(*t.get("convergence")), where + " convergence");
      }
      if (auto s = str(t, "resolution", where)) {
        f.resolution = *s;
        one_of(*s, resolutions, line_of(*t.get("resolution")), where + " resolution");
      }
      if (const toml::node* n = t.get("formal_order")) {
        if (auto v = n->value<double>(); v && *v > 0)
          f.formal_order = *v;
        else
          diag_.error(line_of(*n), where + " formal_order: expected a positive number");
      }
      f.ignore = strings(t, "ignore", where);
      for (const auto& g : f.ignore)
        param(g, line_of(*t.get("ignore")), where + " ignore");
    } else {
      for (const char* key : {"convergence", "resolution", "formal_order", "ignore"})
        if (const toml::node* n = t.get(key))
          diag_.error(line_of(*n),
                      where + " " + key + ": only figures of kind = \"convergence\" take it");
    }
    const bool series = f.kind == "series";
    if (auto s = str(t, "file", where)) {
      f.file = *s;
      if (!series)
        diag_.error(line_of(*t.get("file")),
                    where + " file: only figures of kind = \"series\" read an HDF5 file");
    } else if (series && !t.get("file")) {
      diag_.error(f.line, where + " missing key 'file' (the HDF5 file in each job's output "
                                  "directory, e.g. \"series.h5\")");
    }
    if (auto s = str(t, "x", where)) {
      f.x = *s;
      if (!series) {
        if (auto spec = param(f.x, line_of(*t.get("x")), where + " x"))
          f.x_is_string = spec->type == ParamType::String || spec->type == ParamType::Bool;
      }
    } else if (!t.get("x")) {
      diag_.error(f.line, where + " missing key 'x' (a parameter such as \"n_side\")");
    }
    f.y = strings(t, "y", where);
    if (!t.get("y"))
      diag_.error(f.line, where + " missing key 'y' (a metric, or a list of metrics)");
    else if (f.y.empty() && diag_.size() == errors)
      diag_.error(line_of(*t.get("y")), where + " y: the list is empty");
    f.group = strings(t, "group", where);
    for (const auto& g : f.group) {
      param(g, line_of(*t.get("group")), where + " group");
      if (g == f.x && !series)
        diag_.error(line_of(*t.get("group")), where + " group: '" + g + "' is already the x axis");
    }
    if (const toml::node* w = t.get("where")) {
      if (auto wt = w->as_table()) {
        for (auto&& [k, v] : *wt) {
          std::string pname(k.str());
          const ParamSpec* spec = param(pname, line_of(v), where + " where");
          if (!spec)
            continue;
          FilterValue fv{pname, {}};
          std::vector<const toml::node*> items;
          if (auto arr = v.as_array())
            for (const auto& el : *arr)
              items.push_back(&el);
          else
            items.push_back(&v);
          for (const toml::node* item : items) {
            auto val = scalar(*item);
            if (!val) {
              diag_.error(line_of(*item), where + " where " + pname + ": expected " +
                                              type_phrase(spec->type) + " or a list of them");
              continue;
            }
            if (auto err = check_value(*spec, *val)) {
              diag_.error(line_of(*item), where + " where " + pname + ": " + *err);
              continue;
            }
            fv.values.push_back(*val);
          }
          f.where.push_back(std::move(fv));
        }
      } else {
        diag_.error(line_of(*w), where + " where: expected a table such as { lattice = "
                                         "\"uniform\" }");
      }
    }
    if (auto s = str(t, "agg", where)) {
      f.agg = *s;
      one_of(f.agg, aggs, line_of(*t.get("agg")), where + " agg");
    }
    if (auto b = boolean(t, "spread", where))
      f.spread = *b;
    if (auto b = boolean(t, "log_x", where))
      f.log_x = *b;
    if (auto b = boolean(t, "log_y", where))
      f.log_y = *b;
    if (auto s = str(t, "x_label", where))
      f.x_label = *s;
    if (auto s = str(t, "y_label", where))
      f.y_label = *s;
    if (auto s = str(t, "fit", where)) {
      f.fit = *s;
      one_of(f.fit, fits, line_of(*t.get("fit")), where + " fit");
    }
    if (f.convergence && f.y.size() > 1)
      diag_.error(line_of(*t.get("y")),
                  where + " y: a convergence figure takes one metric (write one figure each)");
    if (f.convergence && f.x_is_string)
      diag_.error(line_of(*t.get("x")), where + " x: '" + f.x +
                                            "' is not a number; a convergence figure needs a "
                                            "resolution such as dx or n_side");
    if (f.x_is_string && f.log_x)
      diag_.error(line_of(*t.get("log_x")),
                  where + " log_x: x = '" + f.x + "' is not a number; it cannot be on a log axis");
    if (f.x_is_string && f.fit != "none")
      diag_.error(line_of(*t.get("fit")),
                  where + " fit: x = '" + f.x + "' is not a number; nothing to fit");
    if (const toml::node* r = t.get("fit_range")) {
      auto arr = r->as_array();
      bool ok = arr && arr->size() == 2 && (*arr)[0].is_number() && (*arr)[1].is_number();
      if (ok) {
        double lo = (*arr)[0].value<double>().value_or(0),
               hi = (*arr)[1].value<double>().value_or(0);
        ok = lo < hi;
        f.fit_range = {lo, hi};
      }
      if (!ok)
        diag_.error(line_of(*r), where + " fit_range: expected [low, high] with low < high");
      else if (f.fit == "none")
        diag_.error(line_of(*r), where + " fit_range: set fit = \"power\" or \"linear\" too");
    }
    if (t.get("mark")) {
      f.mark = strings(t, "mark", where);
      for (const auto& m : f.mark)
        one_of(m, markable, line_of(*t.get("mark")), where + " mark");
    }
    if (const toml::node* refs = t.get("reference")) {
      auto arr = refs->as_array();
      if (!arr || !arr->is_array_of_tables())
        diag_.error(line_of(*refs), where + " reference: expected [[figures.reference]] tables");
      else
        for (const auto& el : *arr)
          if (auto ref = reference(*el.as_table(), where + " reference"))
            f.references.push_back(std::move(*ref));
    }
    if (diag_.size() != errors)
      return std::nullopt;
    return f;
  }

  std::optional<ReferenceSeries> reference(const toml::table& t, const std::string& where) {
    ReferenceSeries r;
    r.line = line_of(t);
    std::size_t errors = diag_.size();
    for (auto&& [k, v] : t) {
      std::string key(k.str());
      if (std::find(reference_keys.begin(), reference_keys.end(), key) == reference_keys.end())
        diag_.error(line_of(v), where + " unknown key '" + key + "'" +
                                    did_you_mean(key, reference_keys) + "; expected " +
                                    quoted_list(reference_keys));
    }
    if (auto s = str(t, "label", where))
      r.label = *s;
    else if (!t.get("label"))
      diag_.error(r.line, where + ": missing key 'label' (the legend entry)");
    if (auto s = str(t, "citation", where))
      r.citation = *s;
    auto expr = str(t, "expr", where);
    auto csv = str(t, "csv", where);
    if (expr.has_value() == csv.has_value() && !t.get("expr") && !t.get("csv"))
      diag_.error(r.line, where + ": give either expr = \"...\" (a function of x) or csv = "
                                  "\"file.csv\" with x and y columns");
    else if (expr && csv)
      diag_.error(r.line, where + ": give expr or csv, not both");
    if (expr) {
      try {
        r.expr = Expr::parse(*expr);
        for (const auto& n : r.expr->names()) {
          if (n == "x")
            continue;
          auto spec = find_spec(specs_, n);
          if (!spec || (spec->type != ParamType::Real && spec->type != ParamType::Int))
            diag_.error(line_of(*t.get("expr")), where + " expr: unknown name '" + n + "' in \"" +
                                                     *expr +
                                                     "\"; use x and the case's numeric parameters");
        }
      } catch (const ExprError& e) {
        diag_.error(line_of(*t.get("expr")), where + " expr: " + e.what() + " in \"" + *expr +
                                                 "\" at character " +
                                                 std::to_string(e.position() + 1));
      }
      if (t.get("x") || t.get("y"))
        diag_.error(r.line, where + ": x and y name CSV columns; an expr reference has none");
    }
    if (csv) {
      r.csv = std::filesystem::path(file_).parent_path() / *csv;
      auto x = str(t, "x", where), y = str(t, "y", where);
      if (!x || !y) {
        diag_.error(r.line, where + ": a csv reference needs x = \"column\" and y = \"column\"");
      } else {
        r.csv_x = *x;
        r.csv_y = *y;
        try {
          auto table = read_reference_csv(r.csv);
          for (const auto& c : {r.csv_x, r.csv_y})
            if (std::find(table.columns.begin(), table.columns.end(), c) == table.columns.end())
              diag_.error(r.line, where + ": " + r.csv.string() + " has no column '" + c + "'" +
                                      did_you_mean(c, table.columns) +
                                      "; columns: " + quoted_list(table.columns));
        } catch (const std::exception& e) {
          diag_.error(line_of(*t.get("csv")), where + " csv: " + e.what());
        }
      }
    }
    if (auto s = str(t, "style", where)) {
      r.style = *s;
      one_of(r.style, {"line", "points"}, line_of(*t.get("style")), where + " style");
    } else {
      r.style = r.expr ? "line" : "points";
    }
    if (diag_.size() != errors)
      return std::nullopt;
    return r;
  }
};

// A reference file's fields (RFC 4180, commands.hpp), trimmed of blanks and a carriage return.
std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out = csv_split(line);
  for (auto& s : out) {
    auto b = s.find_first_not_of(" \t\r");
    auto e = s.find_last_not_of(" \t\r");
    s = b == std::string::npos ? "" : s.substr(b, e - b + 1);
  }
  return out;
}

} // namespace

CsvTable read_reference_csv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot read " + path.string());
  CsvTable t;
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#')
      continue;
    auto cells = split_csv_line(line);
    if (t.columns.empty()) {
      t.columns = cells;
      continue;
    }
    if (cells.size() != t.columns.size())
      throw std::runtime_error(path.string() + ":" + std::to_string(lineno) + ": expected " +
                               std::to_string(t.columns.size()) + " fields, got " +
                               std::to_string(cells.size()));
    std::vector<double> row;
    for (const auto& c : cells) {
      char* end = nullptr;
      double v = std::strtod(c.c_str(), &end);
      if (c.empty() || *end)
        throw std::runtime_error(path.string() + ":" + std::to_string(lineno) + ": '" + c +
                                 "' is not a number");
      row.push_back(v);
    }
    t.rows.push_back(std::move(row));
  }
  if (t.columns.empty())
    throw std::runtime_error(path.string() + ": no header row");
  return t;
}

std::vector<FigureSpec> parse_figures_node(const toml::node& figures,
                                           const std::vector<ParamSpec>& specs,
                                           const std::string& file, Diagnostics& diag) {
  FigureParser p(specs, file, diag);
  return p.parse(figures);
}

std::vector<FigureSpec> parse_figures_text(const std::string& text, const std::string& file,
                                           const std::vector<ParamSpec>& specs) {
  Diagnostics diag(file);
  toml::table root;
  try {
    root = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    diag.error(static_cast<int>(e.source().begin.line),
               "TOML syntax error: " + std::string(e.description()));
    diag.throw_if_any();
  }
  std::vector<FigureSpec> out;
  if (auto n = root.get("figures"))
    out = parse_figures_node(*n, specs, file, diag);
  diag.throw_if_any();
  return out;
}

std::vector<FigureSpec> load_figures(const std::filesystem::path& study_file,
                                     const std::vector<ParamSpec>& specs) {
  return parse_figures_text(read_file(study_file), study_file.string(), specs);
}

} // namespace sph::runner
