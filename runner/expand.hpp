// Expansion of a study (and tier) into its ordered list of jobs: the cartesian product of [sweep]
// axes and [[zip]] groups (first axis slowest), minus exclusions, then the explicit [[cases]];
// each job fully resolved (defaults, derived values), validated, keyed, duplicates collapsed.
#pragma once

#include "study.hpp"

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

struct Expansion {
  std::string tier;                 // "full" or the tier's name
  std::vector<JobSpec> jobs;        // deterministic order
  std::size_t combinations = 0;     // size of the product before exclusions
  std::size_t excluded = 0;         // dropped by exclude
  std::size_t duplicates = 0;       // collapsed because their key was already in the list
  std::vector<std::string> varying; // parameters whose value differs between jobs
};

// Studies (tiers) larger than this are refused before they are expanded (--max-jobs raises it).
inline constexpr std::size_t default_max_jobs = 1000000;

// tier: "" or "full" for the study itself, else the name of a [tiers.NAME].
// Throws StudyError naming the line of the item at fault. The number of jobs is counted first
// (product of the axes and zip groups, plus the explicit cases): more than max_jobs is an error
// naming the line of the largest axis and the count, and nothing is expanded.
Expansion expand(const Study& study, const std::string& tier = "",
                 std::size_t max_jobs = default_max_jobs);

// Builds a JobSpec (key, canonical JSON) from resolved params.
JobSpec make_job(const Study& study, Params params);
// Same, with the job's specs (job_specs of its scheme) already at hand.
JobSpec make_job(const Study& study, Params params, const std::vector<ParamSpec>& specs);

} // namespace sph::runner
