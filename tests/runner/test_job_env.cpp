// The environment of a job process (process.hpp job_environment): OpenMP threads from
// --threads-per-job, and passive waiting unless the user chose a wait policy.
#include "process.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>

using namespace sph::runner;

TEST(JobEnvironment, PassiveWaitingUnlessTheUserSetsAPolicy) {
  const char* before = std::getenv("OMP_WAIT_POLICY");
  const std::string saved = before ? before : "";
  ::unsetenv("OMP_WAIT_POLICY");
  std::map<std::string, std::string> env;
  for (const auto& [k, v] : job_environment(2))
    env[k] = v;
  EXPECT_EQ(env["OMP_NUM_THREADS"], "2");
  EXPECT_EQ(env["OMP_WAIT_POLICY"], "passive");
  // The user's setting is inherited unchanged: the runner does not override it.
  ::setenv("OMP_WAIT_POLICY", "active", 1);
  env.clear();
  for (const auto& [k, v] : job_environment(1))
    env[k] = v;
  EXPECT_EQ(env.count("OMP_WAIT_POLICY"), 0u);
  EXPECT_EQ(env["OMP_NUM_THREADS"], "1");
  if (before)
    ::setenv("OMP_WAIT_POLICY", saved.c_str(), 1);
  else
    ::unsetenv("OMP_WAIT_POLICY");
}
