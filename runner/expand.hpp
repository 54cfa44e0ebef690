// Expansion of a study (and tier) into its ordered jobs: the cartesian product of [sweep] axes and
// [[zip]] groups (first axis slowest), minus exclusions, then the explicit [[cases]]; each job
// fully resolved (defaults, derived values), validated, keyed, duplicates collapsed. The jobs come
// one at a time (JobStream), so a study of a million jobs is never held whole.
#pragma once

#include "study.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace sph::runner {

struct JobSpec {
  std::string key; // SHA-256 of `canonical`
  std::string case_name;
  std::string scheme;      // "" when the case has no schemes
  Params params;           // every parameter of the job, resolved and typed (with "scheme" when
                           // the case has schemes): exactly what CaseInfo::run receives
  std::string params_json; // canonical JSON of the identity parameters (what the DB shows)
  std::string canonical;   // the hashed text: case, scheme, identity params, numerics version
};

// What a whole pass over an expansion counts.
struct ExpansionSummary {
  std::string tier;                 // "full" or the tier's name
  std::size_t size = 0;             // jobs, after exclusions and duplicates
  std::size_t combinations = 0;     // size of the product before exclusions
  std::size_t excluded = 0;         // dropped by exclude
  std::size_t duplicates = 0;       // collapsed because their key was already in the list
  std::vector<std::string> varying; // parameters whose value differs between the jobs that have them
};

// The whole expansion in memory (small studies, tests; `run`, `submit` and `--dry-run` stream).
struct Expansion : ExpansionSummary {
  std::vector<JobSpec> jobs; // deterministic order
};

// Studies (tiers) larger than this are refused before they are expanded (--max-jobs raises it).
inline constexpr std::size_t default_max_jobs = 1000000;

// The jobs of a study (tier) one at a time, in expansion order, each resolved, validated and
// keyed, duplicates collapsed: what expand() collects, without holding it. The stream keeps the
// keys met so far (32 bytes a job, to collapse duplicates) and the first job's parameters (for
// `varying`). `study` must outlive the stream.
class JobStream {
public:
  // tier: "" or "full" for the study itself, else the name of a [tiers.NAME]. Throws StudyError
  // naming the line of the item at fault. The number of jobs is counted first (product of the
  // axes and zip groups, plus the explicit cases): more than max_jobs is an error naming the line
  // of the largest axis and the count, and nothing is expanded.
  explicit JobStream(const Study& study, const std::string& tier = "",
                     std::size_t max_jobs = default_max_jobs);
  JobStream(Study&&, const std::string& = "", std::size_t = 0) = delete; // would dangle
  JobStream(JobStream&&) noexcept;
  JobStream& operator=(JobStream&&) noexcept;
  ~JobStream();

  // The next job into `job`; false after the last one. The invalid jobs met on the way (up to 25
  // in the product) are thrown then, together, as one StudyError naming their lines.
  bool next(JobSpec& job);
  // The counts so far; the whole expansion's once next() returned false (`varying` only then).
  const ExpansionSummary& summary() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The jobs of a stream by increasing ordinal (their index in the expansion), moving forward only:
// the jobs of a to-do list in expansion order, without holding the others.
class JobCursor {
public:
  explicit JobCursor(JobStream jobs) : jobs_(std::move(jobs)) {}
  // The job at `ordinal`, which is not before the one asked for last (std::out_of_range past the
  // end or backwards).
  const JobSpec& at(std::size_t ordinal);

private:
  JobStream jobs_;
  JobSpec job_;
  std::size_t next_ = 0; // the ordinal of the job next() gives next
};

// Calls f with each job of the study (tier) in order (f may move from it); returns the counts.
// Throws as JobStream does, the invalid jobs after the last valid one was passed to f.
ExpansionSummary for_each_job(const Study& study, const std::string& tier, std::size_t max_jobs,
                              const std::function<void(JobSpec&)>& f);

// The whole expansion: for_each_job collected in a vector.
Expansion expand(const Study& study, const std::string& tier = "",
                 std::size_t max_jobs = default_max_jobs);

// Builds a JobSpec (key, canonical JSON) from resolved params.
JobSpec make_job(const Study& study, Params params);
// Same, with the job's specs (job_specs of its scheme) already at hand.
JobSpec make_job(const Study& study, Params params, const std::vector<ParamSpec>& specs);

} // namespace sph::runner
