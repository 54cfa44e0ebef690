// Job identity: canonical JSON and SHA-256 keys.
#include "expand.hpp"
#include "helpers.hpp"
#include "job_key.hpp"
#include "params.hpp"

#include <gtest/gtest.h>

using namespace sph;
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

TEST(JobKey, IdentityTextIsTheJsonTreeDumpedByteForByte) {
  // The expansion writes the identity parameters directly (identity_params_text); the keys of
  // every job stay those of the JSON tree's dump: every case and scheme at its defaults, and
  // values whose printing could differ (signs, zeros, exponents, integers in Real parameters,
  // escapes and UTF-8 in strings, a neutral default, a parameter outside the key).
  std::vector<ParamValue> reals = {0.0,
                                   -0.0,
                                   1.0,
                                   -1.5,
                                   0.1,
                                   1e-5,
                                   1.2000000000000002,
                                   1e22,
                                   5e-324,
                                   1.7976931348623157e308,
                                   std::int64_t{3}};
  std::vector<ParamValue> ints = {std::int64_t{0}, std::int64_t{-7}, std::int64_t{1} << 62};
  std::vector<ParamValue> strings = {std::string(""), std::string("a\"b\\c"),
                                     std::string("tab\there\n"), std::string("\xc3\xa9t\xc3\xa9"),
                                     std::string("\x7f")};
  int checked = 0;
  for (const auto& info : sph::case_registry())
    for (const std::string& scheme :
         info.schemes.empty() ? std::vector<std::string>{""} : info.schemes) {
      std::vector<ParamSpec> specs = job_specs(info, scheme);
      Params p;
      for (const auto& s : specs)
        p[s.name] = s.default_value;
      EXPECT_EQ(identity_params_text(specs, p), identity_params_json(specs, p).dump());
      for (const auto& s : specs) {
        const auto& values = s.type == ParamType::Real   ? reals
                             : s.type == ParamType::Int  ? ints
                             : s.type == ParamType::Bool ? std::vector<ParamValue>{true, false}
                                                         : strings;
        for (const auto& v : values) {
          Params q = p;
          q[s.name] = v;
          EXPECT_EQ(identity_params_text(specs, q), identity_params_json(specs, q).dump())
              << info.name << "/" << scheme << " " << s.name;
          ++checked;
        }
      }
    }
  EXPECT_GT(checked, 100);
  // A neutral default left out, another value kept; a parameter outside the identity left out.
  std::vector<ParamSpec> specs(3);
  specs[0].name = "ramp";
  specs[0].default_value = std::int64_t{0};
  specs[0].neutral_default = true;
  specs[1].name = "threads";
  specs[1].identity = false;
  specs[2].name = "a";
  for (const ParamValue& ramp : {ParamValue(std::int64_t{0}), ParamValue(0.0), ParamValue(2.5)}) {
    Params p{{"ramp", ramp}, {"threads", 4.0}, {"a", 1.0}};
    EXPECT_EQ(identity_params_text(specs, p), identity_params_json(specs, p).dump());
  }
}
