// Where and with what a job ran: code version (git describe at build time), compiler, host.
#pragma once

#include <string>

namespace sph::runner {

std::string code_version(); // SPH_GIT_VERSION, e.g. "3f2a1b9c0d12-dirty"
std::string compiler_id();  // e.g. "GCC 12.2.0"
std::string host_name();
// Which solver code a job of `case_name` runs (cmake/solver_fingerprint.cmake): a hash of the
// solver's files without the other cases' files, so adding or changing one case leaves the
// results of the others current. SPH_RUNNER_SOLVER_FINGERPRINT overrides it (tests of stale
// results).
std::string solver_fingerprint(const std::string& case_name);

} // namespace sph::runner
