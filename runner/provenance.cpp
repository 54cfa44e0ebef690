// Provenance strings recorded with every attempt.
#include "provenance.hpp"

#include "cases/case.hpp" // case_fingerprint

#include "git_version.hpp" // generated at build time by cmake/git_version.cmake

#include <unistd.h>

namespace sph::runner {

std::string code_version() {
  return SPH_GIT_VERSION;
}

std::string compiler_id() {
#if defined(__clang__)
  return std::string("Clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("GCC ") + __VERSION__;
#else
  return "unknown compiler";
#endif
}

std::string solver_fingerprint(const std::string& case_name) {
  return sph::case_fingerprint(case_name);
}

std::string host_name() {
  char buf[256] = {};
  if (gethostname(buf, sizeof buf - 1) != 0)
    return "unknown-host";
  return buf;
}

} // namespace sph::runner
