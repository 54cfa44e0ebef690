// Study expansion: product order, zip, explicit cases, derived parameters, exclusions, tiers,
// duplicate collapse, and per-job validation errors.
#include "expand.hpp"
#include "helpers.hpp"
#include "params.hpp"

#include <gtest/gtest.h>

#include <set>

using namespace sph::runner;
using namespace sph::runner::test;

namespace {
const std::string head = R"(
[study]
name = "t"
case = "patch_test"
)";

Expansion ex(const std::string& body, const std::string& tier = "") {
  return expand(parse_study(head + body, "t.toml"), tier);
}
std::string str(const JobSpec& j, const char* k) {
  return format_value_plain(j.params.at(k));
}
} // namespace

TEST(Expand, NoAxesGivesOneJobWithDefaults) {
  auto e = ex("");
  ASSERT_EQ(e.jobs.size(), 1u);
  EXPECT_EQ(str(e.jobs[0], "n_side"), "20");
  EXPECT_EQ(str(e.jobs[0], "kernel"), "cubic_spline");
  EXPECT_EQ(e.tier, "full");
}

TEST(Expand, ProductFirstAxisSlowest) {
  auto e = ex("[sweep]\nvisc = [\"visc01\", \"visc02\"]\nn_side = [8, 12, 16]\n");
  ASSERT_EQ(e.jobs.size(), 6u);
  EXPECT_EQ(str(e.jobs[0], "visc") + str(e.jobs[0], "n_side"), "visc018");
  EXPECT_EQ(str(e.jobs[1], "visc") + str(e.jobs[1], "n_side"), "visc0112");
  EXPECT_EQ(str(e.jobs[3], "visc") + str(e.jobs[3], "n_side"), "visc028");
  EXPECT_EQ(e.varying, (std::vector<std::string>{"visc", "n_side"}));
  // Deterministic.
  auto again = ex("[sweep]\nvisc = [\"visc01\", \"visc02\"]\nn_side = [8, 12, 16]\n");
  for (std::size_t i = 0; i < e.jobs.size(); ++i)
    EXPECT_EQ(e.jobs[i].key, again.jobs[i].key);
}

TEST(Expand, ZipGroupsVaryTogetherAndMultiplyWithAxes) {
  auto e = ex("[sweep]\nvisc = [\"visc01\", \"visc02\"]\n[[zip]]\nn_side = [8, 16]\n"
              "h_over_dx = [1.2, 1.5]\n");
  ASSERT_EQ(e.jobs.size(), 4u);
  EXPECT_EQ(str(e.jobs[0], "n_side") + "/" + str(e.jobs[0], "h_over_dx"), "8/1.2");
  EXPECT_EQ(str(e.jobs[1], "n_side") + "/" + str(e.jobs[1], "h_over_dx"), "16/1.5");
  EXPECT_EQ(str(e.jobs[2], "visc"), "visc02");
}

TEST(Expand, ExplicitCasesComeAfterTheProduct) {
  auto e = ex("[params]\nkernel = \"wendland_c2\"\n[sweep]\nn_side = [8, 12]\n"
              "[[cases]]\nn_side = 30\nvisc = \"visc01\"\n");
  ASSERT_EQ(e.jobs.size(), 3u);
  EXPECT_EQ(str(e.jobs[2], "n_side"), "30");
  EXPECT_EQ(str(e.jobs[2], "kernel"), "wendland_c2"); // on top of [params]
  // Only cases: the base job is not added.
  auto only = ex("[[cases]]\nn_side = 8\n[[cases]]\nn_side = 9\n");
  EXPECT_EQ(only.jobs.size(), 2u);
}

TEST(Expand, DerivedParameters) {
  auto e = ex("[sweep]\nn_side = [10, 20]\n[derived]\nh_over_dx = \"1 + n_side / 20\"\n"
              "eta_over_h = \"h_over_dx / 100\"\n");
  ASSERT_EQ(e.jobs.size(), 2u);
  EXPECT_EQ(str(e.jobs[0], "h_over_dx"), "1.5");
  EXPECT_EQ(str(e.jobs[1], "h_over_dx"), "2.0");
  EXPECT_EQ(str(e.jobs[1], "eta_over_h"), "0.02"); // derived from a derived value
  // An Int target must come out integral.
  auto r = ex("[sweep]\nh_over_dx = [1.2, 1.5]\n[derived]\nseed = \"round(h_over_dx * 10)\"\n");
  EXPECT_EQ(str(r.jobs[1], "seed"), "15");
}

TEST(Expand, DerivedErrorsNameTheLine) {
  try {
    ex("[sweep]\nn_side = [10, 20]\n[derived]\nh_over_dx = \"n_side / 2\"\n");
    FAIL();
  } catch (const StudyError& e) {
    EXPECT_CONTAINS(e.what(), "t.toml:8");
    EXPECT_CONTAINS(e.what(), "out of range");
    EXPECT_CONTAINS(e.what(), "n_side = 10");
  }
  try {
    ex("[sweep]\nh_over_dx = [1.25]\n[derived]\nseed = \"h_over_dx * 2\"\n");
    FAIL();
  } catch (const StudyError& e) {
    EXPECT_CONTAINS(e.what(), "is an integer; wrap the expression in round()");
  }
  try {
    ex("[derived]\nh_over_dx = \"eta_over_h\"\neta_over_h = \"h_over_dx\"\n");
    FAIL();
  } catch (const StudyError& e) {
    EXPECT_CONTAINS(e.what(), "circular");
  }
}

TEST(Expand, ExcludeDropsMatchingCombinations) {
  auto e = ex(R"(
[sweep]
lattice = ["uniform", "disordered"]
seed = [1, 2, 3]
)" + std::string("[tiers.x]\nsweep = { seed = [1] }\n"));
  EXPECT_EQ(e.jobs.size(), 6u);
  auto f = expand(parse_study(R"(
[study]
name = "t"
case = "patch_test"
exclude = [ { lattice = "uniform", seed = 2 }, { lattice = "uniform", seed = 3 } ]
[sweep]
lattice = ["uniform", "disordered"]
seed = [1, 2, 3]
)",
                              "t.toml"));
  EXPECT_EQ(f.jobs.size(), 4u);
  EXPECT_EQ(f.excluded, 2u);
  EXPECT_EQ(f.combinations, 6u);
}

TEST(Expand, TiersOverrideParamsSweepZipAndCases) {
  const std::string body = R"(
[params]
kernel = "cubic_spline"
n_side = 40
[sweep]
visc = ["visc01", "visc02", "visc03"]
seed = [1, 2, 3]
[tiers.quick]
params = { kernel = "wendland_c2" }
sweep = { seed = [7], n_side = [8, 12] }
[tiers.pin]
params = { seed = 5 }
[tiers.extra]
cases = [ { n_side = 9 } ]
)";
  auto full = ex(body);
  EXPECT_EQ(full.jobs.size(), 9u);
  auto quick = ex(body, "quick");
  EXPECT_EQ(quick.tier, "quick");
  ASSERT_EQ(quick.jobs.size(), 6u); // visc x seed(1) x n_side(2): axis replaced and axis added
  EXPECT_EQ(str(quick.jobs[0], "kernel"), "wendland_c2");
  EXPECT_EQ(str(quick.jobs[0], "seed"), "7");
  EXPECT_EQ(str(quick.jobs[1], "n_side"), "12"); // a new axis is appended (fastest)
  auto pin = ex(body, "pin");                    // a tier's fixed value pins a swept parameter
  ASSERT_EQ(pin.jobs.size(), 3u);
  EXPECT_EQ(str(pin.jobs[0], "seed"), "5");
  auto extra = ex(body, "extra");
  EXPECT_EQ(extra.jobs.size(), 10u);
}

TEST(Expand, DuplicatesCollapse) {
  // seed 1 twice, and a case equal to a product job.
  auto e = ex("[sweep]\nseed = [1, 2, 1]\n[[cases]]\nseed = 2\n");
  EXPECT_EQ(e.jobs.size(), 2u);
  EXPECT_EQ(e.duplicates, 2u);
  // 1 and 1.0 for a Real parameter are the same job.
  auto r = ex("[sweep]\ndisorder = [1, 1.0, 0.5]\n");
  EXPECT_EQ(r.jobs.size(), 2u);
}

TEST(Expand, LargeStudyExpandsQuickly) {
  auto t0 = std::chrono::steady_clock::now();
  auto e = ex(sweep_20000_jobs);
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(e.jobs.size(), 20000u);
  EXPECT_LT(s, 5.0);
}

// Sweeping the scheme: a scheme's parameters are absent from the other scheme's jobs, which does
// not make them vary (the folder aliases and job labels list what varies: a name of every
// scheme parameter exceeded the file-name limit). Parameters both schemes have with different
// values, and the scheme itself, do vary.
TEST(Expand, AParameterOnlySomeSchemesHaveVariesOnlyWhenItsValuesDiffer) {
  auto e = expand(parse_study("[study]\nname = \"s\"\ncase = \"lid_driven_cavity\"\n[sweep]\n"
                              "scheme = [\"isph\", \"wcsph_tvf\"]\ndx = [0.05, 0.1]\n",
                              "s.toml"));
  ASSERT_EQ(e.jobs.size(), 4u);
  std::set<std::string> v(e.varying.begin(), e.varying.end());
  EXPECT_EQ(v, (std::set<std::string>{"dx", "scheme", "kernel", "h_over_dx", "shift_velocity"}));
}
