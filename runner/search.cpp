// Stability-edge search by bisection: see search.hpp.
#include "search.hpp"

#include "overrides.hpp"
#include "params.hpp"
#include "store.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

namespace sph::runner {

namespace {

double number_of(const ParamValue& v) {
  if (const auto* d = std::get_if<double>(&v))
    return *d;
  if (const auto* i = std::get_if<std::int64_t>(&v))
    return static_cast<double>(*i);
  return std::numeric_limits<double>::quiet_NaN();
}

bool same_value(double x, double y) {
  return std::abs(x - y) <= 1e-12 * std::max(std::abs(x), std::abs(y));
}

// The parameters that make a group: every identity parameter of a job but the searched one and
// the derived ones (a time step derived from the searched value differs from probe to probe).
std::string group_key(const std::string& params_json, const Study& study) {
  nlohmann::json j = nlohmann::json::parse(params_json, nullptr, false);
  if (!j.is_object())
    return params_json;
  j.erase(study.search->param);
  for (const auto& d : study.derived)
    j.erase(d.name);
  return j.dump();
}

std::string group_label(const Params& p, const Study& study, const std::set<std::string>& varying) {
  std::string s;
  for (const auto& [name, v] : p)
    if (varying.count(name) && name != study.search->param)
      s += (s.empty() ? "" : " ") + name + "=" + format_value_plain(v);
  return s.empty() ? "(all)" : s;
}

std::string short_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

struct Group {
  std::string key;
  Params params;
};

// The groups: the jobs of the selection (tier, --set, --where), one per group key.
std::vector<Group> groups_of(const Selection& sel, const Study& study) {
  std::vector<Group> out;
  std::set<std::string> seen;
  JobStream jobs = sel.jobs();
  JobSpec j;
  while (jobs.next(j))
    if (matches_where(j.params, sel.where)) {
      std::string k = group_key(j.params_json, study);
      if (seen.insert(k).second)
        out.push_back({std::move(k), j.params});
    }
  return out;
}

// The recorded probes of each group (jobs of the study's search tier that finished).
std::map<std::string, std::vector<Probe>> recorded_probes(Store& store, const Study& study,
                                                          const std::string& label) {
  std::map<std::string, std::vector<Probe>> out;
  const auto st = store.find_study(study.name);
  if (!st)
    return out;
  const Search& s = *study.search;
  const ParamSpec* spec = find_spec(study.specs, s.param);
  const double fallback = spec ? number_of(spec->default_value) : 0.0;
  std::map<std::int64_t, std::map<std::string, double>> metrics;
  if (!s.unstable_above.empty() || !s.unstable_below.empty())
    for (const MetricValue& m : store.study_metrics(st->id))
      if (m.value)
        metrics[m.job_id][m.name] = *m.value;
  for (const StudyJob& job : store.study_jobs(st->id, label, true, "")) {
    Verdict v;
    if (job.state == JobState::done)
      v = Verdict::stable;
    else if (job.state == JobState::diverged)
      v = Verdict::unstable;
    else if (job.state == JobState::failed || job.state == JobState::timeout)
      v = Verdict::failed;
    else
      continue; // pending, running, submitted: not yet a probe
    if (v == Verdict::stable) {
      const auto& m = metrics[job.id];
      for (const auto& [name, bound] : s.unstable_above)
        if (auto it = m.find(name); it != m.end() && it->second > bound)
          v = Verdict::unstable;
      for (const auto& [name, bound] : s.unstable_below)
        if (auto it = m.find(name); it != m.end() && it->second < bound)
          v = Verdict::unstable;
    }
    const nlohmann::json p = nlohmann::json::parse(job.params_json, nullptr, false);
    double value = fallback;
    if (p.is_object())
      if (auto it = p.find(s.param); it != p.end() && it->is_number())
        value = it->get<double>();
    out[group_key(job.params_json, study)].push_back({value, v});
  }
  return out;
}

} // namespace

Bracket bracket_of(const Search& s, const std::vector<Probe>& probes) {
  Bracket r;
  r.probes = probes.size();
  auto t = [&](double v) {
    return s.log ? std::log(v / s.lo) / std::log(s.hi / s.lo) : (v - s.lo) / (s.hi - s.lo);
  };
  auto find = [&](double v) -> const Probe* {
    for (const Probe& p : probes)
      if (same_value(p.value, v))
        return &p;
    return nullptr;
  };
  for (const Probe& p : probes)
    if (p.verdict == Verdict::failed) {
      r.state = "a probe failed at " + short_number(p.value) +
                " (runner status shows why; --retry-failed runs it again)";
      return r;
    }
  const Probe* plo = find(s.lo);
  if (!plo) {
    r.next = s.lo, r.state = "searching";
    return r;
  }
  if (plo->verdict == Verdict::unstable) {
    r.b = s.lo, r.state = "unstable at lo: the edge lies beyond lo";
    return r;
  }
  const Probe* phi = find(s.hi);
  if (!phi) {
    r.a = s.lo, r.next = s.hi, r.state = "searching";
    return r;
  }
  if (phi->verdict == Verdict::stable) {
    r.a = s.hi, r.state = "stable at hi: the edge lies beyond hi";
    return r;
  }
  double tb = std::numeric_limits<double>::infinity();
  for (const Probe& p : probes)
    if (p.verdict == Verdict::unstable && t(p.value) >= 0 && t(p.value) < tb)
      tb = t(p.value), r.b = p.value;
  double ta = -std::numeric_limits<double>::infinity();
  for (const Probe& p : probes)
    if (p.verdict == Verdict::stable) {
      const double tp = t(p.value);
      if (tp < tb && tp > ta)
        ta = tp, r.a = p.value;
      if (tp > tb)
        r.non_monotone = true;
    }
  const double a = *r.a, b = *r.b;
  if (std::abs(b - a) <= s.until * std::abs(a)) {
    r.state = "bracketed";
    return r;
  }
  r.next = s.log ? std::sqrt(a * b) : 0.5 * (a + b);
  r.state = "searching";
  return r;
}

std::vector<GroupBracket> search_brackets(const Study& study, const RunOptions& opts,
                                          Store* store) {
  const Selection sel = select_jobs(study, opts);
  const std::vector<Group> groups = groups_of(sel, study);
  std::map<std::string, std::vector<Probe>> probes;
  if (store)
    probes = recorded_probes(*store, study, sel.label);
  std::map<std::string, std::set<std::string>> values;
  for (const Group& g : groups)
    for (const auto& [name, v] : g.params)
      values[name].insert(format_value_plain(v));
  std::set<std::string> varying;
  for (const auto& [name, vs] : values)
    if (vs.size() > 1)
      varying.insert(name);
  const ParamSpec* spec = find_spec(study.specs, study.search->param);
  const bool integer = spec && spec->type == ParamType::Int;
  std::vector<GroupBracket> out;
  for (const Group& g : groups) {
    GroupBracket gb{group_label(g.params, study, varying), g.params,
                    bracket_of(*study.search, probes[g.key])};
    if (integer && gb.bracket.next) {
      // An integer parameter: the bracket cannot be narrower than 1.
      const double n = std::round(*gb.bracket.next);
      if ((gb.bracket.a && same_value(n, *gb.bracket.a)) ||
          (gb.bracket.b && same_value(n, *gb.bracket.b)))
        gb.bracket.next.reset(), gb.bracket.state = "bracketed (adjacent integers)";
      else
        gb.bracket.next = n;
    }
    out.push_back(std::move(gb));
  }
  return out;
}

namespace {

void print_brackets(const Study& study, const std::vector<GroupBracket>& groups,
                    std::ostream& out) {
  const Search& s = *study.search;
  out << study.name << ": stability edge of " << s.param
      << " (stable at lo = " << short_number(s.lo) << ", unstable at hi = " << short_number(s.hi)
      << ", until " << short_number(s.until) << (s.log ? ", log scale" : "") << ")\n";
  std::vector<std::vector<std::string>> rows = {
      {"group", "probes", "edge_lo (stable)", "edge_hi (unstable)", "state"}};
  for (const GroupBracket& g : groups) {
    const Bracket& b = g.bracket;
    std::string state = b.state + (b.non_monotone ? "; a stable probe lies beyond edge_hi" : "");
    if (b.next)
      state += "; next probe " + short_number(*b.next);
    rows.push_back({g.label, std::to_string(b.probes), b.a ? short_number(*b.a) : "-",
                    b.b ? short_number(*b.b) : "-", state});
  }
  std::vector<std::size_t> w(rows[0].size(), 0);
  for (const auto& r : rows)
    for (std::size_t k = 0; k < r.size(); ++k)
      w[k] = std::max(w[k], r[k].size());
  for (const auto& r : rows) {
    std::string line;
    for (std::size_t k = 0; k < r.size(); ++k)
      line += r[k] + (k + 1 < r.size() ? std::string(w[k] - r[k].size() + 2, ' ') : "");
    out << line << "\n";
  }
}

std::optional<Store> open_if_exists(const RunOptions& opts) {
  std::error_code ec;
  if (!std::filesystem::exists(opts.db_path, ec))
    return std::nullopt;
  return Store::open_read(opts.db_path);
}

} // namespace

int run_search(const Study& study, const RunOptions& opts, std::ostream& out, std::ostream& err) {
  const Search& s = *study.search;
  const Selection sel = select_jobs(study, opts);
  const ParamSpec* spec = find_spec(study.specs, s.param);
  const bool integer = spec && spec->type == ParamType::Int;
  std::set<std::string> derived;
  for (const auto& d : study.derived)
    derived.insert(d.name);
  int code = 0;
  for (int round = 1;; ++round) {
    std::vector<GroupBracket> groups;
    {
      std::optional<Store> store = open_if_exists(opts);
      groups = search_brackets(study, opts, store ? &*store : nullptr);
    }
    // The probes of this round: every unfinished group's next value, as explicit jobs of a study
    // with the same name (accumulating: earlier probes stay members of the tier).
    Study probe = sel.study;
    probe.sweep.clear(), probe.zip.clear(), probe.exclude.clear(), probe.params.clear();
    probe.cases.clear(), probe.tiers.clear();
    probe.search.reset();
    probe.accumulate = true;
    for (const GroupBracket& g : groups) {
      if (!g.bracket.next)
        continue;
      ExplicitCase c;
      for (const auto& [name, v] : g.params)
        if (name != s.param && !derived.count(name))
          c.overrides.push_back({name, v, s.line});
      c.overrides.push_back({s.param,
                             integer ? ParamValue(static_cast<std::int64_t>(*g.bracket.next))
                                     : ParamValue(*g.bracket.next),
                             s.line});
      probe.cases.push_back(std::move(c));
    }
    if (probe.cases.empty() || opts.dry_run) {
      print_brackets(study, groups, out);
      if (opts.dry_run && !probe.cases.empty())
        out << "(dry run: " << probe.cases.size() << " probe(s) would run next)\n";
      break;
    }
    out << study.name << ": search round " << round << ", " << probe.cases.size() << " probe(s)\n";
    RunOptions po = opts;
    po.set.clear(), po.where.clear();
    po.tier.clear();
    if (sel.label != full_tier) {
      Tier t;
      t.name = sel.label;
      probe.tiers.push_back(t);
      po.tier = sel.label;
    }
    const int rc = run_study(probe, po, out, err);
    if (rc >= 128)
      return rc; // interrupted: the next run resumes from the recorded probes
    code = std::max(code, rc);
  }
  return code;
}

} // namespace sph::runner
