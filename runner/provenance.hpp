// Where and with what a job ran: code version (git describe at build time), compiler, host.
#pragma once

#include <string>

namespace sph::runner {

std::string code_version(); // SPH_GIT_VERSION, e.g. "3f2a1b9c0d12-dirty"
std::string compiler_id();  // e.g. "GCC 12.2.0"
std::string host_name();
// Hash of every file under solver/ at build time (cmake/solver_fingerprint.cmake): which solver
// code an attempt ran. SPH_RUNNER_SOLVER_FINGERPRINT overrides it (tests of stale results).
std::string solver_fingerprint();

} // namespace sph::runner
