// What a study will cost before it runs (issue 16 part 4, first step): for each job, particles x
// steps from its parameters (cost_size: a formula per case, today cylinder_channel) times the
// seconds per particle-step of its case and scheme, calibrated from the database's own finished
// jobs (their n_particles and steps metrics and CPU time) where there are any, else a measured
// default (docs/alsph.md). Cases without a formula are estimated from the mean CPU time of their
// finished jobs of the same case and scheme, or not at all (said so).
#pragma once

#include "expand.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace sph::runner {

struct JobSize {
  double particles = 0;
  double steps = 0;
};

// Particles x steps of a job from its parameters; nullopt for cases without a formula.
std::optional<JobSize> cost_size(const JobSpec& job);

// One finished attempt of a case and scheme: its CPU time, and its particles and steps when it
// reported them (metrics n_particles, steps).
struct CostSample {
  double cpu_s = 0;
  std::optional<double> particles, steps;
  std::string params_json; // the job's identity parameters: the rate is taken from the samples
                           // that share the most scheme parameters with the job (algorithm, ...)
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
