// The solver fingerprint of this build (see fingerprint.hpp).
#include "core/fingerprint.hpp"

#include "solver_fingerprint.hpp" // generated at build time by cmake/solver_fingerprint.cmake

#include <cstdlib>

namespace sph {

std::string solver_fingerprint() {
  if (const char* e = std::getenv("SPH_RUNNER_SOLVER_FINGERPRINT"); e && *e)
    return e;
  return SPH_SOLVER_FINGERPRINT;
}

} // namespace sph
