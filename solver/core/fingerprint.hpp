// The solver fingerprint of this build: a hash of every file under solver/ at build time
// (cmake/solver_fingerprint.cmake), so two builds of the same solver code share it and any change
// to the solver changes it. The runner records it with each attempt (stale results) and the
// checkpoints carry it (io/checkpoint.hpp: a checkpoint of other solver code is not continued).
// The environment variable SPH_RUNNER_SOLVER_FINGERPRINT overrides it (tests of other builds).
#pragma once

#include <string>

namespace sph {

std::string solver_fingerprint();

} // namespace sph
