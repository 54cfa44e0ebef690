// Parameters from the command line: `runner STUDY --set KEY=VALUE` (an override of the study's
// value for every job: a new job identity where the value differs), `--where KEY=VALUE` (run only
// the jobs of the study with that value) and `runner one CASE KEY=VALUE ...` (one job without a
// study file). Each KEY=VALUE is typed and checked against the parameter's spec before anything
// runs; a bad one is a StudyError naming the key and what it expects.
#pragma once

#include "expand.hpp"
#include "study.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace sph::runner {

// "KEY=VALUE" typed by the spec of KEY among `specs` (an integer, a real, true/false or a string
// in its choices) and checked against its range. `option` names the source in messages
// ("--set", "--where", "runner one").
Assignment parse_assignment(const std::vector<ParamSpec>& specs, const std::string& kv,
                            const std::string& option);

// Applies overrides to a study: KEY becomes a fixed parameter with VALUE for every job; an axis,
// zip member, tier setting, explicit case value or derived definition of KEY is dropped.
void apply_overrides(Study& study, const std::vector<Assignment>& sets);

// "n_side=40,visc=visc03": the label of a set of overrides (in the tier name they register under).
std::string overrides_label(const std::vector<Assignment>& sets);

// A job's parameters match every --where assignment.
bool matches_where(const Params& params, const std::vector<Assignment>& where);

// The error of --where filters that match no job of a study (tier, named in the message unless
// "full"), from a new pass over its jobs: the filter that matches nothing and the values the study
// has, or that the filters match nothing together.
[[noreturn]] void fail_where(JobStream jobs, const std::vector<Assignment>& where,
                             const std::string& tier);

// The study of `runner one`: name "adhoc", the case, its scheme ("" for the default) and the
// parameters; registering it adds its job to the study without retiring earlier ones.
Study adhoc_study(const std::string& case_name, const std::string& scheme,
                  const std::vector<std::string>& assignments);

inline constexpr const char* adhoc_study_name = "adhoc";

struct RunOptions;
// `runner one`: runs the adhoc study's one job in the foreground (run_study with opts, which keeps
// its log), then prints its state, metrics, and the paths of its log and outputs. The exit code
// is run_study's.
int cmd_one(const Study& adhoc, const RunOptions& opts, std::ostream& out, std::ostream& err);

} // namespace sph::runner
