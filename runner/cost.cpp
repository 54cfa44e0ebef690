// Cost estimates of jobs before they run (cost.hpp).
#include "cost.hpp"

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

// Measured seconds per particle-step when the database has nothing to calibrate from.
struct Default {
  const char* case_scheme;
  double s_per_particle_step;
  const char* source;
};
const Default defaults[] = {
    // docs/alsph.md, "Cost": a whole step (5 inner iterations, search, shifting, forces) per
    // particle, 8.1 us (Algorithm 1) and 5.3 us (Algorithm 2) on one core: the mean of the two.
    {"cylinder_channel/alsph", 6.7e-6, "docs/alsph.md: 8.1 / 5.3 us per particle-step"},
};

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
    std::vector<double> k;
    for (const auto& s : sm)
      if (s.particles && s.steps && *s.particles > 0 && *s.steps > 0)
        k.push_back(s.cpu_s / (*s.particles * *s.steps));
    if (!k.empty()) {
      const double kk = median(k);
      std::snprintf(buf, sizeof buf,
                    "particles x steps x %.3g us per particle-step (median of %zu finished "
                    "job(s) in the database)",
                    1e6 * kk, k.size());
      say(buf);
      return kk * size->particles * size->steps;
    }
    for (const auto& d : defaults)
      if (cs == d.case_scheme) {
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
