// Cost estimates of jobs before they run (cost.hpp).
#include "cost.hpp"

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

// Measured seconds per particle-step when the database has nothing to calibrate from; `param`
// (if set) must have `value` in the job.
struct Default {
  const char* case_scheme;
  const char* param;
  double value;
  double s_per_particle_step;
  const char* source;
};
const Default defaults[] = {
    // docs/alsph.md, "What a step costs": CPU seconds per particle-step of the recorded D/dx = 10
    // runs (60 D/U, 15 226 particles, dt U/dx = 5.08e-2, double coefficients), one core.
    {"cylinder_channel/alsph", "algorithm", 1, 5.06e-6,
     "Algorithm 1 at D/dx = 10: 5.06 us per particle-step (docs/alsph.md)"},
    {"cylinder_channel/alsph", "algorithm", 2, 2.10e-6,
     "Algorithm 2 at D/dx = 10: 2.10 us per particle-step (docs/alsph.md)"},
};

// The value of a job parameter as JSON text, and the same of a sample's identity parameters
// (a parameter at its neutral default is absent there: compared as the scheme's default).
std::string param_text(const ParamValue& v) {
  return std::visit([](const auto& x) { return nlohmann::json(x).dump(); }, v);
}

// The samples that share the most scheme parameters with the job (all of them when the scheme
// has none or no sample records its parameters).
std::vector<const CostSample*> closest_samples(const JobSpec& job,
                                               const std::vector<CostSample>& sm) {
  std::vector<const CostSample*> out;
  const SchemeInfo* scheme = job.scheme.empty() ? nullptr : find_scheme(job.scheme);
  int best = -1;
  for (const CostSample& s : sm) {
    int same = 0;
    const nlohmann::json p = nlohmann::json::parse(s.params_json, nullptr, false);
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
      out.push_back(&s);
  }
  return out;
}

} // namespace

std::optional<JobSize> cost_size(const JobSpec& job) {
  if (job.case_name == "cylinder_channel") {
    // Channel L x H (in D) less the cylinder, on a lattice of spacing dx = D / D_over_dx; steps
    // t_end / dt with dt = dt_star dx / U (U = D = 1). A job that diverges costs less.
    auto r = number(job, "D_over_dx"), dts = number(job, "dt_star"), t = number(job, "t_end");
    auto l = number(job, "channel_length"), h = number(job, "channel_height");
    if (!r || !dts || !t || !l || !h || *dts <= 0)
      return std::nullopt;
    const double pi = 3.14159265358979323846;
    return JobSize{(*l * *h - pi / 4) * *r * *r, *t * *r / *dts};
  }
  return std::nullopt;
}

double StudyEstimate::wall_s(std::size_t workers) const {
  return std::max(cpu_s / static_cast<double>(std::max<std::size_t>(workers, 1)), longest_job_s);
}

std::optional<double> estimate_job(const JobSpec& job, const CostSamples& samples,
                                   std::string* how) {
  const std::string cs = job.case_name + "/" + (job.scheme.empty() ? "-" : job.scheme);
  auto it = samples.find(cs);
  const std::vector<CostSample> none;
  const auto& sm = it == samples.end() ? none : it->second;
  char buf[200];
  auto say = [&](const std::string& s) {
    if (how)
      *how = s;
  };
  if (auto size = cost_size(job)) {
    std::vector<CostSample> sized;
    for (const auto& s : sm)
      if (s.particles && s.steps && *s.particles > 0 && *s.steps > 0)
        sized.push_back(s);
    std::vector<double> k;
    for (const CostSample* s : closest_samples(job, sized))
      k.push_back(s->cpu_s / (*s->particles * *s->steps));
    if (!k.empty()) {
      const double kk = median(k);
      std::snprintf(buf, sizeof buf,
                    "particles x steps x %.3g us per particle-step (median of the %zu finished "
                    "job(s) in the database closest in scheme parameters)",
                    1e6 * kk, k.size());
      say(buf);
      return kk * size->particles * size->steps;
    }
    for (const auto& d : defaults)
      if (cs == d.case_scheme && (!d.param || number(job, d.param) == d.value)) {
        std::snprintf(buf, sizeof buf,
                      "particles x steps x %.3g us per particle-step (%s; nothing finished "
                      "in the database to calibrate from)",
                      1e6 * d.s_per_particle_step, d.source);
        say(buf);
        return d.s_per_particle_step * size->particles * size->steps;
      }
  }
  if (!sm.empty()) {
    std::vector<double> c;
    for (const auto& s : sm)
      c.push_back(s.cpu_s);
    say("the median CPU time of its " + std::to_string(c.size()) +
        " finished job(s) in the database (no cost formula for this case)");
    return median(c);
  }
  say("no estimate (no cost formula and no finished job of this case and scheme)");
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
