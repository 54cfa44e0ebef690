// The SQL schema of the job store, one migration per schema version (PRAGMA user_version).
#pragma once

#include <vector>

namespace sph::runner {

// migrations()[k] brings a database from user_version k to k+1.
const std::vector<const char*>& migrations();

} // namespace sph::runner
