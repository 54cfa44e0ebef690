// The contract between the solver and whoever runs it (the runner, a test, a user's program):
// the registry of cases. A case declares its parameters (core/params.hpp) and a run function:
// resolved parameters in, metrics out (core/run.hpp). A case that integrates in time is a
// FlowCase (cases/time_loop.hpp): geometry, boundary hooks, probes and metrics around the one
// shared time loop, with any registered scheme (schemes/scheme.hpp).
//
// Adding a case: one file in solver/cases/ that registers its CaseInfo beside the class:
//   namespace { const Registrar<CaseInfo> reg(make_my_case()); }
#pragma once

#include "core/params.hpp"
#include "core/registry.hpp"
#include "core/run.hpp"
#include "schemes/scheme.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace sph {

struct CaseInfo {
  std::string name;
  std::string description;          // one line, with the paper and section
  std::vector<std::string> schemes; // schemes this case runs with (empty: none; first = default)
  std::vector<ParamSpec> params;    // the case's own parameters (geometry, physics, diagnostics)
  std::function<RunResult(const Params&, const RunContext&)> run;
  // Optional: the case's own constraints on a resolved parameter set, checked when a study is
  // validated (before anything runs): an error message ("1/dx must be an integer"), or nullopt.
  std::function<std::optional<std::string>(const Params&)> check;
};

// All registered cases (by name), and look-up by name (nullptr when no case has that name).
inline const std::vector<CaseInfo>& case_registry() {
  return Registry<CaseInfo>::entries();
}
inline const CaseInfo* find_case(const std::string& name) {
  return Registry<CaseInfo>::find(name);
}

// Version of the numerics; enters every job key. Bump when a change alters results of existing
// parameter sets, so that old and new results never share a key.
inline constexpr int numerics_version = 1;

} // namespace sph
