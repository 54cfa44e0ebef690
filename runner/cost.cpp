// Cost estimates of jobs before they run (cost.hpp).
#include "cost.hpp"

#include "cases/case.hpp"
#include "schemes/scheme.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <variant>

namespace sph::runner {

namespace {

std::optional<double> number(const JobSpec& job, const std::string& name) {
  auto it = job.params.find(name);
  if (it == job.params.end())
    return std::nullopt;
  if (auto d = std::get_if<double>(&it->second))
    return *d;
  if (auto i = std::get_if<std::int64_t>(&it->second))
    return static_cast<double>(*i);
  return std::nullopt;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// CPU seconds per particle and elementary step when the database has nothing to calibrate from:
// the median over the published runs of each scheme (docs/results/*.csv, cpu_time_s /
// (n_particles x work steps), jobs of at least 2 CPU s, one core; docs/runner.md). `case_name`
// (if set) must be the job's case, `param` (if set) must have `value` in the job; the first entry
// that matches is taken, so a case's own entry stands before its scheme's.
struct Default {
  const char* scheme;
  int dim;
  const char* case_name;
  const char* param;
  double value;
  double s_per_particle_step;
  const char* source;
};
const Default defaults[] = {
    {"alsph", 2, nullptr, "algorithm", 1, 5.06e-6, "Algorithm 1, published runs at D/dx = 10"},
    {"alsph", 2, nullptr, "algorithm", 2, 2.10e-6, "Algorithm 2, published runs at D/dx = 10"},
    {"isph", 2, nullptr, nullptr, 0, 2.63e-6, "median of 76 published 2D cavity runs"},
    {"wcsph_tvf", 2, nullptr, nullptr, 0, 0.27e-6,
     "per acoustic sub-step, median of 38 published 2D runs"},
    // The nozzle's measured rate is a third of the 3D cavity's (63 % of its particles are wall
    // and buffer particles; what makes the difference is not separated).
    {"wcsph_tvf", 3, "fda_nozzle", nullptr, 0, 2.41e-6,
     "per acoustic sub-step, the published dx = 1 mm run"},
    {"wcsph_tvf", 3, nullptr, nullptr, 0, 7.1e-6,
     "per acoustic sub-step, 2 published 3D cavity runs"},
    {"contact", 2, nullptr, nullptr, 0, 0.72e-6, "median of 14 published 2D runs"},
    {"contact", 3, nullptr, nullptr, 0, 2.6e-6, "median of 60 published 3D runs"},
};

// The value of a job parameter as JSON text, and the same of a sample's identity parameters
// (a parameter at its neutral default is absent there: compared as the scheme's default).
std::string param_text(const ParamValue& v) {
  return std::visit([](const auto& x) { return nlohmann::json(x).dump(); }, v);
}

// The samples that share the most scheme parameters with the job (all of them when the scheme
// has none or no sample records its parameters).
std::vector<const CostSample*> closest_samples(const JobSpec& job,
                                               const std::vector<const CostSample*>& sm) {
  std::vector<const CostSample*> out;
  const SchemeInfo* scheme = job.scheme.empty() ? nullptr : find_scheme(job.scheme);
  int best = -1;
  for (const CostSample* s : sm) {
    int same = 0;
    const nlohmann::json p = nlohmann::json::parse(s->params_json, nullptr, false);
    if (scheme && p.is_object())
      for (const ParamSpec& spec : scheme->params) {
        const auto jv = job.params.find(spec.name);
        if (jv == job.params.end())
          continue;
        const auto it = p.find(spec.name);
        const std::string sv = it == p.end() ? param_text(spec.default_value) : it->dump();
        same += nlohmann::json::parse(sv) == nlohmann::json::parse(param_text(jv->second));
      }
    if (same > best)
      best = same, out.clear();
    if (same == best)
      out.push_back(s);
  }
  return out;
}

} // namespace

std::optional<JobSize> cost_size(const JobSpec& job) {
  const CaseInfo* info = find_case(job.case_name);
  if (!info || !info->size)
    return std::nullopt;
  try {
    return info->size(job.params);
  } catch (const std::exception&) {
    return std::nullopt; // parameters the case refuses: the job will say why when it runs
  }
}

double StudyEstimate::wall_s(std::size_t workers) const {
  return std::max(cpu_s / static_cast<double>(std::max<std::size_t>(workers, 1)), longest_job_s);
}

std::optional<double> estimate_job(const JobSpec& job, const CostSamples& samples,
                                   std::string* how) {
  const std::string scheme = job.scheme.empty() ? "-" : job.scheme;
  auto say = [&](const std::string& s) {
    if (how)
      *how = s;
  };
  const std::optional<JobSize> size = cost_size(job);
  if (!size) {
    say("unknown (the case cannot size its jobs before they run)");
    return std::nullopt;
  }
  const double work = size->particles * size->steps * size->work_per_step;
  char buf[240];
  std::vector<const CostSample*> same, other;
  for (const auto& [cs, v] : samples) {
    const auto slash = cs.rfind('/');
    if (slash == std::string::npos || cs.substr(slash + 1) != scheme)
      continue;
    const bool this_case = cs.substr(0, slash) == job.case_name;
    for (const CostSample& s : v)
      if (this_case)
        same.push_back(&s);
      else if (s.dim == size->dim)
        other.push_back(&s);
  }
  // The median rate of the pool's samples closest in scheme parameters that reported their size,
  // per predicted particle-step for the job's own case (where the sample has it), else per
  // particle-step taken.
  double rate = 0;
  auto use = [&](const std::vector<const CostSample*>& pool, bool this_case, const char* where) {
    std::vector<double> k;
    std::vector<const CostSample*> sized;
    for (const CostSample* s : pool)
      if (s->particles && s->steps && *s->particles > 0 && *s->steps > 0)
        sized.push_back(s);
    for (const CostSample* s : closest_samples(job, sized))
      k.push_back(s->cpu_s / (this_case && s->predicted_work && *s->predicted_work > 0
                                  ? *s->predicted_work
                                  : *s->particles * s->work_steps.value_or(*s->steps)));
    if (k.empty())
      return false;
    rate = median(k);
    std::snprintf(buf, sizeof buf,
                  "particles x steps x %.3g us per particle-step (median of the %zu finished "
                  "job(s) %s closest in scheme parameters)",
                  1e6 * rate, k.size(), where);
    say(buf);
    return true;
  };
  if (use(same, true, "of this case in the database") ||
      use(other, false, "of other cases of this scheme and dimension in the database"))
    return rate * work;
  for (const auto& d : defaults)
    if (scheme == d.scheme && size->dim == d.dim &&
        (!d.case_name || job.case_name == d.case_name) &&
        (!d.param || number(job, d.param) == d.value)) {
      std::snprintf(buf, sizeof buf,
                    "particles x steps x %.3g us per particle-step (%s; nothing finished in the "
                    "database to calibrate from)",
                    1e6 * d.s_per_particle_step, d.source);
      say(buf);
      return d.s_per_particle_step * work;
    }
  say("unknown (no finished job of this scheme and dimension in the database, no measured rate)");
  return std::nullopt;
}

void CostTally::add(const JobSpec& job) {
  Group& g = groups_[job.case_name + "/" + (job.scheme.empty() ? "-" : job.scheme)];
  ++g.n;
  std::string how;
  auto cost = estimate_job(job, samples_, &how);
  if (g.how.empty() || cost)
    g.how = how;
  if (!cost) {
    ++e_.unknown;
    return;
  }
  ++e_.estimated;
  e_.cpu_s += *cost;
  e_.longest_job_s = std::max(e_.longest_job_s, *cost);
}

StudyEstimate CostTally::result() const {
  StudyEstimate e = e_;
  for (const auto& [cs, g] : groups_)
    e.basis.push_back(cs + ": " + std::to_string(g.n) + " job(s), " + g.how);
  return e;
}

StudyEstimate estimate_jobs(const std::vector<const JobSpec*>& jobs, const CostSamples& samples) {
  CostTally t(samples);
  for (const JobSpec* j : jobs)
    t.add(*j);
  return t.result();
}

std::string format_cost(double s, const char* unit) {
  char buf[64];
  auto put = [&](double x, const char* what) {
    std::snprintf(buf, sizeof buf, x >= 100 ? "%.0f %s %s" : "%.3g %s %s", x, unit, what);
  };
  if (s >= 3600)
    put(s / 3600, "hours");
  else if (s >= 60)
    put(s / 60, "minutes");
  else
    put(s, "seconds");
  return buf;
}

} // namespace sph::runner
