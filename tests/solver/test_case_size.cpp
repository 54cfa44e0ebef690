// The size of a job before it runs (CaseInfo::size, cases/case.hpp), which the runner's cost
// model multiplies by a measured CPU time per particle and elementary step: set against what the
// same job reports when it runs (n_particles, steps, work_steps). One small job per scheme.
#include "case_helpers.hpp"

#include <gtest/gtest.h>

#include <set>

using namespace sph;
using sph::testing::case_defaults;
using sph::testing::metric;

namespace {

struct SizeCase {
  const char* case_name;
  const char* scheme;
  Params overrides;
  double steps_tol;         // relative: a scheme with adaptive steps sizes from its first step
  double particles_tol = 0; // relative, below: an open boundary adds particles as the run goes
};

void expect_size_matches_the_run(const SizeCase& c) {
  SCOPED_TRACE(std::string(c.case_name) + " / " + c.scheme);
  const CaseInfo* info = find_case(c.case_name);
  ASSERT_TRUE(info && info->size);
  Params prm = case_defaults(c.case_name, c.scheme);
  for (const auto& [k, v] : c.overrides)
    prm[k] = v;
  const JobSize z = info->size(prm);
  const RunResult r = info->run(prm, RunContext{});
  ASSERT_EQ(r.status, RunStatus::Done) << r.message;
  const double n = metric(r, "n_particles"); // the largest count of the run
  EXPECT_LE(z.particles, n);
  EXPECT_GE(z.particles, (1.0 - c.particles_tol) * n);
  EXPECT_EQ(z.dim, static_cast<int>(metric(r, "dimension")));
  const double steps = metric(r, "steps"), work = metric(r, "work_steps");
  EXPECT_NEAR(z.steps, steps, c.steps_tol * steps);
  EXPECT_NEAR(z.steps * z.work_per_step, work, c.steps_tol * work);
  // The run records the same size as its metric predicted_work.
  EXPECT_EQ(metric(r, "predicted_work"), z.particles * z.steps * z.work_per_step);
}

} // namespace

TEST(CaseSize, FixedStepSchemesSizeTheirJobsExactly) {
  // ISPH and ALSPH step at the job's dt: the steps are what the run takes; the closed cavity keeps
  // its particles, the channel's outlet buffer fills as the fluid leaves (here 1052 at the start,
  // 1488 at the end of this short channel).
  expect_size_matches_the_run({"lid_driven_cavity",
                               "isph",
                               {{"dx", 0.05}, {"t_end", 0.2}, {"Re", 1000.0}, {"dt", 0.002}},
                               0.0});
  expect_size_matches_the_run({"cylinder_channel",
                               "alsph",
                               {{"D_over_dx", std::int64_t{6}},
                                {"t_end", 0.5},
                                {"ramp_time", 0.0},
                                {"channel_length", 6.0},
                                {"channel_height", 4.0},
                                {"upstream_length", 2.0},
                                {"dt_star", 2.54e-2}},
                               0.0,
                               0.3});
}

TEST(CaseSize, AdaptiveStepSchemesSizeTheirJobsFromTheFirstStep) {
  // wcsph_tvf: the advection step and its acoustic sub-steps from the initial velocity (the
  // Taylor-Green vortex decays, so later steps are a little longer); contact: its sound-speed step.
  // (Not so the wcsph_tvf cavity, whose impulsive lid start shrinks the advection step 2-3x by
  // its acceleration criterion: the runner's calibration per case takes that into its rate.)
  expect_size_matches_the_run({"taylor_green",
                               "wcsph_tvf",
                               {{"n_side", std::int64_t{20}}, {"t_end", 0.5}, {"tvf", "limited"}},
                               0.15});
  expect_size_matches_the_run({"cylinder_array",
                               "contact",
                               {{"n_d", std::int64_t{8}}, {"t_end_visc", 0.02}, {"zeta", 0.0}},
                               0.15});
}

// `runner cases CASE` lists the case's metrics: the list (with the time loop's and the scheme's)
// is what a short run with `prm` records, neither more nor less.
static void expect_declared_metrics_are_recorded(const std::string& name, Params prm) {
  const CaseInfo* info = find_case(name);
  ASSERT_TRUE(info);
  std::set<std::string> declared;
  for (const auto& d : info->metrics)
    declared.insert(d.name);
  for (const auto& d : find_scheme("wcsph_tvf")->metrics)
    declared.insert(d.name);
  for (const auto& d : flow_loop_metrics())
    if (d.name != "t_stop") // diverged jobs only
      declared.insert(d.name);
  const RunResult r = info->run(prm, RunContext{});
  ASSERT_EQ(r.status, RunStatus::Done) << r.message;
  std::set<std::string> recorded;
  for (const auto& [k, v] : r.metrics)
    recorded.insert(k);
  EXPECT_EQ(declared, recorded) << name;
}

// The nozzle's per-station, per-section and per-plane metrics of its default domain.
TEST(CaseOutputs, FdaNozzlesDeclaredMetricsAreWhatItsRunRecords) {
  Params prm = case_defaults("fda_nozzle", "wcsph_tvf");
  prm["dx"] = 0.001;
  prm["t_end"] = 5e-4; // a few steps: the flux window needs two
  expect_declared_metrics_are_recorded("fda_nozzle", prm);
}

TEST(CaseOutputs, TaylorGreensDeclaredMetricsAreWhatItsRunRecords) {
  Params prm = case_defaults("taylor_green", "wcsph_tvf");
  prm["n_side"] = std::int64_t{16};
  prm["t_end"] = 0.1;
  expect_declared_metrics_are_recorded("taylor_green", prm);
}
