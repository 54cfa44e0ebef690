// The contract between the solver and whoever runs it (the runner, a test, a user's program):
// the registry of cases. A case declares its parameters (core/params.hpp) and a run function:
// resolved parameters in, metrics out (core/run.hpp). A case that integrates in time is a
// FlowCase (cases/time_loop.hpp): geometry, boundary hooks, probes and metrics around the one
// shared time loop, with any registered scheme (schemes/scheme.hpp).
//
// Adding a case: one file in solver/cases/ that registers its CaseInfo beside the class:
//   namespace { const Registrar<CaseInfo> reg(make_my_case()); }
#pragma once

#include "core/fingerprint.hpp"
#include "core/params.hpp"
#include "core/registry.hpp"
#include "core/run.hpp"
#include "schemes/scheme.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace sph {

// What a job will cost, known before it runs (the runner's cost model multiplies it by a measured
// CPU time per particle and elementary step): the particles of its initial configuration, the
// steps to t_end at the scheme's stable step of that configuration, and the elementary steps per
// step (wcsph_tvf's acoustic sub-steps; 1 for the other schemes). A case that stops early (a
// steady state, a divergence) takes fewer steps: for those the estimate is an upper bound.
struct JobSize {
  double particles = 0;
  double steps = 0;
  double work_per_step = 1;
  int dim = 2;
};

struct CaseInfo {
  std::string name;
  std::string source;      // the file that registers the case (set by Registrar; its fingerprint)
  std::string description; // one line, with the paper and section
  std::vector<std::string> schemes; // schemes this case runs with (empty: none; first = default)
  std::vector<ParamSpec> params;    // the case's own parameters (geometry, physics, diagnostics)
  std::function<RunResult(const Params&, const RunContext&)> run;
  // Optional: the case's own constraints on a resolved parameter set, checked when a study is
  // validated (before anything runs): an error message ("1/dx must be an integer"), or nullopt.
  std::function<std::optional<std::string>(const Params&)> check;
  // Optional: the size of a job (JobSize) from its resolved parameters, by setting the case up
  // without running it (size_flow_case in cases/time_loop.hpp). Without it the job's cost is
  // unknown before it runs.
  std::function<JobSize(const Params&)> size;
  // What a job records besides the time loop's costs (flow_loop_metrics below) and its scheme's
  // counters (SchemeInfo::metrics): the case's metrics and the datasets of its HDF5 file. Empty:
  // not declared (the case's doc page lists them).
  std::vector<OutputDoc> metrics;
  std::vector<OutputDoc> datasets;
  // A test fixture of the runner, not a physical case: not listed by `runner cases`.
  bool test_fixture = false;
};

// The metrics every flow case's job records (the costs of run_flow_case, cases/time_loop.hpp).
inline const std::vector<OutputDoc>& flow_loop_metrics() {
  static const std::vector<OutputDoc> m{
      {"steps", "time steps taken"},
      {"work_steps", "elementary steps (wcsph_tvf: acoustic sub-steps; else = steps)"},
      {"wall_time_s", "wall-clock seconds of the job (all attempts)"},
      {"cpu_time_s", "CPU seconds of the job's process (all threads, all attempts)"},
      {"time_per_step_s", "wall seconds per step"},
      {"cpu_time_per_step_s", "CPU seconds per step"},
      {"time_per_particle_step_s", "wall seconds per particle and elementary step"},
      {"n_particles", "largest particle count of the run (all kinds)"},
      {"dimension", "2 or 3"},
      {"predicted_work", "particles x steps x elementary steps per step, as the cost model sized "
                         "the job before it ran"},
      {"t_stop", "simulated time at which a diverged job stopped (diverged jobs only)"},
  };
  return m;
}

// All registered cases (by name), and look-up by name (nullptr when no case has that name).
inline const std::vector<CaseInfo>& case_registry() {
  return Registry<CaseInfo>::entries();
}
inline const CaseInfo* find_case(const std::string& name) {
  return Registry<CaseInfo>::find(name);
}
// The solver fingerprint of a case's jobs (core/fingerprint.hpp): the solver without the other
// cases' files; an unknown case gets the whole solver's.
inline std::string case_fingerprint(const std::string& case_name) {
  const CaseInfo* c = find_case(case_name);
  return c ? source_fingerprint(c->source) : solver_fingerprint();
}

// Version of the numerics; enters every job key. Bump when a change alters results of existing
// parameter sets, so that old and new results never share a key.
inline constexpr int numerics_version = 1;

} // namespace sph
