// Read-only commands over the store: query, status, cases, table, export, publish.
#include "commands.hpp"

#include "convergence.hpp"

#include "diagnostics.hpp"
#include "job_file.hpp"
#include "params.hpp"
#include "progress.hpp"
#include "provenance.hpp"
#include "store.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <variant>
#include <vector>

namespace sph::runner {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos)
    return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"')
      q += '"';
    q += c;
  }
  return q + "\"";
}

std::vector<std::string> csv_split(const std::string& line) {
  std::vector<std::string> f(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"')
        f.back() += '"', ++i;
      else if (c == '"')
        quoted = false;
      else
        f.back() += c;
    } else if (c == '"')
      quoted = true;
    else if (c == ',')
      f.emplace_back();
    else
      f.back() += c;
  }
  return f;
}

namespace {

std::string cell(const Stmt& s, int i) {
  switch (s.type(i)) {
  case SQLITE_NULL:
    return "";
  case SQLITE_INTEGER:
    return std::to_string(s.integer(i));
  case SQLITE_FLOAT: {
    std::string r = format_real(s.real(i));
    return r;
  }
  case SQLITE_BLOB: {
    // As an SQL blob literal (X'00ff...'), never raw bytes in the CSV.
    const auto* p = static_cast<const unsigned char*>(sqlite3_column_blob(s.handle(), i));
    const int n = sqlite3_column_bytes(s.handle(), i);
    static const char* hex = "0123456789abcdef";
    std::string r = "X'";
    for (int k = 0; k < n; ++k)
      r += hex[p[k] >> 4], r += hex[p[k] & 15];
    return r + "'";
  }
  default:
    return s.text(i);
  }
}

std::int64_t study_id(Store& store, const std::string& name) {
  if (auto st = store.find_study(name))
    return st->id;
  std::vector<std::string> names = store.study_names();
  throw std::runtime_error("no study named '" + name + "' in the database" +
                           did_you_mean(name, names) +
                           (names.empty() ? "" : "; studies: " + quoted_list(names)));
}

// This build's solver fingerprint of a recorded study's case (stale results).
std::string study_fingerprint(Store& store, const std::string& name) {
  const auto st = store.find_study(name);
  return solver_fingerprint(st ? st->case_name : std::string());
}

// The study's tiers a job belongs to, ';'-separated (export's and publish's `tier` column).
std::string joined_tiers(const StudyJob& j) {
  std::string tiers;
  for (const auto& t : j.tiers)
    tiers += (tiers.empty() ? "" : ";") + t;
  return tiers;
}

// The ';'-separated tiers of a, then those of b that a lacks.
std::string merged_tiers(const std::string& a, const std::string& b) {
  std::string out = a;
  std::set<std::string> seen;
  std::istringstream ia(a), ib(b);
  for (std::string t; std::getline(ia, t, ';');)
    seen.insert(t);
  for (std::string t; std::getline(ib, t, ';');)
    if (!t.empty() && seen.insert(t).second)
      out += (out.empty() ? "" : ";") + t;
  return out;
}

std::string json_path(const std::string& param) {
  for (char c : param)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_')
      throw std::runtime_error("bad parameter name '" + param + "'");
  return "$." + param;
}

} // namespace

int cmd_query(const std::filesystem::path& db_path, const std::string& sql, std::ostream& out,
              double timeout_s) {
  Store store = Store::open_read(db_path);
  Stmt s = store.prepare_read_query(sql);
  store.set_deadline(timeout_s);
  int n = s.columns();
  for (int i = 0; i < n; ++i)
    out << (i ? "," : "") << csv_field(s.column_name(i));
  out << "\n";
  try {
    while (out && s.step()) { // a failed write ends it (main says the output is incomplete)
      for (int i = 0; i < n; ++i)
        out << (i ? "," : "") << csv_field(cell(s, i));
      out << "\n";
    }
  } catch (const SqliteError&) {
    if (!store.deadline_passed())
      throw;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", timeout_s);
    throw std::runtime_error(std::string("the query was stopped after ") + buf +
                             " s (--timeout S sets the limit, 0: none); the rows printed are "
                             "incomplete");
  }
  return 0;
}

int cmd_status(const std::filesystem::path& db_path, const std::string& study, std::ostream& out) {
  Store store = Store::open_read(db_path);
  std::optional<std::int64_t> sid;
  if (!study.empty())
    sid = study_id(store, study);
  double now = unix_now();

  // "stale": done or diverged jobs whose result was made by other solver code than this build's
  // (docs/runner.md, "Stale results"); counted among done/diverged too.
  std::map<std::pair<std::string, std::string>, std::map<JobState, std::int64_t>> table;
  std::map<std::pair<std::string, std::string>, std::int64_t> stale;
  std::int64_t stale_total = 0;
  for (const StateCount& c : store.state_table(sid, solver_fingerprint)) {
    table[{c.study, c.tier}][c.state] = c.count;
    stale[{c.study, c.tier}] += c.stale;
    stale_total += c.stale;
  }
  if (table.empty())
    out << "no jobs" << (study.empty() ? "" : " in study '" + study + "'") << "\n";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%-24s %-8s %7s", "study", "tier", "total");
  out << buf;
  for (JobState s : all_job_states()) {
    std::snprintf(buf, sizeof buf, " %8s", to_string(s));
    out << buf;
  }
  out << "    stale\n";
  for (const auto& [k, counts] : table) {
    std::int64_t total = 0;
    for (const auto& [s, c] : counts)
      total += c;
    std::snprintf(buf, sizeof buf, "%-24s %-8s %7lld", k.first.c_str(), k.second.c_str(),
                  static_cast<long long>(total));
    out << buf;
    for (JobState s : all_job_states()) {
      auto it = counts.find(s);
      std::snprintf(buf, sizeof buf, " %8lld",
                    static_cast<long long>(it == counts.end() ? 0 : it->second));
      out << buf;
    }
    std::snprintf(buf, sizeof buf, " %8lld", static_cast<long long>(stale[k]));
    out << buf << "\n";
  }
  if (stale_total > 0)
    out << "\nstale: " << stale_total << " finished job(s) were computed by other solver code "
        << "than this build's for their case; their results are "
        << "kept and shown, `runner STUDY.toml --rerun-stale` recomputes them\n";

  bool header = false;
  for (const RunningJob& r : store.running_jobs(sid)) {
    if (!header)
      out << "\nrunning jobs:\n", header = true;
    out << "  " << r.key.substr(0, 12) << "  " << r.host << ":" << r.pid << "  heartbeat "
        << (!r.heartbeat_at ? std::string("never")
                            : format_duration(now - *r.heartbeat_at) + " ago");
    // A runner refreshes its heartbeats every 5 s; the next run resets jobs older than 30 s.
    if (r.heartbeat_at && now - *r.heartbeat_at > 30)
      out << " (stale: owner gone? the next run re-queues it)";
    if (r.progress) {
      std::snprintf(buf, sizeof buf, "  %.0f%%", 100 * *r.progress);
      out << buf;
    }
    out << "  " << r.params_json << "\n";
  }

  header = false;
  for (const SubmittedArray& a : store.submitted_arrays(sid)) {
    if (!header)
      out << "\nsubmitted to Slurm (runner ingest records finished ones):\n", header = true;
    out << "  array " << (a.array_id.empty() ? std::string("?") : a.array_id) << ": " << a.jobs
        << " job(s), submitted " << format_duration(now - a.since) << " ago\n";
  }

  header = false;
  for (const AttemptError& e : store.last_errors(sid, 10)) {
    if (!header)
      out << "\nlast errors:\n", header = true;
    std::string first = e.error_text.substr(0, e.error_text.find('\n'));
    out << "  " << e.key.substr(0, 12) << " attempt " << e.attempt << " " << e.attempt_state << " ["
        << e.failure_class << "] (" << format_duration(now - e.finished_at) << " ago): " << first
        << (e.job_state == JobState::done ? "  (job done since)" : "") << "\n";
  }
  return 0;
}

namespace {
void print_params(std::ostream& out, const std::vector<ParamSpec>& params) {
  for (const auto& p : params) {
    std::string constraint = constraint_text(p);
    char buf[128];
    std::snprintf(buf, sizeof buf, "  %-14s %-6s default %-16s", p.name.c_str(),
                  type_name(p.type).c_str(), format_value(p.default_value).c_str());
    out << buf;
    if (!constraint.empty())
      out << " " << constraint << ";";
    out << " " << p.doc;
    if (!p.identity)
      out << " (not part of the job key)";
    out << "\n";
  }
}
} // namespace

int cmd_cases(std::ostream& out, const std::string& name) {
  if (name.empty()) {
    for (const auto& c : case_registry()) {
      if (c.test_fixture)
        continue;
      out << c.name << ": " << c.description << "\n";
      if (!c.schemes.empty())
        out << "  schemes: " << quoted_list(c.schemes) << "\n";
      print_params(out, c.params);
    }
    out << "\nschemes (their parameters join those of the case a study runs them with):\n";
    for (const auto& s : scheme_registry()) {
      out << "scheme " << s.name << ": " << s.description << "\n";
      print_params(out, s.params);
    }
    out << "\nOne case with its metrics and outputs: runner cases CASE\n";
    return 0;
  }
  const CaseInfo* c = find_case(name);
  if (!c) {
    std::vector<std::string> names;
    for (const auto& k : case_registry())
      if (!k.test_fixture)
        names.push_back(k.name);
    throw std::runtime_error("runner cases: no case '" + name + "'" + did_you_mean(name, names) +
                             "; cases: " + quoted_list(names));
  }
  auto docs = [&](const std::vector<OutputDoc>& list) {
    for (const auto& d : list) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "  %-28s ", d.name.c_str());
      out << buf << d.doc << "\n";
    }
  };
  out << c->name << ": " << c->description << "\n\nparameters:\n";
  print_params(out, c->params);
  for (const auto& sn : c->schemes)
    if (const SchemeInfo* s = find_scheme(sn)) {
      out << "\nscheme " << s->name << (sn == c->schemes.front() ? " (the default)" : "") << ": "
          << s->description << "\n";
      print_params(out, s->params);
      if (!s->metrics.empty()) {
        out << "  its metrics:\n";
        docs(s->metrics);
      }
    }
  out << "\nmetrics:\n";
  if (c->metrics.empty())
    out << "  (not declared here: the case's page in docs/ lists them)\n";
  docs(c->metrics);
  if (c->size) { // a flow case: the time loop's costs
    out << "\nmetrics of every flow case:\n";
    docs(flow_loop_metrics());
  }
  if (!c->datasets.empty()) {
    out << "\nHDF5 datasets (<job folder>/" << c->name << ".h5):\n";
    docs(c->datasets);
  }
  return 0;
}

namespace {

// --where KEY=VALUE filters of `runner table`: every key must be a parameter of some job of
// the study (or `scheme`).
JobFilter where_filter(Store& store, std::int64_t sid, const std::vector<std::string>& where) {
  JobFilter f;
  for (const auto& w : where) {
    auto eq = w.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::runtime_error("--where '" + w + "': expected KEY=VALUE, e.g. lattice=uniform");
    std::string key = w.substr(0, eq), value = w.substr(eq + 1);
    if (key == "scheme") {
      f.schemes.push_back(value);
      continue;
    }
    if (!store.has_param(sid, key)) {
      std::vector<std::string> names = store.param_names(sid);
      throw std::runtime_error("--where '" + w + "': '" + key + "' is not a parameter of this " +
                               "study's jobs" + did_you_mean(key, names) +
                               (names.empty() ? "" : "; parameters: " + quoted_list(names)));
    }
    char* endp = nullptr;
    double x = std::strtod(value.c_str(), &endp);
    if (value == "true" || value == "false")
      f.params.emplace_back(key, value == "true" ? 1.0 : 0.0);
    else if (!value.empty() && endp && *endp == 0)
      f.params.emplace_back(key, x);
    else
      f.params.emplace_back(key, value);
  }
  return f;
}

// The text of a pivot key, as `runner query` prints it.
std::string cell_text(const SqlCell& c) {
  switch (c.type) {
  case SQLITE_NULL:
    return "";
  case SQLITE_INTEGER:
    return std::to_string(c.integer);
  case SQLITE_FLOAT:
    return format_real(c.real);
  default:
    return c.text;
  }
}

std::string markdown_cell(const std::string& s) {
  std::string out;
  for (char c : s)
    out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

} // namespace

int cmd_table(const std::filesystem::path& db_path, const TableOptions& t, std::ostream& out) {
  static const std::map<std::string, std::string> aggs = {
      {"mean", "avg"}, {"min", "min"}, {"max", "max"}, {"count", "count"}, {"median", ""}};
  auto agg = aggs.find(t.agg);
  if (agg == aggs.end())
    throw std::runtime_error("--agg must be mean, median, min, max or count");
  if (t.format != "text" && t.format != "csv" && t.format != "markdown")
    throw std::runtime_error("--format must be text, csv or markdown");
  Store store = Store::open_read(db_path);
  std::int64_t sid = study_id(store, t.study);
  json_path(t.rows);
  json_path(t.cols);
  // --rows and --cols as --where takes its keys: a parameter of the study's jobs, or scheme.
  for (const auto& [opt, key] : {std::pair{"--rows", &t.rows}, std::pair{"--cols", &t.cols}})
    if (*key != "scheme" && !store.has_param(sid, *key)) {
      std::vector<std::string> names = store.param_names(sid);
      throw std::runtime_error(std::string(opt) + " '" + *key + "' is not a parameter of this " +
                               "study's jobs" + did_you_mean(*key, names) +
                               (names.empty() ? "" : "; parameters: " + quoted_list(names)));
    }
  JobFilter filter = where_filter(store, sid, t.where);
  // Keep numeric order for numeric parameter values.
  struct Key {
    bool numeric;
    double x;
    std::string s;
    bool operator<(const Key& o) const {
      if (numeric != o.numeric)
        return numeric;
      return numeric ? x < o.x : s < o.s;
    }
  };
  auto key = [&](const SqlCell& c) {
    return Key{c.type == SQLITE_INTEGER || c.type == SQLITE_FLOAT, c.real, cell_text(c)};
  };
  std::map<Key, std::map<Key, std::string>> cells;
  std::set<Key> cols;
  auto put = [&](const Key& r, const Key& c, std::optional<double> v) {
    cols.insert(c);
    char buf[32];
    if (!v)
      buf[0] = 0;
    else
      std::snprintf(buf, sizeof buf, "%.6g", *v);
    cells[r][c] = buf;
  };
  // The jobs of each cell: their count, the median, and the parameters that vary inside a cell
  // (an aggregate over them is worth a note: one outlier seed can carry a mean).
  std::map<Key, std::map<Key, std::vector<const PivotMember*>>> members;
  const std::vector<PivotMember> all = store.pivot_members(sid, t.rows, t.cols, t.metric, filter);
  for (const PivotMember& m : all)
    members[key(m.row)][key(m.col)].push_back(&m);
  if (t.agg == "median") {
    for (auto& [r, row] : members)
      for (auto& [c, ms] : row) {
        std::vector<double> v;
        for (const PivotMember* m : ms)
          v.push_back(m->value);
        std::sort(v.begin(), v.end());
        const std::size_t n = v.size();
        put(r, c, n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
      }
  } else {
    for (const PivotCell& p : store.pivot(sid, t.rows, t.cols, t.metric, agg->second, filter))
      put(key(p.row), key(p.col), p.value);
  }
  std::string cell_note;
  {
    std::size_t lo = SIZE_MAX, hi = 0;
    std::set<std::string> varying;
    for (const auto& [r, row] : members)
      for (const auto& [c, ms] : row) {
        lo = std::min(lo, ms.size()), hi = std::max(hi, ms.size());
        std::map<std::string, std::set<std::string>> values;
        for (const PivotMember* m : ms) {
          const auto j = nlohmann::json::parse(m->params, nullptr, false);
          if (j.is_object())
            for (const auto& [name, v] : j.items())
              if (name != t.rows && name != t.cols)
                values[name].insert(v.dump());
        }
        for (const auto& [name, vs] : values)
          if (vs.size() > 1)
            varying.insert(name);
      }
    if (hi > 1 && t.agg != "count") {
      cell_note =
          "note: each cell is the " + t.agg + " of " +
          (lo == hi ? std::to_string(hi) : std::to_string(lo) + " to " + std::to_string(hi)) +
          " jobs";
      if (!varying.empty()) {
        std::string names;
        for (const auto& n : varying)
          names += (names.empty() ? "" : ", ") + n;
        cell_note += " that differ in " + names;
      }
      cell_note += " (--agg count shows how many, --agg median or --where pick)\n";
    }
  }
  if (cells.empty()) {
    std::vector<std::string> names = store.metric_names(sid);
    bool known = std::find(names.begin(), names.end(), t.metric) != names.end();
    std::string where_text;
    for (const auto& w : t.where)
      where_text += (where_text.empty() ? " with " : " and ") + w;
    throw std::runtime_error(
        "no values of metric '" + t.metric + "' in study '" + t.study + "'" + where_text +
        (known ? ""
               : did_you_mean(t.metric, names) +
                     (names.empty() ? "" : "; metrics: " + quoted_list(names))));
  }
  // Rows and columns in the order the study lists their values (the first job of each value in
  // the study's expansion); values without a recorded job last, in their natural order.
  std::map<Key, std::int64_t> row_first, col_first;
  for (const PivotMember& m : all) {
    auto first = [&](std::map<Key, std::int64_t>& f, const Key& k) {
      auto [it, fresh] = f.emplace(k, m.ordinal);
      if (!fresh)
        it->second = std::min(it->second, m.ordinal);
    };
    first(row_first, key(m.row)), first(col_first, key(m.col));
  }
  auto in_study_order = [](std::vector<Key> keys, const std::map<Key, std::int64_t>& f) {
    std::stable_sort(keys.begin(), keys.end(), [&](const Key& a, const Key& b) {
      const auto ia = f.find(a), ib = f.find(b);
      const std::int64_t oa = ia == f.end() ? INT64_MAX : ia->second;
      const std::int64_t ob = ib == f.end() ? INT64_MAX : ib->second;
      return oa < ob;
    });
    return keys;
  };
  std::vector<Key> row_keys;
  for (const auto& [r, row] : cells)
    row_keys.push_back(r);
  row_keys = in_study_order(row_keys, row_first);
  const std::vector<Key> col_keys =
      in_study_order(std::vector<Key>(cols.begin(), cols.end()), col_first);
  std::vector<std::vector<std::string>> grid;
  std::vector<std::string> head{t.rows + " \\ " + t.cols};
  for (const auto& c : col_keys)
    head.push_back(c.s);
  grid.push_back(head);
  for (const auto& r : row_keys) {
    const auto& row = cells[r];
    std::vector<std::string> line{r.s};
    for (const auto& c : col_keys) {
      auto it = row.find(c);
      line.push_back(it == row.end() ? "" : it->second);
    }
    grid.push_back(line);
  }
  // Stale results (made by other solver code) are shown, not hidden: a note under the table
  // (not in CSV, which stays a plain grid; `runner export` has a stale column).
  std::string stale_note = cell_note;
  if (std::size_t n =
          store.stale_in_study(sid, study_fingerprint(store, t.study), std::nullopt, true))
    stale_note += "note: " + std::to_string(n) + " of the study's finished jobs are " +
                  "stale (computed by other solver code than this build's; --rerun-stale)\n";
  if (t.format == "csv") {
    for (const auto& line : grid) {
      for (std::size_t i = 0; i < line.size(); ++i)
        out << (i ? "," : "") << csv_field(line[i]);
      out << "\n";
    }
    return 0;
  }
  if (t.format == "markdown") {
    for (std::size_t r = 0; r < grid.size(); ++r) {
      out << "|";
      for (const auto& c : grid[r])
        out << " " << markdown_cell(c) << " |";
      out << "\n";
      if (r == 0) {
        out << "|";
        for (std::size_t i = 0; i < grid[r].size(); ++i)
          out << (i ? " ---: |" : " --- |");
        out << "\n";
      }
    }
    out << (stale_note.empty() ? "" : "\n" + stale_note);
    return 0;
  }
  std::vector<std::size_t> width(head.size(), 0);
  for (const auto& line : grid)
    for (std::size_t i = 0; i < line.size(); ++i)
      width[i] = std::max(width[i], line[i].size());
  out << t.agg << "(" << t.metric << ") for study " << t.study;
  for (std::size_t i = 0; i < t.where.size(); ++i)
    out << (i ? ", " : " where ") << t.where[i];
  out << "\n";
  for (const auto& line : grid) {
    for (std::size_t i = 0; i < line.size(); ++i) {
      std::string pad(width[i] - line[i].size(), ' ');
      out << (i ? "  " : "") << (i ? pad + line[i] : line[i] + pad);
    }
    out << "\n";
  }
  out << stale_note;
  return 0;
}

int cmd_export(const std::filesystem::path& db_path, const std::string& study,
               const std::string& format, std::ostream& out) {
  if (format != "csv" && format != "json")
    throw std::runtime_error("--format must be csv or json");
  Store store = Store::open_read(db_path);
  std::int64_t sid = study_id(store, study);
  struct Row {
    std::string key, state, scheme, tier, output_dir;
    nlohmann::json params;
    std::map<std::string, std::optional<double>> metrics;
    bool stale = false; // made by other solver code than this build's
  };
  std::vector<Row> rows;
  std::map<std::int64_t, std::size_t> index;
  for (const StudyJob& j :
       store.study_jobs(sid, std::nullopt, true, study_fingerprint(store, study))) {
    index[j.id] = rows.size();
    rows.push_back({j.key,
                    to_string(j.state),
                    j.scheme,
                    joined_tiers(j),
                    j.output_dir,
                    nlohmann::json::parse(j.params_json),
                    {},
                    j.stale});
  }
  std::vector<std::string> metric_names;
  for (const MetricValue& m : store.study_metrics(sid)) {
    auto it = index.find(m.job_id);
    if (it == index.end())
      continue;
    if (std::find(metric_names.begin(), metric_names.end(), m.name) == metric_names.end())
      metric_names.push_back(m.name);
    rows[it->second].metrics[m.name] = m.value;
  }
  if (format == "json") {
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& r : rows) {
      nlohmann::json metrics = nlohmann::json::object();
      for (const auto& [k, v] : r.metrics)
        metrics[k] = v ? nlohmann::json(*v) : nlohmann::json();
      arr.push_back(
          {{"job", r.key},
           {"status", r.state},
           {"scheme", r.scheme},
           {"tier", r.tier},
           {"output_dir", r.output_dir.empty() ? nlohmann::json() : nlohmann::json(r.output_dir)},
           {"params", r.params},
           {"metrics", metrics},
           {"stale", r.stale}});
    }
    out << arr.dump(1) << "\n";
    return 0;
  }
  std::vector<std::string> param_names;
  for (const auto& r : rows)
    for (const auto& [k, v] : r.params.items())
      if (std::find(param_names.begin(), param_names.end(), k) == param_names.end())
        param_names.push_back(k);
  // A name that is both a parameter and a metric (t_end), or that of a fixed column, is given as
  // param.NAME / metric.NAME; every other column keeps its plain name (docs/runner.md).
  static const std::set<std::string> fixed = {"job",  "status",     "scheme",
                                              "tier", "output_dir", "stale"};
  const std::set<std::string> params_set(param_names.begin(), param_names.end());
  const std::set<std::string> metrics_set(metric_names.begin(), metric_names.end());
  out << "job,status,scheme,tier,output_dir";
  for (const auto& p : param_names)
    out << "," << csv_field(metrics_set.count(p) || fixed.count(p) ? "param." + p : p);
  for (const auto& n : metric_names)
    out << "," << csv_field(params_set.count(n) || fixed.count(n) ? "metric." + n : n);
  out << ",stale\n"; // the last column: 1 when made by other solver code than this build's
  for (const auto& r : rows) {
    out << r.key << "," << r.state << "," << csv_field(r.scheme) << "," << csv_field(r.tier) << ","
        << csv_field(r.output_dir);
    for (const auto& p : param_names) {
      out << ",";
      if (!r.params.contains(p))
        continue;
      const auto& v = r.params[p];
      if (v.is_string())
        out << csv_field(v.get<std::string>());
      else if (v.is_number_float())
        out << format_real(v.get<double>());
      else
        out << v.dump();
    }
    for (const auto& n : metric_names) {
      out << ",";
      auto it = r.metrics.find(n);
      if (it != r.metrics.end() && it->second)
        out << format_real(*it->second);
    }
    out << "," << (r.stale ? 1 : 0) << "\n";
  }
  return 0;
}

namespace {

const char* publish_header = "study,job,tier,code_version,params,metric,value";

} // namespace

int cmd_publish(const std::filesystem::path& db_path, const std::string& study,
                const std::filesystem::path& out_file, std::ostream& log) {
  // The file is read, then replaced by a renamed temporary file: only a regular file (or none
  // yet) can be (a device would be read forever, a link replaced by a file).
  if (std::error_code ec;
      std::filesystem::exists(std::filesystem::symlink_status(out_file, ec)) &&
      !std::filesystem::is_regular_file(std::filesystem::symlink_status(out_file, ec)))
    throw std::runtime_error("--out '" + out_file.string() +
                             "' is not a regular file; publish rewrites a CSV file in place, give "
                             "the path of one (or of a file to create)");
  // The rows already committed, grouped by job in file order.
  std::vector<std::string> order;
  std::map<std::string, std::vector<std::string>> old_rows;
  std::map<std::string, std::string> old_tiers; // a job's tier label in the file
  if (std::ifstream in{out_file}) {
    std::string line;
    if (!std::getline(in, line) || line != publish_header)
      throw std::runtime_error(out_file.string() + ": line 1: expected the header '" +
                               publish_header + "'");
    for (int n = 2; std::getline(in, line); ++n) {
      const auto f = csv_split(line);
      if (f.size() != 7 || f[0] != study)
        throw std::runtime_error(out_file.string() + ": line " + std::to_string(n) +
                                 ": expected 7 fields of study '" + study + "'");
      if (!old_rows.count(f[1]))
        order.push_back(f[1]), old_tiers[f[1]] = f[2];
      old_rows[f[1]].push_back(line);
    }
  }
  Store store = Store::open_read(db_path);
  const std::int64_t sid = study_id(store, study);
  const auto versions = store.metric_code_versions(sid);
  std::map<std::int64_t, std::vector<const MetricValue*>> metrics;
  const auto values = store.study_metrics(sid);
  for (const MetricValue& m : values)
    metrics[m.job_id].push_back(&m);
  std::map<std::string, std::vector<std::string>> new_rows;
  std::vector<std::string> new_order;
  std::size_t stale = 0;
  std::set<std::string> retired; // jobs of earlier versions of the study file only
  for (const StudyJob& j :
       store.study_jobs(sid, std::nullopt, false, study_fingerprint(store, study))) {
    if (j.tiers.empty()) { // in no tier of the current expansion: export and status hide it too
      retired.insert(j.key);
      continue;
    }
    if ((j.state != JobState::done && j.state != JobState::diverged) || !metrics.count(j.id))
      continue;
    const auto v = versions.find(j.id);
    // A job the file has already keeps the tiers it was published under (another database may
    // have run it for another tier), this database's added after them.
    std::string tiers = joined_tiers(j);
    if (const auto o = old_tiers.find(j.key); o != old_tiers.end())
      tiers = merged_tiers(o->second, tiers);
    const std::string prefix = csv_field(study) + "," + j.key + "," + csv_field(tiers) + "," +
                               csv_field(v == versions.end() ? "" : v->second) + "," +
                               csv_field(j.params_json) + ",";
    auto& rows = new_rows[j.key];
    for (const MetricValue* m : metrics[j.id])
      rows.push_back(prefix + csv_field(m->name) + "," +
                     (m->value ? format_real(*m->value) : std::string("nan")));
    new_order.push_back(j.key);
    stale += j.stale;
  }
  std::ostringstream text;
  text << publish_header << "\n";
  std::size_t kept = 0, replaced = 0, added = 0, removed = 0;
  for (const auto& key : order) {
    if (retired.count(key)) {
      ++removed;
      continue;
    }
    const auto it = new_rows.find(key);
    const auto& rows = it == new_rows.end() ? old_rows[key] : it->second;
    (it == new_rows.end() ? kept : replaced) += 1;
    for (const auto& r : rows)
      text << r << "\n";
  }
  for (const auto& key : new_order)
    if (!old_rows.count(key)) {
      ++added;
      for (const auto& r : new_rows[key])
        text << r << "\n";
    }
  write_file_atomic(out_file, text.str());
  log << out_file.string() << ": " << added << " jobs added, " << replaced << " replaced, " << kept
      << " kept from the file";
  if (removed)
    log << ", " << removed << " removed (no longer in the study: its file changed)";
  if (stale)
    log << "; " << stale << " of the database's jobs are stale (made by other solver code than "
        << "this build's; their code_version says which)";
  log << "\n";
  return 0;
}

namespace {

// A job's parameters as ConvergeRow holds them: name -> the value as JSON text.
std::map<std::string, std::string> dumped(const nlohmann::json& p) {
  std::map<std::string, std::string> out;
  if (p.is_object())
    for (const auto& [k, v] : p.items())
      out[k] = v.dump();
  return out;
}

// The rows of `runner converge` from the database: the study's current jobs with the metric.
std::vector<ConvergeRow> converge_rows_db(const std::filesystem::path& db_path,
                                          const ConvergeOptions& c) {
  Store store = Store::open_read(db_path);
  const std::int64_t sid = study_id(store, c.study);
  if (!store.has_param(sid, c.param)) {
    std::vector<std::string> names = store.param_names(sid);
    throw std::runtime_error("--param '" + c.param + "' is not a parameter of this study's jobs" +
                             did_you_mean(c.param, names) +
                             (names.empty() ? "" : "; parameters: " + quoted_list(names)));
  }
  JobFilter filter = where_filter(store, sid, c.where);
  const std::vector<PivotMember> all = store.pivot_members(sid, c.param, c.param, c.metric, filter);
  if (all.empty()) {
    std::vector<std::string> names = store.metric_names(sid);
    const bool known = std::find(names.begin(), names.end(), c.metric) != names.end();
    throw std::runtime_error("no values of metric '" + c.metric + "' in study '" + c.study + "'" +
                             (known
                                  ? std::string(" with these filters")
                                  : did_you_mean(c.metric, names) +
                                        (names.empty() ? "" : "; metrics: " + quoted_list(names))));
  }
  std::vector<ConvergeRow> rows;
  for (const PivotMember& m : all) {
    if (m.row.type != SQLITE_INTEGER && m.row.type != SQLITE_FLOAT)
      throw std::runtime_error("--param '" + c.param + "' has a non-numeric value '" +
                               cell_text(m.row) + "'");
    rows.push_back({m.row.type == SQLITE_INTEGER ? static_cast<double>(m.row.integer) : m.row.real,
                    m.value, dumped(nlohmann::json::parse(m.params, nullptr, false))});
  }
  return rows;
}

// The same from a published record (docs/results/STUDY.csv, `runner publish`): its rows of the
// study and metric, --where applied to each job's parameters.
std::vector<ConvergeRow> converge_rows_csv(const std::filesystem::path& file,
                                           const ConvergeOptions& c) {
  std::ifstream in(file);
  if (!in)
    throw std::runtime_error(file.string() + ": cannot read");
  std::string line;
  if (!std::getline(in, line) || line != publish_header)
    throw std::runtime_error(file.string() + ": line 1: expected the header '" + publish_header +
                             "' (a file written by runner publish)");
  std::vector<std::pair<std::string, std::string>> where;
  for (const auto& w : c.where) {
    const auto eq = w.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::runtime_error("--where '" + w + "': expected KEY=VALUE, e.g. lattice=uniform");
    where.emplace_back(w.substr(0, eq), w.substr(eq + 1));
  }
  auto matches = [&](const nlohmann::json& p, const std::string& key, const std::string& value) {
    const auto it = p.find(key);
    if (it == p.end())
      return false;
    if (it->is_number()) {
      char* endp = nullptr;
      const double x = std::strtod(value.c_str(), &endp);
      return endp && *endp == 0 && !value.empty() && x == it->get<double>();
    }
    if (it->is_boolean())
      return (value == "true") == it->get<bool>() && (value == "true" || value == "false");
    return it->is_string() && it->get<std::string>() == value;
  };
  std::vector<ConvergeRow> rows;
  std::set<std::string> params_seen, metrics_seen;
  bool param_numeric = true;
  for (int n = 2; std::getline(in, line); ++n) {
    const auto f = csv_split(line);
    if (f.size() != 7)
      throw std::runtime_error(file.string() + ": line " + std::to_string(n) +
                               ": expected 7 fields");
    if (f[0] != c.study)
      continue;
    metrics_seen.insert(f[5]);
    const nlohmann::json p = nlohmann::json::parse(f[4], nullptr, false);
    if (!p.is_object())
      continue;
    for (const auto& [k, v] : p.items())
      params_seen.insert(k);
    if (f[5] != c.metric)
      continue;
    bool ok = true;
    for (const auto& [k, v] : where)
      ok = ok && matches(p, k, v);
    const auto it = p.find(c.param);
    if (!ok || it == p.end())
      continue;
    if (!it->is_number()) {
      param_numeric = false;
      continue;
    }
    rows.push_back({it->get<double>(), std::strtod(f[6].c_str(), nullptr), dumped(p)});
  }
  if (!params_seen.count(c.param)) {
    const std::vector<std::string> names(params_seen.begin(), params_seen.end());
    throw std::runtime_error(file.string() + ": --param '" + c.param +
                             "' is not a parameter of "
                             "study '" +
                             c.study + "'" + did_you_mean(c.param, names));
  }
  if (!param_numeric)
    throw std::runtime_error("--param '" + c.param + "' has non-numeric values");
  if (rows.empty()) {
    const std::vector<std::string> names(metrics_seen.begin(), metrics_seen.end());
    throw std::runtime_error(file.string() + ": no values of metric '" + c.metric + "' in study '" +
                             c.study + "'" +
                             (metrics_seen.count(c.metric) ? std::string(" with these filters")
                                                           : did_you_mean(c.metric, names)));
  }
  return rows;
}

} // namespace

ConvergeTable converge_table(const std::vector<ConvergeRow>& rows, const ConvergeOptions& c) {
  using Row = ConvergeRow;
  // A count (n_side, D_over_dx) when every value is a whole number >= 2, else a spacing.
  bool count = c.resolution == "count";
  if (c.resolution == "auto") {
    count = true;
    for (const Row& r : rows)
      count = count && r.x >= 2 && r.x == std::floor(r.x);
  }
  // The groups: the other parameters that vary, leaving out those that are a function of the
  // resolution (a time step derived from dx does not split a group).
  std::map<std::string, std::set<std::string>> values;
  std::map<std::string, std::map<double, std::set<std::string>>> by_x;
  for (const Row& r : rows)
    for (const auto& [k, v] : r.params)
      if (k != c.param)
        values[k].insert(v), by_x[k][r.x].insert(v);
  std::vector<std::string> group_keys;
  for (const auto& [k, vs] : values) {
    if (vs.size() < 2 || std::find(c.ignore.begin(), c.ignore.end(), k) != c.ignore.end())
      continue;
    bool function_of_x = true;
    for (const auto& [x, s] : by_x[k])
      function_of_x = function_of_x && s.size() == 1;
    if (!function_of_x)
      group_keys.push_back(k);
  }
  std::map<std::string, std::map<double, std::vector<double>>> groups;
  for (const Row& r : rows) {
    std::string label;
    for (const auto& k : group_keys) {
      const auto it = r.params.find(k);
      std::string v = it == r.params.end() ? "-" : it->second;
      if (v.size() > 1 && v.front() == '"')
        v = v.substr(1, v.size() - 2);
      label += (label.empty() ? "" : " ") + k + "=" + v;
    }
    groups[label][r.x].push_back(r.f);
  }
  ConvergeTable t;
  t.count = count;
  std::vector<std::string>& header = t.header;
  header = {"group", "resolutions", c.param + " finest", c.metric + " finest"};
  if (c.kind == "self")
    for (const char* s : {"p", "extrapolated", "GCI_fine %", "note"})
      header.push_back(s);
  else
    for (const char* s : {"p (finest pair)", "p (fit, all)", "note"})
      header.push_back(s);
  std::vector<std::vector<std::string>>& table = t.rows;
  auto num = [](std::optional<double> v, const char* fmt = "%.4g") {
    if (!v)
      return std::string();
    char buf[32];
    std::snprintf(buf, sizeof buf, fmt, *v);
    return std::string(buf);
  };
  for (const auto& [label, by_res] : groups) {
    std::vector<GridValue> grids;
    std::string list;
    bool averaged = false;
    for (const auto& [x, fs] : by_res) {
      double f = 0;
      for (double v : fs)
        f += v;
      f /= static_cast<double>(fs.size());
      averaged = averaged || fs.size() > 1;
      grids.push_back({count ? 1.0 / x : x, f});
      list += (list.empty() ? "" : " ") + num(x, "%.6g");
    }
    std::vector<std::string> row = {label.empty() ? "(all)" : label, list};
    const auto finest =
        std::min_element(grids.begin(), grids.end(), [](auto& a, auto& b) { return a.h < b.h; });
    row.push_back(num(count ? 1.0 / finest->h : finest->h, "%.6g"));
    row.push_back(num(finest->f));
    if (grids.size() < 2) {
      row.insert(row.end(), c.kind == "self" ? 3 : 2, "");
      row.push_back("one resolution");
    } else if (c.kind == "self") {
      const Convergence r = self_convergence(grids, c.formal_order);
      row.push_back(num(r.p, "%.3f"));
      row.push_back(num(r.f_ext));
      row.push_back(r.gci_fine ? num(100.0 * *r.gci_fine, "%.3g") : "");
      row.push_back(r.note + (r.grids > 3
                                  ? std::string(r.note.empty() ? "" : "; ") +
                                        "p from the three finest of " + std::to_string(r.grids)
                                  : ""));
    } else {
      const Convergence r = error_convergence(grids);
      row.push_back(num(r.p, "%.3f"));
      row.push_back(r.grids > 2 ? num(r.p_fit, "%.3f") : "");
      row.push_back(r.note);
    }
    if (averaged)
      row.back() +=
          (row.back().empty() ? "" : "; ") + std::string("mean of several jobs per resolution");
    table.push_back(row);
  }
  return t;
}

int cmd_converge(const std::filesystem::path& db_path, const ConvergeOptions& c,
                 std::ostream& out) {
  if (c.kind != "self" && c.kind != "error")
    throw std::runtime_error("--kind must be self or error");
  if (c.resolution != "auto" && c.resolution != "spacing" && c.resolution != "count")
    throw std::runtime_error("--resolution must be auto, spacing or count");
  if (c.format != "text" && c.format != "csv" && c.format != "markdown")
    throw std::runtime_error("--format must be text, csv or markdown");
  json_path(c.param);
  const ConvergeTable t = converge_table(
      c.published.empty() ? converge_rows_db(db_path, c) : converge_rows_csv(c.published, c), c);
  const bool count = t.count;
  const std::vector<std::string>& header = t.header;
  const std::vector<std::vector<std::string>>& table = t.rows;
  const bool text = c.format == "text", md = c.format == "markdown";
  if (text) {
    out << c.study << ": " << c.metric << " against " << c.param
        << (count ? " (a count: spacing h = 1/" + c.param + ")" : " (a spacing)") << ", "
        << (c.kind == "self" ? "self-convergence: order from the three finest resolutions (Celik "
                               "et al. 2008), Richardson extrapolation, GCI with Fs = 1.25 (3 "
                               "with two resolutions)"
                             : "an error against a reference: order from the finest pair and a "
                               "least-squares fit of ln|error| against ln h")
        << "\n";
    std::vector<std::size_t> w(header.size());
    for (std::size_t k = 0; k < header.size(); ++k) {
      w[k] = header[k].size();
      for (const auto& r : table)
        w[k] = std::max(w[k], r[k].size());
    }
    auto line = [&](const std::vector<std::string>& r) {
      std::string s;
      for (std::size_t k = 0; k < r.size(); ++k)
        s += r[k] + std::string(k + 1 < r.size() ? w[k] - r[k].size() + 2 : 0, ' ');
      while (!s.empty() && s.back() == ' ')
        s.pop_back();
      out << s << "\n";
    };
    line(header);
    for (const auto& r : table)
      line(r);
  } else {
    auto line = [&](const std::vector<std::string>& r) {
      for (std::size_t k = 0; k < r.size(); ++k)
        out << (md ? (k ? " | " : "| ") : (k ? "," : ""))
            << (md ? markdown_cell(r[k]) : csv_field(r[k]));
      out << (md ? " |\n" : "\n");
    };
    line(header);
    if (md)
      line(std::vector<std::string>(header.size(), "---"));
    for (const auto& r : table)
      line(r);
  }
  return 0;
}

} // namespace sph::runner
