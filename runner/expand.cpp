// Study expansion: tier merge, product of axes and zip groups, exclusions, explicit cases, derived
// parameters in dependency order, per-job validation, keys and duplicate collapse.
#include "expand.hpp"

#include "diagnostics.hpp"
#include "job_key.hpp"
#include "params.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <unordered_set>

namespace sph::runner {

namespace {

// The study definition after applying a tier.
struct Definition {
  std::vector<Assignment> params;
  std::vector<Axis> sweep;
  std::vector<ZipGroup> zip;
  std::vector<ExplicitCase> cases;
  std::vector<Exclude> exclude;
};

template <class V>
auto find_named(V& v, const std::string& name) {
  return std::find_if(v.begin(), v.end(), [&](const auto& x) { return x.name == name; });
}

bool in_zip(const std::vector<ZipGroup>& zip, const std::string& name, int* line) {
  for (const auto& g : zip)
    for (const auto& a : g.axes)
      if (a.name == name) {
        *line = a.line;
        return true;
      }
  return false;
}

Definition apply_tier(const Study& s, const Tier* t, Diagnostics& diag) {
  Definition d{s.params, s.sweep, s.zip, s.cases, s.exclude};
  if (!t)
    return d;
  const std::string where = "[tiers." + t->name + "]";
  if (t->zip)
    d.zip = *t->zip;
  if (t->cases)
    d.cases = *t->cases;
  if (t->exclude)
    d.exclude = *t->exclude;
  int zline = 0;
  // A tier's fixed value pins a parameter the base sweeps; a tier's axis sweeps one it fixes.
  for (const auto& a : t->params) {
    if (!t->zip && in_zip(d.zip, a.name, &zline)) {
      diag.error(a.line, where + " params " + a.name + ": '" + a.name +
                             "' is in a [[zip]] group (line " + std::to_string(zline) +
                             "); override the zip groups in the tier instead");
      continue;
    }
    if (auto it = find_named(d.sweep, a.name); it != d.sweep.end())
      d.sweep.erase(it);
    if (auto it = find_named(d.params, a.name); it != d.params.end())
      *it = a;
    else
      d.params.push_back(a);
  }
  for (const auto& ax : t->sweep) {
    if (!t->zip && in_zip(d.zip, ax.name, &zline)) {
      diag.error(ax.line, where + " sweep " + ax.name + ": '" + ax.name +
                              "' is in a [[zip]] group (line " + std::to_string(zline) +
                              "); override the zip groups in the tier instead");
      continue;
    }
    if (auto it = find_named(d.params, ax.name); it != d.params.end())
      d.params.erase(it);
    if (auto it = find_named(d.sweep, ax.name); it != d.sweep.end())
      *it = ax;
    else
      d.sweep.push_back(ax);
  }
  // Zip groups given by the tier must not collide with the merged params and axes.
  if (t->zip)
    for (const auto& g : d.zip)
      for (const auto& a : g.axes) {
        if (auto it = find_named(d.params, a.name); it != d.params.end())
          diag.error(a.line, where + " zip " + a.name + ": '" + a.name +
                                 "' is also a fixed parameter (line " + std::to_string(it->line) +
                                 ")");
        if (auto it = find_named(d.sweep, a.name); it != d.sweep.end())
          diag.error(a.line, where + " zip " + a.name + ": '" + a.name +
                                 "' is also a sweep axis (line " + std::to_string(it->line) + ")");
      }
  return d;
}

// Derived parameters in an order where each comes after those it uses.
std::vector<const Derived*> derived_order(const Study& s, Diagnostics& diag) {
  std::vector<const Derived*> order;
  std::map<std::string, int> state; // 0 unvisited, 1 visiting, 2 done
  std::map<std::string, const Derived*> by_name;
  for (const auto& d : s.derived)
    by_name[d.name] = &d;
  std::function<bool(const Derived*)> visit = [&](const Derived* d) {
    int& st = state[d->name];
    if (st == 2)
      return true;
    if (st == 1) {
      diag.error(d->line, "[derived] " + d->name + ": circular definition (\"" + d->expr.text() +
                              "\" depends on itself)");
      return false;
    }
    st = 1;
    for (const auto& ref : d->expr.names())
      if (auto it = by_name.find(ref); it != by_name.end())
        if (!visit(it->second))
          return false;
    st = 2;
    order.push_back(d);
    return true;
  };
  for (const auto& d : s.derived)
    if (!visit(&d))
      break;
  return order;
}

std::optional<double> numeric(const Params& p, const std::string& name) {
  auto it = p.find(name);
  if (it == p.end())
    return std::nullopt;
  if (auto d = std::get_if<double>(&it->second))
    return *d;
  if (auto i = std::get_if<std::int64_t>(&it->second))
    return static_cast<double>(*i);
  return std::nullopt;
}

class Expander {
public:
  Expander(const Study& s, Diagnostics& diag) : s_(s), diag_(diag) {}

  // Computes derived values and checks them; false (after reporting) when the job is invalid.
  bool resolve(Params& p, const std::vector<const Derived*>& derived,
               const std::vector<ParamSpec>& specs, const std::string& scheme) {
    for (const Derived* d : derived) {
      const ParamSpec* spec = find_spec(specs, d->name);
      if (!spec) {
        report(d->line, "[derived] " + d->name + ": '" + d->name + "' is a parameter of scheme '" +
                            scheme_owning(*s_.info, d->name) + "', not of scheme '" + scheme +
                            "' that some jobs use");
        return false;
      }
      double x = 0;
      try {
        x = d->expr.eval([&](const std::string& n) { return numeric(p, n); });
      } catch (const ExprError& e) {
        report(d->line,
               "[derived] " + d->name + ": " + e.what() + " in \"" + d->expr.text() + "\"");
        return false;
      }
      ParamValue v = x;
      if (!std::isfinite(x)) {
        report(d->line, "[derived] " + d->name + " = \"" + d->expr.text() + "\" evaluates to " +
                            format_real(x) + " for " + describe(p, d->expr.names()));
        return false;
      }
      if (spec->type == ParamType::Int) {
        double r = std::round(x);
        if (std::abs(x - r) > 1e-9 * std::max(1.0, std::abs(x))) {
          report(d->line, "[derived] " + d->name + " = \"" + d->expr.text() + "\" gives " +
                              format_real(x) + " for " + describe(p, d->expr.names()) + ", but '" +
                              d->name +
                              "' is an integer; wrap the expression in round(), floor() or ceil()");
          return false;
        }
        v = static_cast<std::int64_t>(r);
      }
      if (auto err = check_value(*spec, v)) {
        report(d->line, "[derived] " + d->name + " = \"" + d->expr.text() + "\": " + *err +
                            " for " + describe(p, d->expr.names()));
        return false;
      }
      p[d->name] = v;
    }
    return true;
  }

  void report(int line, const std::string& msg) {
    if (reported_.insert(msg).second)
      diag_.error(line, msg);
  }

private:
  const Study& s_;
  Diagnostics& diag_;
  std::set<std::string> reported_;

  static std::string describe(const Params& p, const std::vector<std::string>& names) {
    std::string s;
    for (const auto& n : names) {
      auto it = p.find(n);
      if (it == p.end())
        continue;
      s += (s.empty() ? "" : ", ") + n + " = " + format_value(it->second);
    }
    return s.empty() ? "this job" : s;
  }
};

// `text` names `word` as a whole identifier.
bool mentions(const std::string& text, const std::string& word) {
  auto ident = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (auto pos = text.find(word); pos != std::string::npos; pos = text.find(word, pos + 1)) {
    bool left = pos == 0 || !ident(text[pos - 1]);
    bool right = pos + word.size() >= text.size() || !ident(text[pos + word.size()]);
    if (left && right)
      return true;
  }
  return false;
}

bool matches(const Params& p, const Exclude& e) {
  for (const auto& a : e.match) {
    auto it = p.find(a.name);
    if (it == p.end() || !(it->second == a.value))
      return false;
  }
  return true;
}

} // namespace

JobSpec make_job(const Study& study, Params params, const std::vector<ParamSpec>& specs) {
  JobSpec job;
  job.case_name = study.case_name;
  if (auto it = params.find(scheme_param); it != params.end())
    job.scheme = std::get<std::string>(it->second);
  job.params_json = identity_params_text(specs, params);
  job.canonical = canonical_job_text(job.case_name, job.scheme, job.params_json, numerics_version);
  job.key = job_key(job.canonical);
  job.params = std::move(params);
  return job;
}

JobSpec make_job(const Study& study, Params params) {
  std::string scheme;
  if (auto it = params.find(scheme_param); it != params.end())
    scheme = std::get<std::string>(it->second);
  return make_job(study, std::move(params), job_specs(*study.info, scheme));
}

namespace {

// A job key in binary: the 32 bytes its 64 hex digits spell (the set of keys met holds these).
using BinaryKey = std::array<unsigned char, 32>;

BinaryKey binary_key(const std::string& hex) {
  auto nibble = [](char c) {
    return static_cast<unsigned char>(c <= '9' ? c - '0' : c - 'a' + 10);
  };
  BinaryKey k{};
  for (std::size_t i = 0; i < k.size(); ++i)
    k[i] = static_cast<unsigned char>(nibble(hex[2 * i]) << 4 | nibble(hex[2 * i + 1]));
  return k;
}

// The bytes of a SHA-256 are uniformly distributed: the first eight are a hash.
struct BinaryKeyHash {
  std::size_t operator()(const BinaryKey& k) const noexcept {
    std::size_t h;
    std::memcpy(&h, k.data(), sizeof h);
    return h;
  }
};

} // namespace

struct JobStream::Impl {
  // A point of a dimension of the product: the values it assigns.
  using Point = std::vector<std::pair<const std::string*, const ParamValue*>>;

  const Study& study;
  const CaseInfo& info;
  Diagnostics diag;
  Expander ex;
  const Tier* tier = nullptr;
  Definition def;
  std::vector<const Derived*> derived;
  Params fixed;                      // explicit values shared by every job
  std::map<std::string, int> set_at; // the line where each parameter is set
  std::vector<std::vector<Point>> dims;
  std::map<std::string, std::vector<ParamSpec>> specs_by_scheme;
  std::map<std::string, Params> defaults_by_scheme;
  std::unordered_set<BinaryKey, BinaryKeyHash> keys;
  std::vector<std::size_t> idx; // the odometer over dims: the next combination
  std::size_t n = 0;            // its index
  std::size_t next_case = 0;
  bool done = false;
  ExpansionSummary sum;
  // Parameters that take different values between the jobs that have them (a scheme's parameters
  // are absent from the other schemes' jobs: that alone is told by `scheme`, not a variation).
  std::map<std::string, ParamValue> seen; // each parameter's value in the first job that has it
  std::set<std::string> differs;

  Impl(const Study& s, const std::string& tier_name, std::size_t max_jobs);
  const std::vector<ParamSpec>& specs_of(const std::string& scheme);
  std::optional<Params> build(const Params& given, int origin_line);
  bool keep(Params p, JobSpec& job);
  bool next(JobSpec& job);
};

JobStream::Impl::Impl(const Study& s, const std::string& tier_name, std::size_t max_jobs)
    : study(s), info(*s.info), diag(s.file), ex(s, diag) {
  if (!tier_name.empty() && tier_name != full_tier) {
    tier = study.find_tier(tier_name);
    if (!tier) {
      auto names = study.tier_names();
      diag.error(0, "no tier named '" + tier_name + "'" + did_you_mean(tier_name, names) +
                        (names.empty() ? "; the study defines no tiers"
                                       : "; defined tiers: " + quoted_list(names)));
      diag.throw_if_any();
    }
  }
  sum.tier = tier ? tier->name : full_tier;
  def = apply_tier(study, tier, diag);
  derived = derived_order(study, diag);
  diag.throw_if_any();

  for (const auto& a : def.params)
    fixed[a.name] = a.value;
  for (const auto& a : def.params)
    set_at.emplace(a.name, a.line);
  for (const auto& a : def.sweep)
    set_at.emplace(a.name, a.line);
  for (const auto& g : def.zip)
    for (const auto& a : g.axes)
      set_at.emplace(a.name, a.line);
  for (const auto& c : def.cases)
    for (const auto& a : c.overrides)
      set_at.emplace(a.name, a.line);

  // Dimensions of the product: each a list of points.
  for (const auto& ax : def.sweep) {
    std::vector<Point> pts;
    for (const auto& v : ax.values)
      pts.push_back({{&ax.name, &v}});
    dims.push_back(std::move(pts));
  }
  for (const auto& g : def.zip) {
    std::vector<Point> pts(g.length());
    for (std::size_t i = 0; i < g.length(); ++i)
      for (const auto& a : g.axes)
        pts[i].push_back({&a.name, &a.values[i]});
    dims.push_back(std::move(pts));
  }

  // With no axes the product is the single base job, unless explicit cases replace it. Counted
  // before anything is expanded (in long double: 1e18 jobs must not wrap around).
  std::size_t total = dims.empty() && !def.cases.empty() ? 0 : 1;
  {
    long double count = static_cast<long double>(total);
    std::string factors;
    int line = 0;
    std::size_t largest = 0;
    auto factor = [&](std::size_t n, int at, const std::string& what) {
      count *= static_cast<long double>(n);
      factors += (factors.empty() ? "" : " x ") + std::to_string(n) + " (" + what + ")";
      if (n > largest)
        largest = n, line = at;
    };
    for (const auto& ax : def.sweep)
      factor(ax.values.size(), ax.line, ax.name);
    for (const auto& g : def.zip)
      factor(g.length(), g.line, "zip group");
    count += static_cast<long double>(def.cases.size());
    if (count > static_cast<long double>(max_jobs)) {
      char buf[64];
      std::snprintf(buf, sizeof buf, count < 1e15L ? "%.0Lf" : "%.3Le", count);
      diag.error(
          line,
          std::string("the study") + (tier ? " (tier '" + tier->name + "')" : std::string()) +
              " expands to " + buf + " jobs" + (factors.empty() ? "" : " = " + factors) +
              (def.cases.empty() ? "" : " + " + std::to_string(def.cases.size()) + " [[cases]]") +
              ", more than the limit of " + std::to_string(max_jobs) +
              "; sweep fewer values, or raise the limit with --max-jobs N");
      diag.throw_if_any();
    }
  }
  for (const auto& d : dims)
    total *= d.size();
  sum.combinations = total;
  keys.reserve(total + def.cases.size());
  idx.assign(dims.size(), 0);
}

const std::vector<ParamSpec>& JobStream::Impl::specs_of(const std::string& scheme) {
  auto [it, fresh] = specs_by_scheme.try_emplace(scheme);
  if (fresh)
    it->second = job_specs(info, scheme);
  return it->second;
}

// A job's full parameter set from its explicit values: its scheme's specs, defaults, derived.
std::optional<Params> JobStream::Impl::build(const Params& given, int origin_line) {
  std::string scheme;
  if (!info.schemes.empty()) {
    auto it = given.find(scheme_param);
    scheme = it == given.end() ? info.schemes.front() : std::get<std::string>(it->second);
  }
  const auto& specs = specs_of(scheme);
  for (const auto& [k, v] : given)
    if (!find_spec(specs, k)) {
      auto at = set_at.find(k);
      ex.report(at == set_at.end() ? origin_line : at->second,
                "'" + k + "' is a parameter of scheme '" + scheme_owning(info, k) +
                    "', not of scheme '" + scheme +
                    "' that some jobs use; set it per scheme with [[zip]] or [[cases]]");
      return std::nullopt;
    }
  auto [dit, fresh_defaults] = defaults_by_scheme.try_emplace(scheme);
  if (fresh_defaults)
    for (const auto& sp : specs)
      dit->second[sp.name] = sp.default_value;
  Params p = dit->second;
  for (const auto& [k, v] : given)
    p[k] = v;
  if (!ex.resolve(p, derived, specs, scheme))
    return std::nullopt;
  if (info.check)
    if (auto bad = info.check(p)) {
      // Name the line of a parameter the case's message mentions (dx in "1/dx must be...").
      int line = origin_line;
      for (const auto& [name, at] : set_at)
        if (mentions(*bad, name)) {
          line = at;
          break;
        }
      ex.report(line, "case '" + info.name + "'" +
                          (scheme.empty() ? std::string() : " (scheme '" + scheme + "')") + ": " +
                          *bad);
      return std::nullopt;
    }
  return p;
}

// Keys the job; false when its key was met before (a duplicate, collapsed).
bool JobStream::Impl::keep(Params p, JobSpec& job) {
  std::string scheme;
  if (auto it = p.find(scheme_param); it != p.end())
    scheme = std::get<std::string>(it->second);
  JobSpec j = make_job(study, std::move(p), specs_of(scheme));
  if (!keys.insert(binary_key(j.key)).second) {
    ++sum.duplicates;
    return false;
  }
  for (const auto& [name, value] : j.params) {
    const auto [it, added] = seen.emplace(name, value);
    if (!added && !(it->second == value))
      differs.insert(name);
  }
  ++sum.size;
  job = std::move(j);
  return true;
}

bool JobStream::Impl::next(JobSpec& job) {
  while (n < sum.combinations && diag.size() < 25) {
    Params given = fixed;
    for (std::size_t k = 0; k < dims.size(); ++k)
      for (const auto& [name, value] : dims[k][idx[k]])
        given[*name] = *value;
    // Advance the odometer: the last dimension varies fastest.
    ++n;
    for (std::size_t k = dims.size(); k-- > 0;) {
      if (++idx[k] < dims[k].size())
        break;
      idx[k] = 0;
    }
    auto p = build(given, 0);
    if (!p)
      continue;
    bool drop = false;
    for (const auto& e : def.exclude)
      drop = drop || matches(*p, e);
    if (drop) {
      ++sum.excluded;
      continue;
    }
    if (keep(std::move(*p), job))
      return true;
  }
  while (next_case < def.cases.size()) {
    const auto& c = def.cases[next_case++];
    Params given = fixed;
    for (const auto& a : c.overrides)
      given[a.name] = a.value;
    if (auto p = build(given, c.line))
      if (keep(std::move(*p), job))
        return true;
  }
  if (!done) {
    done = true;
    diag.throw_if_any();
    for (const auto& sp : study.specs) // in spec order
      if (differs.count(sp.name))
        sum.varying.push_back(sp.name);
  }
  return false;
}

JobStream::JobStream(const Study& study, const std::string& tier, std::size_t max_jobs)
    : impl_(std::make_unique<Impl>(study, tier, max_jobs)) {}
JobStream::JobStream(JobStream&&) noexcept = default;
JobStream& JobStream::operator=(JobStream&&) noexcept = default;
JobStream::~JobStream() = default;

bool JobStream::next(JobSpec& job) {
  return impl_->next(job);
}

const ExpansionSummary& JobStream::summary() const {
  return impl_->sum;
}

const JobSpec& JobCursor::at(std::size_t ordinal) {
  if (ordinal + 1 < next_)
    throw std::out_of_range("JobCursor: job " + std::to_string(ordinal) + " is behind the cursor");
  while (next_ <= ordinal) {
    if (!jobs_.next(job_))
      throw std::out_of_range("JobCursor: no job " + std::to_string(ordinal));
    ++next_;
  }
  return job_;
}

ExpansionSummary for_each_job(const Study& study, const std::string& tier, std::size_t max_jobs,
                              const std::function<void(JobSpec&)>& f) {
  JobStream jobs(study, tier, max_jobs);
  JobSpec job;
  while (jobs.next(job))
    f(job);
  return jobs.summary();
}

Expansion expand(const Study& study, const std::string& tier, std::size_t max_jobs) {
  Expansion out;
  ExpansionSummary sum =
      for_each_job(study, tier, max_jobs, [&](JobSpec& j) { out.jobs.push_back(std::move(j)); });
  static_cast<ExpansionSummary&>(out) = std::move(sum);
  return out;
}

} // namespace sph::runner
