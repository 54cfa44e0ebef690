// The solver fingerprints of this build (see fingerprint.hpp).
#include "core/fingerprint.hpp"

#include "solver_fingerprint.hpp" // generated at build time by cmake/solver_fingerprint.cmake

#include <cstdlib>
#include <cstring>
#include <string_view>

namespace sph {

namespace {
struct CaseFingerprint {
  const char* file; // name of a file in solver/cases/
  const char* fingerprint;
};
constexpr CaseFingerprint case_fingerprints[] = {SPH_CASE_FINGERPRINTS};

const char* override_fingerprint() {
  const char* e = std::getenv("SPH_RUNNER_SOLVER_FINGERPRINT");
  return e && *e ? e : nullptr;
}
} // namespace

std::string solver_fingerprint() {
  if (const char* e = override_fingerprint())
    return e;
  return SPH_SOLVER_FINGERPRINT;
}

std::string source_fingerprint(const std::string& file) {
  if (const char* e = override_fingerprint())
    return e;
  const std::string_view f(file);
  for (const CaseFingerprint& c : case_fingerprints) {
    const std::string tail = std::string("cases/") + c.file;
    if (f.size() >= tail.size() && f.substr(f.size() - tail.size()) == tail &&
        (f.size() == tail.size() || f[f.size() - tail.size() - 1] == '/'))
      return c.fingerprint;
  }
  return solver_fingerprint();
}

} // namespace sph
