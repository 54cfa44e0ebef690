// `runner report`: reads a study's jobs and metrics from the database, aggregates them per figure,
// fits slopes, draws the figures with gnuplot and writes a static HTML page with every table.
#include "report.hpp"

#include "cases/case.hpp"
#include "commands.hpp"
#include "diagnostics.hpp"
#include "io/hdf5.hpp"
#include "params.hpp"
#include "provenance.hpp"
#include "search.hpp"
#include "store.hpp"
#include "study.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace sph::runner {

namespace fs = std::filesystem;
using nlohmann::json;

double LineFit::eval(double x) const {
  return kind == "power" ? std::exp(intercept) * std::pow(x, slope) : intercept + slope * x;
}

std::optional<LineFit> fit_points(const std::string& kind, const std::vector<double>& xs,
                                  const std::vector<double>& ys) {
  std::vector<double> u, v;
  LineFit f;
  f.kind = kind;
  f.x_min = std::numeric_limits<double>::infinity();
  f.x_max = -f.x_min;
  for (std::size_t i = 0; i < xs.size() && i < ys.size(); ++i) {
    double x = xs[i], y = ys[i];
    if (!std::isfinite(x) || !std::isfinite(y))
      continue;
    if (kind == "power") {
      if (x <= 0 || y <= 0)
        continue;
      u.push_back(std::log(x));
      v.push_back(std::log(y));
    } else {
      u.push_back(x);
      v.push_back(y);
    }
    f.x_min = std::min(f.x_min, x);
    f.x_max = std::max(f.x_max, x);
  }
  f.n = u.size();
  if (f.n < 2)
    return std::nullopt;
  double mu = 0, mv = 0;
  for (std::size_t i = 0; i < f.n; ++i)
    mu += u[i], mv += v[i];
  mu /= static_cast<double>(f.n);
  mv /= static_cast<double>(f.n);
  double suu = 0, suv = 0, svv = 0;
  for (std::size_t i = 0; i < f.n; ++i) {
    suu += (u[i] - mu) * (u[i] - mu);
    suv += (u[i] - mu) * (v[i] - mv);
    svv += (v[i] - mv) * (v[i] - mv);
  }
  if (suu <= 0)
    return std::nullopt;
  f.slope = suv / suu;
  f.intercept = mv - f.slope * mu;
  f.r2 = svv > 0 ? suv * suv / (suu * svv) : 1.0;
  return f;
}

namespace {

struct Job {
  std::int64_t id = 0;
  std::string key, state, scheme, output_dir;
  json params; // identity params, plus "scheme" when the case has schemes
  std::map<std::string, std::optional<double>> metrics;
};

// A study that declares no [[figures]]: each of its metrics (the case's declared ones, else every
// metric its done jobs recorded but the time loop's costs and the scheme's counters; at most 12)
// against the first swept parameter that varies among the jobs shown, one curve per value of the
// next varying one. None when no parameter varies.
std::vector<FigureSpec> default_figures(const Study& study, const std::vector<Job>& jobs) {
  auto varies = [&](const std::string& name) {
    std::set<std::string> v;
    for (const Job& j : jobs)
      v.insert(j.params.contains(name) ? j.params[name].dump() : "");
    return v.size() > 1;
  };
  std::vector<std::string> axes;
  for (const Axis& a : study.sweep)
    if (varies(a.name))
      axes.push_back(a.name);
  if (axes.empty())
    return {};
  std::vector<std::string> metrics;
  const CaseInfo* info = find_case(study.case_name);
  if (info && !info->metrics.empty()) {
    for (const auto& m : info->metrics)
      metrics.push_back(m.name);
  } else {
    std::set<std::string> skip;
    for (const auto& m : flow_loop_metrics())
      skip.insert(m.name);
    for (const auto& sch : scheme_registry())
      for (const auto& m : sch.metrics)
        skip.insert(m.name);
    std::set<std::string> seen;
    for (const Job& j : jobs)
      if (j.state == "done")
        for (const auto& [name, v] : j.metrics)
          if (v && !skip.count(name) && seen.insert(name).second)
            metrics.push_back(name);
  }
  if (metrics.size() > 12)
    metrics.resize(12);
  std::vector<FigureSpec> out;
  for (const std::string& m : metrics) {
    FigureSpec f;
    f.name = "default_" + m;
    f.title = m + " against " + axes[0] + " (default figure: the study declares none)";
    f.x = axes[0];
    f.y = {m};
    if (axes.size() > 1)
      f.group = {axes[1]};
    for (const Job& j : jobs)
      if (j.params.contains(axes[0]) && j.params[axes[0]].is_string())
        f.x_is_string = true;
    out.push_back(std::move(f));
  }
  return out;
}

std::string html(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
    case '&':
      o += "&amp;";
      break;
    case '<':
      o += "&lt;";
      break;
    case '>':
      o += "&gt;";
      break;
    case '"':
      o += "&quot;";
      break;
    case '\'':
      o += "&#39;";
      break;
    default:
      o += c;
    }
  }
  return o;
}

std::string short_num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string plain(const json& v) {
  if (v.is_string())
    return v.get<std::string>();
  if (v.is_number_float())
    return format_real(v.get<double>());
  if (v.is_null())
    return "-";
  return v.dump();
}

// Orders JSON values: numbers numerically before strings.
bool json_less(const json& a, const json& b) {
  if (a.is_number() != b.is_number())
    return a.is_number();
  if (a.is_number())
    return a.get<double>() < b.get<double>();
  return plain(a) < plain(b);
}

struct JsonVecLess {
  bool operator()(const std::vector<json>& a, const std::vector<json>& b) const {
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
      if (json_less(a[i], b[i]))
        return true;
      if (json_less(b[i], a[i]))
        return false;
    }
    return a.size() < b.size();
  }
};

double aggregate(const std::string& agg, std::vector<double> v) {
  if (agg == "min")
    return *std::min_element(v.begin(), v.end());
  if (agg == "max")
    return *std::max_element(v.begin(), v.end());
  if (agg == "median") {
    std::sort(v.begin(), v.end());
    std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  }
  double s = 0;
  for (double x : v)
    s += x;
  return s / static_cast<double>(v.size());
}

std::string group_label(const std::vector<std::string>& names, const std::vector<json>& values) {
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i)
    s += (i ? ", " : "") + names[i] + "=" + plain(values[i]);
  return s;
}

// One cell of a pivot table: the aggregated value and what went into it.
struct Cell {
  double value = 0, lo = 0, hi = 0;
  std::size_t n = 0;
};

// What the page shows of one figure.
struct FigureReport {
  FigureData data;
  std::vector<std::vector<json>> groups; // group values, by group index
  std::vector<json> xs;                  // x values (metric figures), sorted
  // pivot[y][group][x index] (metric figures)
  std::vector<std::vector<std::map<std::size_t, Cell>>> pivot;
  std::vector<const Job*> marked;           // jobs drawn as markers
  std::size_t jobs_used = 0;                // jobs matching `where`
  std::vector<std::string> problems;        // e.g. unreadable HDF5 files
  std::vector<std::string> series_rows;     // series figures: per-job summary rows (HTML)
  std::string image;                        // file name when drawn
  std::string image_note;                   // why there is no image
  std::optional<ConvergeTable> convergence; // kind = "convergence": the `runner converge` table
};

bool matches(const FigureSpec& f, const Job& j) {
  for (const auto& w : f.where) {
    const json v = j.params.contains(w.param) ? j.params[w.param] : json();
    bool any = false;
    for (const auto& allowed : w.values)
      any = any || value_to_json(allowed) == v;
    if (!any)
      return false;
  }
  return true;
}

json param_of(const Job& j, const std::string& name) {
  return j.params.contains(name) ? j.params[name] : json();
}

void sample_references(const FigureSpec& f, FigureReport& r, const std::vector<const Job*>& jobs) {
  // The x range of the data (used to sample analytic references).
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& c : r.data.curves)
    for (const auto& p : c.points)
      if (!f.log_x || p.x > 0)
        lo = std::min(lo, p.x), hi = std::max(hi, p.x);
  for (const auto& ref : f.references) {
    if (!ref.expr) {
      RefCurve rc{ref.label, ref.style, {}};
      try {
        auto t = read_reference_csv(ref.csv);
        auto ix = std::find(t.columns.begin(), t.columns.end(), ref.csv_x) - t.columns.begin();
        auto iy = std::find(t.columns.begin(), t.columns.end(), ref.csv_y) - t.columns.begin();
        if (ix >= static_cast<long>(t.columns.size()) || iy >= static_cast<long>(t.columns.size()))
          throw std::runtime_error(ref.csv.string() + " lacks column '" + ref.csv_x + "' or '" +
                                   ref.csv_y + "'");
        for (const auto& row : t.rows)
          rc.points.emplace_back(row[ix], row[iy]);
      } catch (const std::exception& e) {
        r.problems.push_back("reference '" + ref.label + "': " + e.what());
      }
      r.data.references.push_back(std::move(rc));
      continue;
    }
    if (!(lo < hi))
      continue;
    // One curve, or one per group when the expression uses parameters.
    bool uses_params = false;
    for (const auto& n : ref.expr->names())
      uses_params = uses_params || n != "x";
    std::vector<std::pair<std::string, const Job*>> instances;
    if (!uses_params) {
      instances.push_back({ref.label, nullptr});
    } else {
      // One curve per distinct value of the parameters the expression uses (groups that share
      // them share the curve, drawn once).
      std::set<std::vector<json>, JsonVecLess> seen;
      for (std::size_t g = 0; g < r.groups.size(); ++g)
        for (const Job* j : jobs) {
          bool same = true;
          for (std::size_t k = 0; k < f.group.size(); ++k)
            same = same && param_of(*j, f.group[k]) == r.groups[g][k];
          if (!same)
            continue;
          std::vector<json> used;
          for (const auto& n : ref.expr->names())
            if (n != "x")
              used.push_back(param_of(*j, n));
          if (seen.insert(used).second)
            instances.push_back(
                {ref.label +
                     (f.group.empty() ? "" : " (" + group_label(f.group, r.groups[g]) + ")"),
                 j});
          break;
        }
      if (instances.size() == 1)
        instances.front().first = ref.label;
    }
    for (const auto& [label, job] : instances) {
      RefCurve rc{label, ref.style, {}};
      const int n = 100;
      try {
        for (int k = 0; k <= n; ++k) {
          double t = static_cast<double>(k) / n;
          double x = f.log_x ? lo * std::pow(hi / lo, t) : lo + t * (hi - lo);
          double y = ref.expr->eval([&](const std::string& name) -> std::optional<double> {
            if (name == "x")
              return x;
            if (job && job->params.contains(name) && job->params[name].is_number())
              return job->params[name].get<double>();
            return std::nullopt;
          });
          if (std::isfinite(y) && (!f.log_y || y > 0))
            rc.points.emplace_back(x, y);
        }
      } catch (const std::exception& e) {
        r.problems.push_back("reference '" + ref.label + "': " + e.what());
        rc.points.clear();
      }
      r.data.references.push_back(std::move(rc));
    }
  }
}

// The jobs a figure draws: those its `where` selects that have finished (any final state).
std::vector<const Job*> finished_jobs_of(const FigureSpec& f, const std::vector<Job>& all) {
  std::vector<const Job*> jobs;
  for (const auto& j : all)
    if (matches(f, j) && j.state != "pending" && j.state != "running" && j.state != "submitted")
      jobs.push_back(&j);
  return jobs;
}

// A convergence figure's table: `runner converge` over the figure's finished (done) jobs, so the
// report and the command agree on the same jobs.
std::optional<ConvergeTable> convergence_of(const FigureSpec& f, const std::string& study,
                                            const std::vector<Job>& all) {
  ConvergeOptions c;
  c.study = study, c.param = f.x, c.metric = f.y.front(), c.kind = *f.convergence;
  c.resolution = f.resolution, c.formal_order = f.formal_order, c.ignore = f.ignore;
  std::vector<ConvergeRow> rows;
  for (const Job* j : finished_jobs_of(f, all)) {
    const auto m = j->metrics.find(c.metric);
    const auto x = j->params.find(f.x);
    if (j->state != "done" || m == j->metrics.end() || !m->second || x == j->params.end() ||
        !x->is_number())
      continue;
    ConvergeRow row{x->get<double>(), *m->second, {}};
    for (const auto& [k, v] : j->params.items())
      row.params[k] = v.dump();
    rows.push_back(std::move(row));
  }
  if (rows.empty())
    return std::nullopt;
  return converge_table(rows, c);
}

// Why a figure has no data, in the words of its declaration: no finished job at all, none with the
// `where` values, none with its metrics, or none with its HDF5 file.
std::string why_no_data(const FigureSpec& f, const std::vector<Job>& all, const std::string& tier) {
  const std::string of_tier = tier.empty() ? "" : " of tier " + tier;
  std::size_t finished = 0;
  for (const auto& j : all)
    finished += j.state != "pending" && j.state != "running" && j.state != "submitted";
  if (finished == 0)
    return "No data yet: no job" + of_tier + " has finished.";
  const std::vector<const Job*> jobs = finished_jobs_of(f, all);
  if (jobs.empty()) {
    std::string w;
    for (const auto& v : f.where) {
      w += (w.empty() ? "" : " and ") + v.param + " = ";
      for (std::size_t k = 0; k < v.values.size(); ++k)
        w += (k ? " or " : "") + value_to_json(v.values[k]).dump();
    }
    return "No data: none of the " + std::to_string(finished) + " finished jobs" + of_tier +
           " has " + w + ".";
  }
  if (f.kind == "series") {
    std::size_t with_dir = 0;
    for (const Job* j : jobs)
      with_dir += !j->output_dir.empty();
    return "No data: none of the " + std::to_string(jobs.size()) + " matching finished jobs" +
           of_tier + " has readable datasets " + f.x + " and " + f.y.front() + " in " + f.file +
           (with_dir ? "" : " (no job has an output folder)") + ".";
  }
  std::string ys;
  for (const auto& y : f.y)
    ys += (ys.empty() ? "" : ", ") + y;
  return "No data: none of the " + std::to_string(jobs.size()) + " matching finished jobs" +
         of_tier + " recorded " + ys + ".";
}

FigureReport build_metric_figure(const FigureSpec& f, const std::vector<Job>& all) {
  FigureReport r;
  r.data.spec = &f;
  const std::vector<const Job*> jobs = finished_jobs_of(f, all);
  r.jobs_used = jobs.size();
  // Groups and x values, in numeric order.
  std::map<std::vector<json>, std::size_t, JsonVecLess> group_index;
  std::set<std::vector<json>, JsonVecLess> xset;
  for (const Job* j : jobs) {
    std::vector<json> g;
    for (const auto& name : f.group)
      g.push_back(param_of(*j, name));
    group_index.emplace(g, 0);
    std::vector<json> xv;
    xv.push_back(param_of(*j, f.x));
    xset.insert(std::move(xv));
  }
  for (auto& [g, idx] : group_index) {
    idx = r.groups.size();
    r.groups.push_back(g);
  }
  for (const auto& x : xset)
    r.xs.push_back(x[0]);
  auto x_index = [&](const json& x) {
    for (std::size_t i = 0; i < r.xs.size(); ++i)
      if (r.xs[i] == x)
        return i;
    return r.xs.size();
  };
  if (f.x_is_string)
    for (const auto& x : r.xs)
      r.data.x_categories.push_back(plain(x));
  auto x_value = [&](std::size_t xi) {
    return f.x_is_string ? static_cast<double>(xi)
                         : (r.xs[xi].is_number() ? r.xs[xi].get<double>() : std::nan(""));
  };

  // values[y][group][x] = the jobs' values
  std::vector<std::vector<std::map<std::size_t, std::vector<double>>>> values(
      f.y.size(), std::vector<std::map<std::size_t, std::vector<double>>>(r.groups.size()));
  for (const Job* j : jobs) {
    std::vector<json> g;
    for (const auto& name : f.group)
      g.push_back(param_of(*j, name));
    std::size_t gi = group_index[g];
    std::size_t xi = x_index(param_of(*j, f.x));
    if (std::find(f.mark.begin(), f.mark.end(), j->state) != f.mark.end()) {
      r.marked.push_back(j);
      r.data.markers.push_back({x_value(xi), gi, j->state});
      continue;
    }
    if (j->state != "done")
      continue;
    for (std::size_t yi = 0; yi < f.y.size(); ++yi) {
      auto it = j->metrics.find(f.y[yi]);
      if (it != j->metrics.end() && it->second && std::isfinite(*it->second))
        values[yi][gi][xi].push_back(*it->second);
    }
  }
  r.pivot.assign(f.y.size(), std::vector<std::map<std::size_t, Cell>>(r.groups.size()));
  for (std::size_t yi = 0; yi < f.y.size(); ++yi) {
    for (std::size_t gi = 0; gi < r.groups.size(); ++gi) {
      Curve c;
      c.y = f.y[yi];
      // Colour by the first group parameter; point and dash type by the metric and the rest.
      c.group = gi;
      c.y_index = yi;
      if (f.group.size() > 1) {
        std::vector<json> firsts, rests;
        for (const auto& g : r.groups) {
          if (std::find(firsts.begin(), firsts.end(), g[0]) == firsts.end())
            firsts.push_back(g[0]);
          json rest(std::vector<json>(g.begin() + 1, g.end()));
          if (std::find(rests.begin(), rests.end(), rest) == rests.end())
            rests.push_back(rest);
        }
        json rest(std::vector<json>(r.groups[gi].begin() + 1, r.groups[gi].end()));
        c.group = static_cast<std::size_t>(
            std::find(firsts.begin(), firsts.end(), r.groups[gi][0]) - firsts.begin());
        c.y_index =
            yi * rests.size() +
            static_cast<std::size_t>(std::find(rests.begin(), rests.end(), rest) - rests.begin());
      }
      c.label = group_label(f.group, r.groups[gi]);
      if (f.y.size() > 1 || c.label.empty())
        c.label += (c.label.empty() ? "" : ": ") + f.y[yi];
      std::vector<double> fx, fy;
      for (const auto& [xi, v] : values[yi][gi]) {
        Cell cell{aggregate(f.agg, v), *std::min_element(v.begin(), v.end()),
                  *std::max_element(v.begin(), v.end()), v.size()};
        r.pivot[yi][gi][xi] = cell;
        double x = x_value(xi);
        if (!std::isfinite(x) || (f.log_x && x <= 0) || (f.log_y && cell.value <= 0))
          continue;
        c.points.push_back({x, cell.value, cell.lo, cell.hi, cell.n});
        if (!f.fit_range || (x >= f.fit_range->first && x <= f.fit_range->second))
          fx.push_back(x), fy.push_back(cell.value);
      }
      if (f.fit != "none")
        c.fit = fit_points(f.fit, fx, fy);
      r.data.curves.push_back(std::move(c));
    }
  }
  sample_references(f, r, jobs);
  return r;
}

FigureReport build_series_figure(const FigureSpec& f, const std::vector<Job>& all) {
  FigureReport r;
  r.data.spec = &f;
  const std::vector<const Job*> jobs = finished_jobs_of(f, all);
  r.jobs_used = jobs.size();
  std::map<std::vector<json>, std::size_t, JsonVecLess> group_index;
  for (const Job* j : jobs) {
    std::vector<json> g;
    for (const auto& name : f.group)
      g.push_back(param_of(*j, name));
    group_index.emplace(g, 0);
  }
  for (auto& [g, idx] : group_index) {
    idx = r.groups.size();
    r.groups.push_back(g);
  }
  for (const Job* j : jobs) {
    std::vector<json> g;
    for (const auto& name : f.group)
      g.push_back(param_of(*j, name));
    std::size_t gi = group_index[g];
    std::string label = group_label(f.group, g);
    std::string row = "<tr><td><code>" + html(j->key.substr(0, 12)) + "</code></td><td>" +
                      html(j->state) + "</td><td>" + html(label) + "</td>";
    if (j->output_dir.empty()) {
      r.series_rows.push_back(row + "<td colspan=\"3\">no output directory</td></tr>");
      continue;
    }
    fs::path file = fs::path(j->output_dir) / f.file;
    try {
      auto xv = sph::io::read_dataset(file, f.x);
      for (std::size_t yi = 0; yi < f.y.size(); ++yi) {
        auto yv = sph::io::read_dataset(file, f.y[yi]);
        Curve c;
        c.y = f.y[yi];
        c.group = gi;
        c.y_index = yi;
        c.label = label;
        if (f.y.size() > 1 || c.label.empty())
          c.label += (c.label.empty() ? "" : ": ") + f.y[yi];
        for (std::size_t k = 0; k < xv.size() && k < yv.size(); ++k)
          if (std::isfinite(xv[k]) && std::isfinite(yv[k]) && (!f.log_x || xv[k] > 0) &&
              (!f.log_y || yv[k] > 0))
            c.points.push_back({xv[k], yv[k], yv[k], yv[k], 1});
        row += "<td>" + html(f.y[yi]) + "</td><td>" + std::to_string(c.points.size()) +
               "</td><td class=\"num\">" +
               (c.points.empty() ? "" : html(short_num(c.points.back().y))) + "</td>";
        r.data.curves.push_back(std::move(c));
      }
      r.series_rows.push_back(row + "</tr>");
    } catch (const std::exception& e) {
      r.problems.push_back("job " + j->key.substr(0, 12) + ": " + e.what());
      r.series_rows.push_back(row + "<td colspan=\"3\">" + html(e.what()) + "</td></tr>");
    }
    if (std::find(f.mark.begin(), f.mark.end(), j->state) != f.mark.end())
      r.marked.push_back(j);
  }
  sample_references(f, r, jobs);
  return r;
}

std::string utc_now() {
  std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&t));
  return buf;
}

const char* const css = R"(body{font-family:system-ui,sans-serif;margin:2em auto;max-width:1100px;
color:#222;padding:0 1em}h1{margin-bottom:.2em}h2{margin-top:2em;border-bottom:1px solid #ccc}
.meta{color:#555;font-size:.9em}.notice{background:#fff4e5;border-left:4px solid #f0a020;
padding:.5em 1em;margin:1em 0}table{border-collapse:collapse;margin:.8em 0;font-size:.9em}
th,td{border:1px solid #ccc;padding:.25em .6em}th{background:#f3f3f3}td.num{text-align:right;
font-variant-numeric:tabular-nums}figure{margin:1em 0}figure img{max-width:100%;height:auto;
border:1px solid #ddd}figcaption{color:#555;font-size:.9em}.small{font-size:.85em;color:#555}
)";

} // namespace

// Temporary files a killed report left (an image being drawn, the script gnuplot ran, a file
// being written): a later report removes them before it writes its own.
static void remove_leftover_temporaries(const fs::path& out_dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(out_dir, ec)) {
    const std::string n = e.path().filename().string();
    auto ends = [&](const std::string& suffix) {
      return n.size() > suffix.size() &&
             n.compare(n.size() - suffix.size(), suffix.size(), suffix) == 0;
    };
    const bool temporary = n.find(".tmp.") != std::string::npos || ends(".tmp") || ends(".run.gp");
    std::error_code rm;
    if (temporary && e.is_regular_file(rm))
      fs::remove(e.path(), rm);
  }
}

int cmd_report(const ReportOptions& o, std::ostream& out) {
  if (o.image_format != "svg" && o.image_format != "png")
    throw std::runtime_error("--image-format must be svg or png");
  Store store = Store::open_read(o.db);

  // The study: a file, or a name recorded in the database (then its recorded file).
  std::error_code ec;
  fs::path study_file;
  std::string by_name;
  if (fs::is_regular_file(o.study, ec)) {
    study_file = o.study;
  } else {
    auto recorded = store.find_study(o.study);
    if (!recorded) {
      std::vector<std::string> names = store.study_names();
      throw std::runtime_error("'" + o.study + "' is neither a study file nor a study in " +
                               o.db.string() + did_you_mean(o.study, names) +
                               (names.empty() ? "" : "; studies: " + quoted_list(names)));
    }
    study_file = recorded->file;
    by_name = o.study;
  }
  Study study = load_study(study_file);
  std::vector<FigureSpec> figures = load_figures(study_file, study.specs);

  auto recorded = store.find_study(study.name);
  if (!recorded)
    throw std::runtime_error("study '" + study.name + "' (" + study_file.string() +
                             ") has no jobs in " + o.db.string() + "; run it first: runner " +
                             study_file.string() + " --db " + o.db.string());
  const std::int64_t sid = recorded->id;
  const bool definition_changed = recorded->definition_sha256 != study.definition_sha256;
  const std::optional<std::string> tier =
      o.tier.empty() ? std::nullopt : std::optional<std::string>(o.tier);

  // Jobs of the study (or tier) in expansion order, with their metrics.
  std::vector<Job> jobs;
  {
    for (const StudyJob& s :
         store.study_jobs(sid, tier, false, solver_fingerprint(study.case_name))) {
      Job j;
      j.id = s.id;
      j.key = s.key;
      j.state = to_string(s.state);
      j.scheme = s.scheme;
      j.params = json::parse(s.params_json);
      j.output_dir = s.output_dir;
      if (!j.scheme.empty() && !j.params.contains(scheme_param))
        j.params[scheme_param] = j.scheme;
      jobs.push_back(std::move(j));
    }
    if (jobs.empty() && !o.tier.empty())
      throw std::runtime_error("study '" + study.name + "' has no jobs in tier '" + o.tier + "'");
    std::map<std::int64_t, Job*> by_id;
    for (auto& j : jobs)
      by_id[j.id] = &j;
    for (const MetricValue& m : store.study_metrics(sid))
      if (auto it = by_id.find(m.job_id); it != by_id.end())
        it->second->metrics[m.name] = m.value;
  }
  std::map<std::string, std::size_t> states;
  for (const auto& j : jobs)
    ++states[j.state];
  const bool declared = !figures.empty();
  if (!declared)
    figures = default_figures(study, jobs);

  fs::path out_dir = o.out_dir;
  if (out_dir.empty())
    out_dir = o.db.parent_path() / "report" / study.name;
  fs::create_directories(out_dir);
  remove_leftover_temporaries(out_dir);

  std::vector<std::string> notices;
  // Stale results (made by other solver code than this build's) are shown, and said so.
  if (std::size_t n = store.stale_in_study(sid, solver_fingerprint(study.case_name), tier, false))
    notices.push_back(std::to_string(n) +
                      " of the jobs shown are stale: their results were computed by other "
                      "solver code than this build's (solver fingerprint " +
                      solver_fingerprint(study.case_name) +
                      "). Run the study with --rerun-stale to recompute them.");
  if (definition_changed)
    notices.push_back("The study file changed since the study was last run (its SHA-256 differs "
                      "from the one recorded in the database): figures use the file's current "
                      "declarations and the database's jobs.");
  std::string program;
  auto version = gnuplot_version(&program);
  if (!version && !figures.empty())
    notices.push_back("Figures were not drawn: gnuplot was not found (install the Debian "
                      "package gnuplot-nox, or point SPH_GNUPLOT at it). The tables below hold "
                      "all the numbers.");

  std::vector<FigureReport> reports;
  std::size_t drawn = 0, unchanged = 0, failed = 0;
  for (const auto& f : figures) {
    FigureReport r =
        f.kind == "series" ? build_series_figure(f, jobs) : build_metric_figure(f, jobs);
    if (f.convergence)
      r.convergence = convergence_of(f, study.name, jobs);
    std::string image = f.name + "." + o.image_format;
    std::string script = gnuplot_script(r.data, image, o.image_format);
    // The data as CSV, for readers who want the numbers behind the figure.
    {
      std::ostringstream csv;
      csv << "curve,y,x,value,min,max,n\n";
      for (const auto& c : r.data.curves)
        for (const auto& p : c.points) {
          std::string xs = r.data.x_categories.empty()
                               ? format_real(p.x)
                               : r.data.x_categories[static_cast<std::size_t>(p.x)];
          csv << "\"" << c.label << "\"," << c.y << "," << xs << "," << format_real(p.y) << ","
              << format_real(p.lo) << "," << format_real(p.hi) << "," << p.n << "\n";
        }
      std::ofstream(out_dir / (f.name + ".csv")) << csv.str();
    }
    if (script.empty()) {
      r.image_note = why_no_data(f, jobs, o.tier);
    } else if (!version) {
      r.image_note = "Not drawn: gnuplot is not installed.";
      std::ofstream(out_dir / (f.name + ".gp")) << script;
    } else {
      DrawOutcome d = draw_figure(program, *version, out_dir, f.name, script, o.image_format);
      if (d.drawn || d.unchanged) {
        r.image = image;
        drawn += d.drawn;
        unchanged += d.unchanged;
      } else {
        ++failed;
        r.image_note = "Drawing failed: " + d.error;
      }
    }
    reports.push_back(std::move(r));
  }

  // ---- the page ----
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>"
    << html(study.name) << " report</title>\n<meta name=\"viewport\" "
    << "content=\"width=device-width, initial-scale=1\">\n<style>" << css << "</style></head>\n"
    << "<body>\n<h1>" << html(study.name) << "</h1>\n";
  if (!study.description.empty())
    h << "<p>" << html(study.description) << "</p>\n";
  std::string state_text;
  for (const auto& [s, n] : states)
    state_text += (state_text.empty() ? "" : ", ") + std::to_string(n) + " " + s;
  h << "<p class=\"meta\">case <code>" << html(study.case_name)
    << "</code> &middot; study file <code>" << html(study_file.string())
    << "</code> &middot; database <code>" << html(o.db.string()) << "</code>"
    << (o.tier.empty() ? "" : " &middot; tier <code>" + html(o.tier) + "</code>") << "<br>"
    << jobs.size() << " jobs: " << html(state_text) << " &middot; generated " << utc_now()
    << " by runner " << html(code_version()) << (version ? " with " + html(*version) : "")
    << "</p>\n";
  for (const auto& n : notices)
    h << "<p class=\"notice\">" << html(n) << "</p>\n";
  if (!declared)
    h << "<p class=\"notice\">This study declares no figures"
      << (figures.empty() ? "" : ": each metric against the first swept parameter below")
      << "; add [[figures]] tables to " << html(study_file.string())
      << " to choose them (see docs/report.md).</p>\n";
  if (!figures.empty()) {
    h << "<ul>\n";
    for (const auto& f : figures)
      h << "<li><a href=\"#" << html(f.name) << "\">" << html(f.title.empty() ? f.name : f.title)
        << "</a></li>\n";
    h << "</ul>\n";
  }

  // A study with [search]: the bracket of every group (as the search and --dry-run print them).
  if (study.search) {
    RunOptions ro;
    ro.db_path = o.db, ro.tier = o.tier;
    const Search& s = *study.search;
    h << "<section id=\"search\" class=\"figure\">\n<h2>Stability edge of " << html(s.param)
      << "</h2>\n<table class=\"search\"><caption>"
      << html("Bisection between lo = " + format_real(s.lo) +
              " (stable) and hi = " + format_real(s.hi) +
              " (unstable) until |edge_hi - edge_lo| <= " + format_real(s.until) + " edge_lo" +
              (s.log ? ", on a log scale" : "") + "; each probe is a job of the study")
      << "</caption>\n<tr><th>group</th><th>probes</th><th>edge_lo (stable)</th>"
      << "<th>edge_hi (unstable)</th><th>state</th></tr>\n";
    for (const GroupBracket& g : search_brackets(study, ro, &store)) {
      const Bracket& b = g.bracket;
      h << "<tr><td>" << html(g.label) << "</td><td class=\"num\">" << b.probes
        << "</td><td class=\"num\">" << (b.a ? html(format_real(*b.a)) : "")
        << "</td><td class=\"num\">" << (b.b ? html(format_real(*b.b)) : "") << "</td><td>"
        << html(b.state + (b.non_monotone ? "; a stable probe lies beyond edge_hi" : "") +
                (b.next ? "; next probe " + format_real(*b.next) : ""))
        << "</td></tr>\n";
    }
    h << "</table>\n</section>\n";
  }

  for (const auto& r : reports) {
    const FigureSpec& f = *r.data.spec;
    h << "<section id=\"" << html(f.name) << "\" class=\"figure\">\n<h2>"
      << html(f.title.empty() ? f.name : f.title) << "</h2>\n";
    std::string filter;
    for (const auto& w : f.where) {
      std::string vals;
      for (const auto& v : w.values)
        vals += (vals.empty() ? "" : " or ") + format_value_plain(v);
      filter += (filter.empty() ? "" : ", ") + w.param + " = " + vals;
    }
    if (!r.image.empty())
      h << "<figure><img src=\"" << html(r.image) << "\" alt=\""
        << html(f.title.empty() ? f.name : f.title) << "\">\n";
    else
      h << "<figure><p class=\"notice\">" << html(r.image_note) << "</p>\n";
    h << "<figcaption>" << html(f.kind == "series" ? "series " : "")
      << html(f.y.size() == 1 ? f.y[0] : "")
      << (f.y.size() > 1 ? html([&] {
           std::string s;
           for (const auto& y : f.y)
             s += (s.empty() ? "" : ", ") + y;
           return s;
         }())
                         : "")
      << " against " << html(f.x) << (f.group.empty() ? "" : "; one curve per " + html([&] {
                                                               std::string s;
                                                               for (const auto& g : f.group)
                                                                 s += (s.empty() ? "" : ", ") + g;
                                                               return s;
                                                             }()))
      << (filter.empty() ? "" : "; jobs with " + html(filter)) << "; "
      << (f.kind == "metric" ? html(f.agg) + " over the jobs sharing a point" +
                                   (f.spread ? " (bars: min to max)" : "")
                             : "from " + html(f.file) + " in each job's output directory")
      << ". " << r.jobs_used << " jobs. <a href=\"" << html(f.name)
      << ".csv\">data (CSV)</a> &middot; <a href=\"" << html(f.name)
      << ".gp\">gnuplot script</a></figcaption></figure>\n";
    for (const auto& p : r.problems)
      h << "<p class=\"notice\">" << html(p) << "</p>\n";

    // Fits.
    bool any_fit = false;
    for (const auto& c : r.data.curves)
      any_fit = any_fit || c.fit.has_value();
    if (f.fit != "none") {
      h << "<table class=\"fits\"><caption>"
        << (f.fit == "power" ? "Power-law fits y = C x<sup>p</sup> (least squares on log x, log y)"
                             : "Linear fits y = a + b x (least squares)")
        << (f.fit_range ? html(" over " + format_real(f.fit_range->first) +
                               " <= x <= " + format_real(f.fit_range->second))
                        : "")
        << "</caption>\n<tr><th>curve</th><th>" << (f.fit == "power" ? "slope p" : "slope b")
        << "</th><th>" << (f.fit == "power" ? "C" : "a")
        << "</th><th>R&sup2;</th><th>points</th></tr>\n";
      for (const auto& c : r.data.curves) {
        h << "<tr><td>" << html(c.label) << "</td>";
        if (c.fit)
          h << "<td class=\"num\" data-value=\"" << format_real(c.fit->slope) << "\">"
            << html(short_num(c.fit->slope)) << "</td><td class=\"num\">"
            << html(short_num(c.fit->kind == "power" ? std::exp(c.fit->intercept)
                                                     : c.fit->intercept))
            << "</td><td class=\"num\">" << html(short_num(c.fit->r2)) << "</td><td class=\"num\">"
            << c.fit->n << "</td></tr>\n";
        else
          h << "<td colspan=\"4\">fewer than two points</td></tr>\n";
      }
      h << "</table>\n";
    }
    (void)any_fit;

    if (f.convergence) {
      h << "<table class=\"convergence\" data-figure=\"" << html(f.name) << "\"><caption>"
        << html(*f.convergence == "self"
                    ? "Grid convergence of " + f.y.front() + " against " + f.x +
                          ": observed order from the three finest resolutions (Celik et al. "
                          "2008), Richardson extrapolation, GCI of the finest (Roache 1994; "
                          "Fs = 1.25, 3 with two resolutions)"
                    : "Order of the error " + f.y.front() + " against " + f.x +
                          ": from the finest pair and a least-squares fit of ln|error| against "
                          "ln h")
        << (r.convergence && r.convergence->count ? html(" (a count: h = 1/" + f.x + ")") : "")
        << "</caption>\n";
      if (!r.convergence)
        h << "<tr><td>no finished job with " << html(f.y.front()) << "</td></tr>\n";
      else {
        h << "<tr>";
        for (const auto& c : r.convergence->header)
          h << "<th>" << html(c) << "</th>";
        h << "</tr>\n";
        for (const auto& row : r.convergence->rows) {
          h << "<tr>";
          for (std::size_t k = 0; k < row.size(); ++k)
            h << (k < 2 || k + 1 == row.size() ? "<td>" : "<td class=\"num\">") << html(row[k])
              << "</td>";
          h << "</tr>\n";
        }
      }
      h << "</table>\n";
    }

    if (f.kind == "metric") {
      json base = json::object();
      for (const auto& w : f.where) {
        if (w.values.size() == 1)
          base[w.param] = value_to_json(w.values[0]);
        else {
          json arr = json::array();
          for (const auto& v : w.values)
            arr.push_back(value_to_json(v));
          base[w.param] = arr;
        }
      }
      for (std::size_t yi = 0; yi < f.y.size(); ++yi) {
        h << "<table class=\"pivot\" data-figure=\"" << html(f.name) << "\" data-metric=\""
          << html(f.y[yi]) << "\" data-agg=\"" << html(f.agg) << "\"><caption>" << html(f.agg)
          << "(" << html(f.y[yi]) << ")" << (filter.empty() ? "" : ", " + html(filter))
          << "</caption>\n<tr><th>" << html(f.x) << "</th>";
        for (std::size_t gi = 0; gi < r.groups.size(); ++gi)
          h << "<th>" << html(f.group.empty() ? f.y[yi] : group_label(f.group, r.groups[gi]))
            << "</th>";
        h << "</tr>\n";
        for (std::size_t xi = 0; xi < r.xs.size(); ++xi) {
          h << "<tr><th>" << html(plain(r.xs[xi])) << "</th>";
          for (std::size_t gi = 0; gi < r.groups.size(); ++gi) {
            auto it = r.pivot[yi][gi].find(xi);
            if (it == r.pivot[yi][gi].end()) {
              h << "<td class=\"num\"></td>";
              continue;
            }
            const Cell& c = it->second;
            json params = base;
            params[f.x] = r.xs[xi];
            for (std::size_t k = 0; k < f.group.size(); ++k)
              params[f.group[k]] = r.groups[gi][k];
            h << "<td class=\"num\" data-value=\"" << format_real(c.value) << "\" data-n=\"" << c.n
              << "\" data-params=\"" << html(params.dump()) << "\" title=\"" << c.n << " jobs, min "
              << html(short_num(c.lo)) << ", max " << html(short_num(c.hi)) << "\">"
              << html(short_num(c.value)) << "</td>";
          }
          h << "</tr>\n";
        }
        h << "</table>\n";
      }
    } else {
      h << "<table class=\"series\"><tr><th>job</th><th>state</th><th>group</th>";
      for (std::size_t yi = 0; yi < f.y.size(); ++yi)
        h << "<th>y</th><th>points</th><th>last value</th>";
      h << "</tr>\n";
      for (const auto& row : r.series_rows)
        h << row << "\n";
      h << "</table>\n";
    }
    if (!r.marked.empty()) {
      h << "<p class=\"small\">Marked (" << r.marked.size() << " jobs): ";
      for (std::size_t i = 0; i < r.marked.size(); ++i)
        h << (i ? ", " : "") << "<code>" << html(r.marked[i]->key.substr(0, 12)) << "</code> "
          << html(r.marked[i]->state);
      h << "</p>\n";
    }
    bool cited = false;
    for (const auto& ref : f.references)
      if (!ref.citation.empty()) {
        if (!cited)
          h << "<p class=\"small\">References: ";
        h << (cited ? "; " : "") << html(ref.label) << ": " << html(ref.citation);
        cited = true;
      }
    if (cited)
      h << "</p>\n";
    h << "</section>\n";
  }
  h << "<p class=\"small\">Every number on this page was read from the database when the page "
       "was generated; regenerate it with <code>runner report "
    << html(by_name.empty() ? study_file.string() : by_name) << " --db " << html(o.db.string())
    << "</code>.</p>\n</body></html>\n";

  fs::path index = out_dir / "index.html";
  fs::path tmp = out_dir / "index.html.tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f << h.str();
    f.flush();
    if (!f)
      throw std::runtime_error("cannot write " + tmp.string());
  }
  fs::rename(tmp, index);
  out << "report: " << index.string() << ": " << figures.size() << " figures (" << drawn
      << " drawn, " << unchanged << " unchanged"
      << (failed ? ", " + std::to_string(failed) + " failed" : "")
      << (!version && !figures.empty() ? ", gnuplot not found" : "") << "), " << jobs.size()
      << " jobs\n";
  return failed ? 1 : 0;
}

} // namespace sph::runner
