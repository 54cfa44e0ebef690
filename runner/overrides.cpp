// --set, --where and `runner one`: parameters from the command line, typed by their specs.
#include "overrides.hpp"

#include "diagnostics.hpp"
#include "executor.hpp"
#include "params.hpp"
#include "store.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <set>

namespace sph::runner {

namespace {

[[noreturn]] void fail(const std::string& message) {
  throw StudyError({{"command line", 0, 0, message}});
}

// The text of a value as the spec's type reads it; anything else stays a string, so that
// check_value names what was expected and what was given.
ParamValue typed(const ParamSpec& spec, const std::string& text) {
  auto as_int = [&](std::int64_t& out) {
    errno = 0;
    char* end = nullptr;
    long long x = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || !end || *end != 0 || errno == ERANGE)
      return false;
    out = x;
    return true;
  };
  auto as_real = [&](double& out) {
    char* end = nullptr;
    double x = std::strtod(text.c_str(), &end);
    if (text.empty() || !end || *end != 0)
      return false;
    out = x;
    return true;
  };
  switch (spec.type) {
  case ParamType::Bool:
    if (text == "true" || text == "false")
      return text == "true";
    return text;
  case ParamType::Int: {
    std::int64_t i;
    double x;
    if (as_int(i))
      return i;
    if (as_real(x))
      return x;
    return text;
  }
  case ParamType::Real: {
    double x;
    if (as_real(x))
      return x;
    return text;
  }
  case ParamType::String:
    return text;
  }
  return text;
}

std::string spec_summary(const ParamSpec& spec) {
  std::string c = constraint_text(spec);
  return spec.name + " is " + type_phrase(spec.type) + (c.empty() ? "" : " " + c) + " (" +
         spec.doc + ")";
}

} // namespace

Assignment parse_assignment(const std::vector<ParamSpec>& specs, const std::string& kv,
                            const std::string& option) {
  const auto eq = kv.find('=');
  if (eq == std::string::npos || eq == 0)
    fail(option + " '" + kv + "': expected KEY=VALUE, e.g. n_side=40");
  const std::string key = kv.substr(0, eq), text = kv.substr(eq + 1);
  const ParamSpec* spec = find_spec(specs, key);
  if (!spec) {
    std::vector<std::string> names = spec_names(specs);
    fail(option + " " + kv + ": unknown parameter '" + key + "'" + did_you_mean(key, names) +
         "; parameters: " + quoted_list(names));
  }
  ParamValue v = typed(*spec, text);
  if (auto err = check_value(*spec, v))
    fail(option + " " + kv + ": " + *err + "; " + spec_summary(*spec));
  return {key, v, 0};
}

void apply_overrides(Study& s, const std::vector<Assignment>& sets) {
  for (const auto& a : sets) {
    auto named = [&](const auto& item) { return item.name == a.name; };
    auto drop_axes = [&](std::vector<Axis>& axes) { std::erase_if(axes, named); };
    auto drop_zip = [&](std::vector<ZipGroup>& zip) {
      for (auto& z : zip)
        drop_axes(z.axes);
      std::erase_if(zip, [](const ZipGroup& z) { return z.axes.empty(); });
    };
    auto drop_cases = [&](std::vector<ExplicitCase>& cases) {
      for (auto& c : cases)
        std::erase_if(c.overrides, named);
    };
    drop_axes(s.sweep);
    drop_zip(s.zip);
    drop_cases(s.cases);
    std::erase_if(s.derived, named);
    for (auto& t : s.tiers) {
      std::erase_if(t.params, named);
      drop_axes(t.sweep);
      if (t.zip)
        drop_zip(*t.zip);
      if (t.cases)
        drop_cases(*t.cases);
    }
    std::erase_if(s.params, named);
    s.params.push_back(a);
  }
}

std::string overrides_label(const std::vector<Assignment>& sets) {
  std::string s;
  for (const auto& a : sets)
    s += (s.empty() ? "" : ",") + a.name + "=" + format_value_plain(a.value);
  return s;
}

bool matches_where(const Params& params, const std::vector<Assignment>& where) {
  for (const auto& w : where)
    if (auto it = params.find(w.name); it == params.end() || !(it->second == w.value))
      return false;
  return true;
}

void fail_where(JobStream jobs, const std::vector<Assignment>& where, const std::string& tier) {
  // Say which filter matched nothing, and what the study has.
  std::vector<std::vector<std::string>> values(where.size()); // in expansion order
  std::vector<std::set<std::string>> seen(where.size());
  std::vector<bool> any(where.size(), false);
  JobSpec j;
  while (jobs.next(j))
    for (std::size_t i = 0; i < where.size(); ++i)
      if (auto it = j.params.find(where[i].name); it != j.params.end()) {
        std::string v = format_value_plain(it->second);
        if (seen[i].insert(v).second)
          values[i].push_back(v);
        any[i] = any[i] || it->second == where[i].value;
      }
  for (std::size_t i = 0; i < where.size(); ++i) {
    const Assignment& w = where[i];
    if (!any[i])
      fail("--where " + w.name + "=" + format_value_plain(w.value) + ": no job of the study" +
           (tier == full_tier ? std::string() : " (tier " + tier + ")") + " has " + w.name + " = " +
           format_value_plain(w.value) + "; its values: " + quoted_list(values[i]));
  }
  fail("--where: no job of the study matches every filter together");
}

Study adhoc_study(const std::string& case_name, const std::string& scheme,
                  const std::vector<std::string>& assignments) {
  Study s;
  s.name = adhoc_study_name;
  s.case_name = case_name;
  s.description = "jobs run one at a time with `runner one`";
  s.info = find_case(case_name);
  if (!s.info) {
    std::vector<std::string> known;
    for (const auto& ci : case_registry())
      known.push_back(ci.name);
    fail("runner one: unknown case '" + case_name + "'" + did_you_mean(case_name, known) +
         "; cases: " + quoted_list(known) + " (runner cases lists them with their parameters)");
  }
  s.specs = study_specs(*s.info);
  s.accumulate = true;
  if (!scheme.empty()) {
    if (s.info->schemes.empty())
      fail("runner one --scheme " + scheme + ": case '" + case_name + "' takes no scheme");
    s.params.push_back(
        parse_assignment(s.specs, std::string(scheme_param) + "=" + scheme, "runner one --scheme"));
  }
  std::set<std::string> seen;
  for (const auto& kv : assignments) {
    Assignment a = parse_assignment(s.specs, kv, "runner one");
    if (!seen.insert(a.name).second)
      fail("runner one " + kv + ": '" + a.name + "' is given twice");
    if (a.name == scheme_param && !scheme.empty())
      fail("runner one " + kv + ": the scheme is given twice (--scheme and scheme=)");
    s.params.push_back(a);
  }
  return s;
}

int cmd_one(const Study& adhoc, const RunOptions& opts_in, std::ostream& out, std::ostream& err) {
  RunOptions opts = opts_in;
  opts.keep_logs = true;
  opts.set.clear();
  opts.where.clear();
  opts.tier.clear();
  const Expansion ex = expand(adhoc, "", opts.max_jobs);
  if (ex.jobs.size() != 1)
    fail("runner one: expected one job, the parameters give " + std::to_string(ex.jobs.size()));
  const JobSpec& job = ex.jobs.front();
  std::string label = job.case_name + (job.scheme.empty() ? "" : " (" + job.scheme + ")");
  for (const auto& a : adhoc.params)
    if (a.name != scheme_param)
      label += " " + a.name + "=" + format_value_plain(a.value);
  const int rc = run_study(adhoc, opts, out, err);
  if (opts.dry_run)
    return rc;
  Store store = Store::open_read(opts.db_path);
  auto j = store.job_summary(job.key);
  if (!j) {
    err << "runner one: job " << job.key << " is not in " << opts.db_path.string() << "\n";
    return rc ? rc : 1;
  }
  out << "\n"
      << label << ": " << to_string(j->state) << "\njob " << job.key << " (study "
      << adhoc_study_name << ", attempt " << j->attempts << ")\n";
  if (!j->metrics.empty()) {
    out << "metrics:\n";
    std::size_t w = 0;
    for (const auto& [name, v] : j->metrics)
      w = std::max(w, name.size());
    for (const auto& [name, v] : j->metrics) {
      char buf[64];
      if (v)
        std::snprintf(buf, sizeof buf, "%.10g", *v);
      else
        std::snprintf(buf, sizeof buf, "nan");
      out << "  " << name << std::string(w - name.size() + 2, ' ') << buf << "\n";
    }
  }
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path dir = j->output_dir;
  if (!dir.empty()) {
    const fs::path log = dir / ("attempt-" + std::to_string(j->attempts) + ".log");
    out << "log:     " << (fs::exists(log, ec) ? log.string() : std::string("(none kept)")) << "\n";
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.path().filename().string().rfind("attempt-", 0) != 0 &&
          e.path().filename().string()[0] != '.')
        files.push_back(e.path().filename().string());
    std::sort(files.begin(), files.end());
    out << "outputs: " << dir.string() << "/";
    for (std::size_t i = 0; i < files.size(); ++i)
      out << (i ? ", " : " (") << files[i] << (i + 1 == files.size() ? ")" : "");
    out << "\n";
  }
  return rc;
}

} // namespace sph::runner
