// Job identity: canonical JSON and SHA-256 keys.
#include "expand.hpp"
#include "helpers.hpp"
#include "job_key.hpp"

#include <gtest/gtest.h>

using namespace sph::runner;
using namespace sph::runner::test;

namespace {
const char* head = R"(
[study]
name = "k"
case = "patch_test"
)";

std::string only_key(const std::string& body) {
  auto ex = expand(parse_study(std::string(head) + body, "k.toml"));
  EXPECT_EQ(ex.jobs.size(), 1u);
  return ex.jobs.at(0).key;
}
} // namespace

TEST(JobKey, Sha256KnownVector) {
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(JobKey, IntegerAndRealSpellingsOfARealParamAreEqual) {
  EXPECT_EQ(only_key("[params]\ndisorder = 1\n"), only_key("[params]\ndisorder = 1.0\n"));
}

TEST(JobKey, IndependentOfKeyOrderAndOfExplicitDefaults) {
  std::string a = only_key("[params]\nn_side = 12\nkernel = \"wendland_c2\"\n");
  std::string b = only_key("[params]\nkernel = \"wendland_c2\"\nn_side = 12\n");
  EXPECT_EQ(a, b);
  // Defaults are filled in: spelling a default out gives the same job.
  EXPECT_EQ(only_key(""), only_key("[params]\nn_side = 20\n"));
}

TEST(JobKey, DifferentValuesDiffer) {
  EXPECT_NE(only_key("[params]\nn_side = 12\n"), only_key("[params]\nn_side = 13\n"));
  EXPECT_NE(only_key("[params]\nh_over_dx = 1.2\n"),
            only_key("[params]\nh_over_dx = 1.2000000000000002\n"));
}

TEST(JobKey, CanonicalJsonShape) {
  auto ex = expand(parse_study(std::string(head) + "[params]\ndisorder = 1\n", "k.toml"));
  const auto& j = ex.jobs.at(0);
  EXPECT_EQ(j.canonical.rfind("{\"case\":\"patch_test\",\"numerics_version\":", 0), 0u);
  EXPECT_CONTAINS(j.canonical, "\"disorder\":1.0");
  EXPECT_CONTAINS(j.params_json, "\"n_side\":20");
  EXPECT_EQ(j.key, sha256_hex(j.canonical));
  // Same parameters from another study file: same key.
  auto other = expand(parse_study(R"(
[study]
name = "another_name"
case = "patch_test"
description = "different file, same job"
[params]
disorder = 1.0
)",
                                  "other.toml"));
  EXPECT_EQ(other.jobs.at(0).key, j.key);
}
