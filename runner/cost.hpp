// What a study will cost before it runs: for each job, particles x steps x elementary steps per
// step from the case itself (CaseInfo::size: the case set up without running, its scheme's stable
// step there), times CPU seconds per particle-step calibrated from the database's finished jobs:
// - those of the same case and scheme closest in scheme parameters, per particle-step as they
//   were sized before they ran (metric predicted_work): what the size misses for this case (steps
//   that shrink after the first, a steady state reached before t_end, particles that enter) is
//   then in the rate;
// - else those of the same scheme and dimension in other cases, per particle-step they took
//   (n_particles x work_steps);
// - else a rate measured on the published runs (docs/runner.md).
// A job whose case cannot size it, or whose scheme has no rate, is "unknown": no guess.
#pragma once

#include "cases/case.hpp"
#include "expand.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace sph::runner {

// The size of a job from its parameters (the case's CaseInfo::size); nullopt for a case that
// cannot size its jobs or parameters it refuses.
std::optional<JobSize> cost_size(const JobSpec& job);

// One finished attempt of a case and scheme: its CPU time, and its particles, steps, elementary
// steps and dimension when it reported them (metrics n_particles, steps, work_steps or
// acoustic_steps, dimension).
struct CostSample {
  double cpu_s = 0;
  std::optional<double> particles, steps;
  std::string params_json; // the job's identity parameters: the rate is taken from the samples
                           // that share the most scheme parameters with the job (algorithm, ...)
  std::optional<double> work_steps; // elementary steps (absent: = steps)
  std::optional<int> dim;
  std::optional<double> predicted_work; // particles x steps x elementary steps per step as the
                                        // job was sized before it ran (its metric predicted_work)
};

struct StudyEstimate {
  double cpu_s = 0;               // the jobs estimated
  double longest_job_s = 0;       // the longest of them (bounds the wall time from below)
  std::size_t estimated = 0;      // jobs with an estimate
  std::size_t unknown = 0;        // jobs without one (no formula, nothing finished to learn from)
  std::vector<std::string> basis; // one line per case/scheme: how its jobs were estimated
  // Wall time on `workers` cores: the CPU time shared out, never less than the longest job.
  double wall_s(std::size_t workers) const;
};

// By "case/scheme" ("-" for no scheme).
using CostSamples = std::map<std::string, std::vector<CostSample>>;

// The CPU seconds one job is expected to take; nullopt without an estimate. how: the basis.
std::optional<double> estimate_job(const JobSpec& job, const CostSamples& samples,
                                   std::string* how = nullptr);

// The estimate of a study's jobs, added one at a time (a stream of a million jobs is not held).
// samples: the database's finished attempts by "case/scheme" (Store::cost_samples).
class CostTally {
public:
  explicit CostTally(const CostSamples& samples) : samples_(samples) {}
  void add(const JobSpec& job);
  StudyEstimate result() const;

private:
  struct Group {
    std::size_t n = 0;
    std::string how;
  };
  const CostSamples& samples_;
  StudyEstimate e_;
  std::map<std::string, Group> groups_;
};

// The estimate of a list of jobs (a CostTally of each).
StudyEstimate estimate_jobs(const std::vector<const JobSpec*>& jobs, const CostSamples& samples);

// "7450 CPU hours" / "12 CPU minutes" / "40 CPU seconds".
std::string format_cost(double seconds, const char* unit = "CPU");

} // namespace sph::runner
