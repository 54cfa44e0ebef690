// Read-only commands over the store: query, status, cases, table, export.
#include "commands.hpp"

#include "diagnostics.hpp"
#include "params.hpp"
#include "progress.hpp"
#include "provenance.hpp"
#include "store.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>
#include <set>
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

bool only_space(const char* p) {
  for (; p && *p; ++p)
    if (!std::isspace(static_cast<unsigned char>(*p)))
      return false;
  return true;
}

std::int64_t study_id(Db& db, const std::string& name) {
  Stmt q = db.prepare("SELECT id FROM studies WHERE name=?");
  q.bind(1, name);
  if (q.step())
    return q.integer(0);
  std::vector<std::string> names;
  Stmt all = db.prepare("SELECT name FROM studies ORDER BY name");
  while (all.step())
    names.push_back(all.text(0));
  throw std::runtime_error("no study named '" + name + "' in the database" +
                           did_you_mean(name, names) +
                           (names.empty() ? "" : "; studies: " + quoted_list(names)));
}

std::string json_path(const std::string& param) {
  for (char c : param)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_')
      throw std::runtime_error("bad parameter name '" + param + "'");
  return "$." + param;
}

} // namespace

namespace {

// The authorizer of `runner query`: reads only. Denies every write, schema change, transaction
// control, ATTACH/DETACH, and any PRAGMA that sets a value (PRAGMA x = y, or x(y) other than the
// table-valued read pragmas). Together with sqlite3_stmt_readonly() (which is false for VACUUM,
// VACUUM INTO, wal_checkpoint and journal_mode changes) the statement cannot change a file.
int query_authorizer(void* denied, int action, const char* a, const char* b, const char*,
                     const char*) {
  auto deny = [&](const std::string& what) {
    auto* d = static_cast<std::string*>(denied);
    if (d->empty())
      *d = what;
    return SQLITE_DENY;
  };
  switch (action) {
  case SQLITE_SELECT:
  case SQLITE_READ:
  case SQLITE_FUNCTION:
  case SQLITE_RECURSIVE:
    return SQLITE_OK;
  case SQLITE_PRAGMA: {
    static const std::set<std::string> with_argument = {
        "table_info",     "table_xinfo",      "index_info",        "index_xinfo",
        "index_list",     "foreign_key_list", "foreign_key_check", "integrity_check",
        "quick_check",    "table_list",       "function_list",     "pragma_list",
        "collation_list", "database_list",    "compile_options"};
    std::string name = a ? a : "";
    for (auto& c : name)
      c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (!b || with_argument.count(name))
      return SQLITE_OK;
    return deny("PRAGMA " + name + " with a value");
  }
  case SQLITE_ATTACH:
    return deny("ATTACH");
  case SQLITE_DETACH:
    return deny("DETACH");
  case SQLITE_TRANSACTION:
  case SQLITE_SAVEPOINT:
    return deny("transaction control");
  default:
    return deny("a statement that writes");
  }
}

} // namespace

int cmd_query(const std::filesystem::path& db_path, const std::string& sql, std::ostream& out) {
  Store store = Store::open_read(db_path);
  std::string denied;
  sqlite3* h = store.db().handle();
  sqlite3_stmt* raw = nullptr;
  const char* tail = nullptr;
  const char* query_only =
      "runner query only reads: write with the sqlite3 shell on a copy, or through the runner";
  sqlite3_set_authorizer(h, query_authorizer, &denied);
  int rc = sqlite3_prepare_v2(h, sql.c_str(), -1, &raw, &tail);
  if (rc != SQLITE_OK) {
    if (!denied.empty())
      throw std::runtime_error("refused: " + denied + " is not allowed; " + query_only);
    throw std::runtime_error(std::string("SQL error: ") + sqlite3_errmsg(h));
  }
  if (!raw)
    throw std::runtime_error("runner query: the SQL statement is empty; e.g. runner query "
                             "\"SELECT * FROM job_metrics LIMIT 10\"");
  const bool readonly = sqlite3_stmt_readonly(raw) != 0;
  sqlite3_finalize(raw);
  if (!readonly)
    throw std::runtime_error("refused: the statement would change the database or write a file "
                             "(VACUUM, checkpoints, journal mode...); " +
                             std::string(query_only));
  if (!only_space(tail))
    throw std::runtime_error("runner query runs one SQL statement; remove what follows '" +
                             sql.substr(0, static_cast<std::size_t>(tail - sql.c_str())) + "'");
  Stmt s = store.db().prepare(sql);
  int n = s.columns();
  for (int i = 0; i < n; ++i)
    out << (i ? "," : "") << csv_field(s.column_name(i));
  out << "\n";
  while (s.step()) {
    for (int i = 0; i < n; ++i)
      out << (i ? "," : "") << csv_field(cell(s, i));
    out << "\n";
  }
  return 0;
}

int cmd_status(const std::filesystem::path& db_path, const std::string& study, std::ostream& out) {
  Store store = Store::open_read(db_path);
  Db& db = store.db();
  std::optional<std::int64_t> sid;
  if (!study.empty())
    sid = study_id(db, study);
  double now = unix_now();

  static const char* states[] = {"pending", "submitted", "running", "done",
                                 "failed",  "diverged",  "timeout"};
  std::string where = sid ? " WHERE s.id=" + std::to_string(*sid) : "";
  // "stale": done or diverged jobs whose result was made by other solver code than this build's
  // (docs/runner.md, "Stale results"); counted among done/diverged too.
  Stmt q = db.prepare("SELECT s.name, sj.tier, j.state, count(*), sum(" +
                      stale_sql(db, "j.id", "j.state", "?1") +
                      ") FROM studies s JOIN study_jobs "
                      "sj ON sj.study_id=s.id AND sj.current JOIN jobs j ON j.id=sj.job_id" +
                      where + " GROUP BY s.name, sj.tier, j.state ORDER BY s.name, sj.tier");
  q.bind(1, solver_fingerprint());
  std::map<std::pair<std::string, std::string>, std::map<std::string, std::int64_t>> table;
  std::int64_t stale_total = 0;
  while (q.step()) {
    table[{q.text(0), q.text(1)}][q.text(2)] = q.integer(3);
    table[{q.text(0), q.text(1)}]["stale"] += q.integer(4);
    stale_total += q.integer(4);
  }
  if (table.empty())
    out << "no jobs" << (study.empty() ? "" : " in study '" + study + "'") << "\n";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%-24s %-8s %7s", "study", "tier", "total");
  out << buf;
  for (const char* s : states) {
    std::snprintf(buf, sizeof buf, " %8s", s);
    out << buf;
  }
  out << "    stale\n";
  for (const auto& [k, counts] : table) {
    std::int64_t total = 0;
    for (const auto& [s, c] : counts)
      if (std::string(s) != "stale")
        total += c;
    std::snprintf(buf, sizeof buf, "%-24s %-8s %7lld", k.first.c_str(), k.second.c_str(),
                  static_cast<long long>(total));
    out << buf;
    for (const char* s :
         {"pending", "submitted", "running", "done", "failed", "diverged", "timeout", "stale"}) {
      auto it = counts.find(s);
      std::snprintf(buf, sizeof buf, " %8lld",
                    static_cast<long long>(it == counts.end() ? 0 : it->second));
      out << buf;
    }
    out << "\n";
  }
  if (stale_total > 0)
    out << "\nstale: " << stale_total << " finished job(s) were computed by other solver code "
        << "than this build's (fingerprint " << solver_fingerprint() << "); their results are "
        << "kept and shown, `runner STUDY.toml --rerun-stale` recomputes them\n";

  // Per-job test (study_jobs_job index), so that the few running or failed jobs drive the
  // queries rather than the list of all the study's jobs.
  std::string job_filter = sid ? " AND EXISTS (SELECT 1 FROM study_jobs sj WHERE sj.job_id=j.id "
                                 "AND sj.study_id=" +
                                     std::to_string(*sid) + ")"
                               : "";
  Stmt r = db.prepare("SELECT j.key, j.owner_host, j.owner_pid, j.heartbeat_at, j.progress, "
                      "j.params_json FROM jobs j WHERE j.state='running'" +
                      job_filter + " ORDER BY j.heartbeat_at");
  bool header = false;
  while (r.step()) {
    if (!header)
      out << "\nrunning jobs:\n", header = true;
    out << "  " << r.text(0).substr(0, 12) << "  " << r.text(1) << ":" << r.integer(2)
        << "  heartbeat "
        << (r.is_null(3) ? std::string("never") : format_duration(now - r.real(3)) + " ago");
    // A runner refreshes its heartbeats every 5 s; the next run resets jobs older than 30 s.
    if (!r.is_null(3) && now - r.real(3) > 30)
      out << " (stale: owner gone? the next run re-queues it)";
    if (!r.is_null(4)) {
      std::snprintf(buf, sizeof buf, "  %.0f%%", 100 * r.real(4));
      out << buf;
    }
    out << "  " << r.text(5) << "\n";
  }

  Stmt sb = db.prepare("SELECT substr(j.slurm_job_id, 1, instr(j.slurm_job_id, '_') - 1), "
                       "count(*), min(j.updated_at) FROM jobs j WHERE j.state='submitted'" +
                       job_filter + " GROUP BY 1 ORDER BY 3");
  header = false;
  while (sb.step()) {
    if (!header)
      out << "\nsubmitted to Slurm (runner ingest records finished ones):\n", header = true;
    out << "  array " << (sb.text(0).empty() ? std::string("?") : sb.text(0)) << ": "
        << sb.integer(1) << " job(s), submitted " << format_duration(now - sb.real(2)) << " ago\n";
  }

  Stmt e =
      db.prepare("SELECT j.key, a.attempt, a.state, a.finished_at, a.error_text, "
                 "coalesce(a.failure_class, a.state), j.state FROM "
                 "attempts a JOIN jobs j ON j.id=a.job_id WHERE a.state IN "
                 "('failed','timeout','abandoned','interrupted') AND a.error_text IS NOT NULL" +
                 job_filter + " ORDER BY a.finished_at DESC LIMIT 10");
  header = false;
  while (e.step()) {
    if (!header)
      out << "\nlast errors:\n", header = true;
    std::string text = e.text(4);
    std::string first = text.substr(0, text.find('\n'));
    out << "  " << e.text(0).substr(0, 12) << " attempt " << e.integer(1) << " " << e.text(2)
        << " [" << e.text(5) << "] (" << format_duration(now - e.real(3)) << " ago): " << first
        << (e.text(6) == "done" ? "  (job done since)" : "") << "\n";
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

int cmd_cases(std::ostream& out) {
  for (const auto& c : case_registry()) {
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
  return 0;
}

namespace {

// --where KEY=VALUE filters of `runner table`, turned into the set of the study's jobs that match
// them all. The set is read from the job_params index, starting from the filter that matches the
// fewest jobs (counted first, on the covering index), so that a filtered pivot of a 100,000-job
// study touches only the jobs it shows.
using Bind = std::variant<double, std::string, std::int64_t>;
struct Filter {
  std::vector<std::pair<std::string, Bind>> params; // (name, value)
  std::vector<std::string> schemes;
};

Filter where_filter(Db& db, std::int64_t sid, const std::vector<std::string>& where) {
  Filter f;
  for (const auto& w : where) {
    auto eq = w.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::runtime_error("--where '" + w + "': expected KEY=VALUE, e.g. lattice=uniform");
    std::string key = w.substr(0, eq), value = w.substr(eq + 1);
    if (key == "scheme") {
      f.schemes.push_back(value);
      continue;
    }
    // The key must be a parameter of some job of the study.
    Stmt k = db.prepare("SELECT 1 FROM job_params p WHERE p.name=? AND EXISTS (SELECT 1 FROM "
                        "study_jobs sj WHERE sj.job_id=p.job_id AND sj.study_id=?) LIMIT 1");
    k.bind(1, key).bind(2, sid);
    if (!k.step()) {
      std::vector<std::string> names;
      Stmt n = db.prepare("SELECT DISTINCT name FROM job_params WHERE job_id IN (SELECT job_id "
                          "FROM study_jobs WHERE study_id=?) ORDER BY 1");
      n.bind(1, sid);
      while (n.step())
        names.push_back(n.text(0));
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

Stmt& bind_value(Stmt& s, int i, const Bind& b) {
  if (std::holds_alternative<double>(b))
    return s.bind(i, std::get<double>(b));
  if (std::holds_alternative<std::int64_t>(b))
    return s.bind(i, std::get<std::int64_t>(b));
  return s.bind(i, std::get<std::string>(b));
}

// A subquery `SELECT ... AS id` of the distinct jobs of study `sid` (current expansion) matching
// the filter's parameters; appends the values of its placeholders, in order, to `binds`.
std::string selected_jobs(Db& db, std::int64_t sid, const Filter& f, std::vector<Bind>& binds) {
  if (f.params.empty()) {
    binds.emplace_back(sid);
    return "SELECT DISTINCT job_id AS id FROM study_jobs WHERE study_id=? AND current";
  }
  // Most selective first: it drives the join, the others are primary-key look-ups.
  std::vector<std::pair<std::int64_t, std::size_t>> order;
  for (std::size_t i = 0; i < f.params.size(); ++i) {
    Stmt c = db.prepare("SELECT count(*) FROM job_params WHERE name=? AND value=?");
    c.bind(1, f.params[i].first);
    bind_value(c, 2, f.params[i].second);
    c.step();
    order.emplace_back(c.integer(0), i);
  }
  std::sort(order.begin(), order.end());
  std::string from = "job_params f0", cond;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto& [name, value] = f.params[order[k].second];
    std::string a = "f";
    a += std::to_string(k);
    if (k > 0) {
      from += " CROSS JOIN job_params ";
      from += a;
      cond += " AND " + a + ".job_id=f0.job_id AND ";
    }
    cond += a + ".name=? AND " + a + ".value=?";
    binds.emplace_back(name);
    binds.push_back(value);
  }
  binds.emplace_back(sid);
  return "SELECT f0.job_id AS id FROM " + from + " WHERE " + cond +
         " AND EXISTS (SELECT 1 FROM study_jobs sj WHERE sj.job_id=f0.job_id AND sj.study_id=? "
         "AND sj.current)";
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
      {"mean", "avg"}, {"min", "min"}, {"max", "max"}, {"count", "count"}};
  auto agg = aggs.find(t.agg);
  if (agg == aggs.end())
    throw std::runtime_error("--agg must be mean, min, max or count");
  if (t.format != "text" && t.format != "csv" && t.format != "markdown")
    throw std::runtime_error("--format must be text, csv or markdown");
  Store store = Store::open_read(db_path);
  Db& db = store.db();
  std::int64_t sid = study_id(db, t.study);
  json_path(t.rows);
  json_path(t.cols);
  Filter filter = where_filter(db, sid, t.where);
  auto expr = [&](const std::string& p) {
    return p == "scheme" ? std::string("j.scheme")
                         : "(SELECT value FROM job_params WHERE job_id=j.id AND name='" + p + "')";
  };
  std::vector<Bind> binds;
  std::string sel = selected_jobs(db, sid, filter, binds);
  std::string scheme_cond;
  for (const auto& sc : filter.schemes) {
    scheme_cond += " AND j.scheme = ?";
    binds.emplace_back(sc);
  }
  // CROSS JOIN keeps SQLite's join order: the selected jobs drive, the rest are look-ups.
  Stmt q = db.prepare("SELECT " + expr(t.rows) + ", " + expr(t.cols) + ", " + agg->second +
                      "(m.value) FROM (" + sel +
                      ") sel CROSS JOIN jobs j CROSS JOIN metrics m "
                      "WHERE j.id=sel.id AND m.job_id=sel.id AND m.name=?" +
                      scheme_cond + " GROUP BY 1, 2 ORDER BY 1, 2");
  int i = 1;
  for (std::size_t k = 0; k + filter.schemes.size() < binds.size(); ++k)
    bind_value(q, i++, binds[k]);
  q.bind(i++, t.metric);
  for (std::size_t k = binds.size() - filter.schemes.size(); k < binds.size(); ++k)
    bind_value(q, i++, binds[k]);
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
  auto key = [&](int i) {
    Key k{q.type(i) == SQLITE_INTEGER || q.type(i) == SQLITE_FLOAT, q.real(i), cell(q, i)};
    return k;
  };
  std::map<Key, std::map<Key, std::string>> cells;
  std::set<Key> cols;
  while (q.step()) {
    Key r = key(0), c = key(1);
    cols.insert(c);
    char buf[32];
    if (q.is_null(2))
      buf[0] = 0;
    else
      std::snprintf(buf, sizeof buf, "%.6g", q.real(2));
    cells[r][c] = buf;
  }
  if (cells.empty()) {
    Stmt m = db.prepare("SELECT DISTINCT m.name FROM metrics m JOIN study_jobs sj ON "
                        "sj.job_id=m.job_id WHERE sj.study_id=? ORDER BY 1");
    m.bind(1, sid);
    std::vector<std::string> names;
    while (m.step())
      names.push_back(m.text(0));
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
  std::vector<std::vector<std::string>> grid;
  std::vector<std::string> head{t.rows + " \\ " + t.cols};
  for (const auto& c : cols)
    head.push_back(c.s);
  grid.push_back(head);
  for (const auto& [r, row] : cells) {
    std::vector<std::string> line{r.s};
    for (const auto& c : cols) {
      auto it = row.find(c);
      line.push_back(it == row.end() ? "" : it->second);
    }
    grid.push_back(line);
  }
  // Stale results (made by other solver code) are shown, not hidden: a note under the table
  // (not in CSV, which stays a plain grid; `runner export` has a stale column).
  std::string stale_note;
  {
    Stmt c = db.prepare("SELECT count(*) FROM jobs j WHERE j.id IN (SELECT job_id FROM study_jobs "
                        "WHERE study_id=?1 AND current) AND " +
                        stale_sql(db, "j.id", "j.state", "?2"));
    c.bind(1, sid).bind(2, solver_fingerprint());
    if (c.step() && c.integer(0) > 0)
      stale_note = "note: " + std::to_string(c.integer(0)) + " of the study's finished jobs are " +
                   "stale (computed by other solver code than this build's; --rerun-stale)\n";
  }
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
  Db& db = store.db();
  std::int64_t sid = study_id(db, study);
  struct Row {
    std::string key, state, scheme;
    nlohmann::json params;
    std::map<std::string, std::optional<double>> metrics;
    bool stale = false; // made by other solver code than this build's
  };
  std::vector<Row> rows;
  std::map<std::int64_t, std::size_t> index;
  Stmt q = db.prepare(
      "SELECT j.id, j.key, j.state, j.scheme, j.params_json, " +
      stale_sql(db, "j.id", "j.state", "?2") +
      " FROM jobs j JOIN "
      "(SELECT job_id, min(ordinal) AS o FROM study_jobs WHERE study_id=?1 AND current GROUP "
      "BY job_id) sj ON sj.job_id=j.id ORDER BY sj.o");
  q.bind(1, sid).bind(2, solver_fingerprint());
  while (q.step()) {
    index[q.integer(0)] = rows.size();
    rows.push_back(
        {q.text(1), q.text(2), q.text(3), nlohmann::json::parse(q.text(4)), {}, q.integer(5) != 0});
  }
  std::vector<std::string> metric_names;
  Stmt m = db.prepare("SELECT m.job_id, m.name, m.value FROM metrics m WHERE m.job_id IN "
                      "(SELECT job_id FROM study_jobs WHERE study_id=?) ORDER BY m.job_id, "
                      "m.ordinal");
  m.bind(1, sid);
  while (m.step()) {
    auto it = index.find(m.integer(0));
    if (it == index.end())
      continue;
    std::string name = m.text(1);
    if (std::find(metric_names.begin(), metric_names.end(), name) == metric_names.end())
      metric_names.push_back(name);
    rows[it->second].metrics[name] = m.opt_real(2);
  }
  if (format == "json") {
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& r : rows) {
      nlohmann::json metrics = nlohmann::json::object();
      for (const auto& [k, v] : r.metrics)
        metrics[k] = v ? nlohmann::json(*v) : nlohmann::json();
      arr.push_back({{"job", r.key},
                     {"status", r.state},
                     {"scheme", r.scheme},
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
  out << "job,status,scheme";
  for (const auto& p : param_names)
    out << "," << csv_field(p);
  for (const auto& n : metric_names)
    out << "," << csv_field(n);
  out << ",stale\n"; // the last column: 1 when made by other solver code than this build's
  for (const auto& r : rows) {
    out << r.key << "," << r.state << "," << csv_field(r.scheme);
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

} // namespace sph::runner
