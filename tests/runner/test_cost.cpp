// The cost of a study before it runs: particles x steps x elementary steps per step from the case
// (CaseInfo::size) times seconds per particle-step, calibrated from the database's finished jobs
// (this case first, then other cases of the scheme and dimension, then a measured default);
// --dry-run prints it, and a run estimated at more than an hour of wall time needs --yes.
#include "cost.hpp"
#include "e2e_helpers.hpp"
#include "expand.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

// The number before " CPU hours" in an estimate line, or -1.
double cpu_hours(const std::string& out) {
  auto e = out.find("estimate: ");
  auto h = out.find(" CPU hours", e);
  if (e == std::string::npos || h == std::string::npos)
    return -1;
  return std::atof(out.substr(e + 10, h - e - 10).c_str());
}

// cylinder_channel with ALSPH, t_end = 10, D/dx = 10 and 20; `params`: more [params] lines.
Expansion channel_jobs(const std::string& params = "") {
  return expand(parse_study("[study]\nname = \"c\"\ncase = \"cylinder_channel\"\nscheme = "
                            "\"alsph\"\n[params]\nt_end = 10.0\n" +
                                params + "[sweep]\nD_over_dx = [10, 20]\n",
                            "c.toml"));
}

} // namespace

TEST(Cost, TheFlagshipStudysDryRunPrintsItsEstimateAndARunNeedsYes) {
  TempDir dir;
  const std::string study = std::string(SPH_SOURCE_DIR) + "/studies/alsph_dt.toml";
  auto dry = run_runner(dir, "'" + study + "' --dry-run");
  ASSERT_EQ(dry.code, 0) << dry.out;
  // 36 jobs, about 4,000 CPU hours at the recorded D/dx = 10 rates (5.06 us per particle-step for
  // Algorithm 1, 2.10 for Algorithm 2): D/dx = 30 is 163k particles, the smallest dt_star 4.7
  // million steps.
  EXPECT_CONTAINS(dry.out, "for 36 of the 36 job(s) to run");
  const double h = cpu_hours(dry.out);
  EXPECT_GT(h, 3000) << dry.out;
  EXPECT_LT(h, 5000) << dry.out;
  EXPECT_CONTAINS(dry.out, "cylinder_channel/alsph: 36 job(s), particles x steps x ");
  EXPECT_CONTAINS(dry.out, " us per particle-step (Algorithm ");
  // Running it is refused before anything is written, pointing to --yes, a tier and submit.
  auto run = run_runner(dir, "'" + study + "'");
  EXPECT_EQ(run.code, 2) << run.out;
  EXPECT_CONTAINS(run.out, "more than an hour: nothing was run");
  EXPECT_CONTAINS(run.out, "--yes");
  EXPECT_CONTAINS(run.out, "--tier quick");
  EXPECT_CONTAINS(run.out, "runner submit");
  EXPECT_FALSE(fs::exists(dir / "results"));
  // Its quick tier is seconds: no estimate above an hour, nothing refused (dry run here).
  auto quick = run_runner(dir, "'" + study + "' --tier quick --dry-run");
  ASSERT_EQ(quick.code, 0) << quick.out;
  EXPECT_CONTAINS(quick.out, "CPU seconds for 4 of the 4 job(s) to run");
}

TEST(Cost, EstimatesUseTheDatabasesFinishedJobsWhenThereAreAny) {
  Expansion ex = channel_jobs();
  ASSERT_EQ(ex.jobs.size(), 2u);
  std::vector<const JobSpec*> jobs{&ex.jobs[0], &ex.jobs[1]};
  auto size0 = cost_size(ex.jobs[0]), size1 = cost_size(ex.jobs[1]);
  ASSERT_TRUE(size0 && size1);
  // D/dx = 10 in the 14 x 13 channel: about (182 - pi/4) x 100 fluid particles and the walls;
  // t_end / dt steps with dt = dt_star dx / U (the default dt_star 5.08e-3).
  EXPECT_NEAR(size0->particles / ((14.0 * 13.0 - 3.14159265358979 / 4) * 100), 1.05, 0.05);
  EXPECT_EQ(size0->steps, std::ceil(10.0 * 10 / 5.08e-3));
  EXPECT_EQ(size1->steps, std::ceil(10.0 * 20 / 5.08e-3));
  EXPECT_NEAR(size1->particles / size0->particles, 4, 0.2);
  EXPECT_EQ(size0->work_per_step, 1.0);

  // Nothing finished: the measured default of the job's algorithm (the study leaves it at the
  // scheme's default, Algorithm 1: 5.06 us per particle-step).
  auto d = estimate_jobs(jobs, {});
  EXPECT_EQ(d.estimated, 2u);
  EXPECT_NEAR(d.cpu_s,
              5.06e-6 * (size0->particles * size0->steps + size1->particles * size1->steps),
              1e-6 * d.cpu_s);
  // Finished jobs at 2 us per particle-step (the median of three): that rate.
  std::map<std::string, std::vector<CostSample>> s = {
      {"cylinder_channel/alsph", {{2.0, 1e3, 1e3}, {30.0, 1e3, 1e4}, {1.0, 1e3, 1e3}}}};
  auto c = estimate_jobs(jobs, s);
  EXPECT_NEAR(c.cpu_s, 2e-6 * (size0->particles * size0->steps + size1->particles * size1->steps),
              1e-9 * c.cpu_s);
  EXPECT_NEAR(c.longest_job_s, 2e-6 * size1->particles * size1->steps, 1e-9 * c.cpu_s);
  EXPECT_CONTAINS(c.basis.at(0), "median of the 3 finished job(s)");
  // Samples of both algorithms (Algorithm 1 at 5 us, Algorithm 2 at 2 us): each job takes the
  // rate of the samples of its own algorithm, not the median of all.
  std::map<std::string, std::vector<CostSample>> mixed = {
      {"cylinder_channel/alsph",
       {{5.0, 1e3, 1e3, R"({"algorithm":1})"},
        {5.0, 1e3, 1e3, R"({"algorithm":1})"},
        {5.0, 1e3, 1e3, R"({"algorithm":1})"},
        {2.0, 1e3, 1e3, R"({"algorithm":2})"}}}};
  EXPECT_NEAR(estimate_jobs(jobs, mixed).cpu_s,
              5e-6 * (size0->particles * size0->steps + size1->particles * size1->steps),
              1e-9 * c.cpu_s);
  Expansion ex1 = channel_jobs("algorithm = 2\n");
  std::vector<const JobSpec*> jobs1{&ex1.jobs[0], &ex1.jobs[1]};
  EXPECT_NEAR(estimate_jobs(jobs1, mixed).cpu_s,
              2e-6 * (size0->particles * size0->steps + size1->particles * size1->steps),
              1e-9 * c.cpu_s);
  EXPECT_NEAR(estimate_jobs(jobs1, {}).cpu_s,
              2.10e-6 * (size0->particles * size0->steps + size1->particles * size1->steps),
              1e-6 * c.cpu_s);
  EXPECT_NEAR(c.wall_s(2), c.longest_job_s, 1e-9 * c.cpu_s); // one job dominates
  EXPECT_NEAR(c.wall_s(1), c.cpu_s, 1e-9 * c.cpu_s);

  // A case that cannot size its jobs: no estimate, whatever the database holds (the CPU time of
  // other jobs of the case is no measure of these).
  Expansion p = expand(parse_study(
      "[study]\nname = \"p\"\ncase = \"patch_test\"\n[sweep]\nseed = [1, 2, 3]\n", "p.toml"));
  std::vector<const JobSpec*> pj{&p.jobs[0], &p.jobs[1], &p.jobs[2]};
  EXPECT_FALSE(cost_size(p.jobs[0]));
  for (const CostSamples& sm :
       {CostSamples{}, CostSamples{{"patch_test/-", {{0.5, 400.0, {}}, {0.1, {}, {}}}}}}) {
    auto none = estimate_jobs(pj, sm);
    EXPECT_EQ(none.estimated, 0u);
    EXPECT_EQ(none.unknown, 3u);
    EXPECT_CONTAINS(none.basis.at(0), "unknown (the case cannot size its jobs");
  }
}

// A case the database has never seen takes the rate of the scheme's jobs of the same dimension in
// other cases; its elementary steps (wcsph_tvf: acoustic sub-steps) carry the rate across.
TEST(Cost, ANewCaseIsEstimatedFromTheSchemesOtherCasesOfItsDimension) {
  Expansion ex = expand(parse_study(R"([study]
name = "t"
case = "taylor_green"
scheme = "wcsph_tvf"
[params]
t_end = 1.0
[sweep]
n_side = [40]
)",
                                    "t.toml"));
  const JobSpec& job = ex.jobs.at(0);
  auto size = cost_size(job);
  ASSERT_TRUE(size);
  EXPECT_EQ(size->particles, 1600);
  EXPECT_EQ(size->dim, 2);
  EXPECT_GT(size->work_per_step, 2.0); // c0 = 10 U: several acoustic sub-steps per step
  const double work = size->particles * size->steps * size->work_per_step;
  // 2D cavity jobs at 0.5 us per particle and acoustic step (1000 particles, 100 steps of 4
  // sub-steps, 0.2 s); a 3D one at 50 us and a 2D one that did not record its dimension, unused.
  CostSamples sm = {{"lid_driven_cavity/wcsph_tvf",
                     {{0.2, 1e3, 100.0, "{}", 400.0, 2},
                      {0.2, 1e3, 100.0, "{}", 400.0, 2},
                      {20.0, 1e3, 100.0, "{}", 400.0, 3},
                      {9.0, 1e3, 100.0, "{}", 400.0, {}}}}};
  std::string how;
  auto c = estimate_job(job, sm, &how);
  ASSERT_TRUE(c);
  EXPECT_NEAR(*c, 0.5e-6 * work, 1e-9 * *c);
  EXPECT_CONTAINS(how, "of other cases of this scheme and dimension");
  // Jobs of its own case win over the other cases', per particle-step as they were sized before
  // they ran: this one took 5e5 particle-steps (1000 x 500) where it was sized at 2.5e5, so the
  // case's rate is 1 s / 2.5e5 (the size's shortfall for this case is learned), not 1 s / 5e5.
  sm["taylor_green/wcsph_tvf"] = {{1.0, 1e3, 100.0, "{}", 500.0, 2, 2.5e5}};
  EXPECT_NEAR(*estimate_job(job, sm, &how), 4e-6 * work, 1e-9 * work);
  EXPECT_CONTAINS(how, "of this case in the database");
  // A sample recorded before jobs reported their predicted size: per particle-step taken.
  sm["taylor_green/wcsph_tvf"] = {{1.0, 1e3, 100.0, "{}", 500.0, 2}};
  EXPECT_NEAR(*estimate_job(job, sm), 2e-6 * work, 1e-9 * work);
  // Nothing in the database: the scheme's published 2D rate per acoustic sub-step.
  EXPECT_NEAR(*estimate_job(job, {}, &how), 0.27e-6 * work, 1e-9 * work);
  EXPECT_CONTAINS(how, "per acoustic sub-step");
}

TEST(Cost, ACaseWithItsOwnPublishedRateIsPricedByItBeforeItsSchemesRate) {
  auto job_of = [](const std::string& case_name) {
    return expand(parse_study("[study]\nname = \"t\"\ncase = \"" + case_name +
                                  "\"\nscheme = \"wcsph_tvf\"\n[params]\nt_end = 0.01\n",
                              "t.toml"))
        .jobs.at(0);
  };
  // Nothing in the database: the nozzle by its own published rate, the 3D cavity by the scheme's
  // 3D rate (the nozzle's is a third of it).
  const JobSpec nozzle = job_of("fda_nozzle"), cavity = job_of("lid_driven_cavity_3d");
  auto ns = cost_size(nozzle), cs = cost_size(cavity);
  ASSERT_TRUE(ns && cs);
  ASSERT_EQ(ns->dim, 3);
  std::string how;
  const double n_work = ns->particles * ns->steps * ns->work_per_step;
  EXPECT_NEAR(*estimate_job(nozzle, {}, &how), 2.41e-6 * n_work, 1e-9 * 2.41e-6 * n_work);
  EXPECT_CONTAINS(how, "published dx = 1 mm run");
  const double c_work = cs->particles * cs->steps * cs->work_per_step;
  EXPECT_NEAR(*estimate_job(cavity, {}, &how), 7.1e-6 * c_work, 1e-9 * 7.1e-6 * c_work);
  EXPECT_CONTAINS(how, "3D cavity runs");
}

TEST(Cost, FormatsCostsInReadableUnits) {
  EXPECT_EQ(format_cost(7465.0 * 3600), "7465 CPU hours");
  EXPECT_EQ(format_cost(2.95 * 3600), "2.95 CPU hours");
  EXPECT_EQ(format_cost(90), "1.5 CPU minutes");
  EXPECT_EQ(format_cost(12.5, "wall"), "12.5 wall seconds");
}

TEST(Cost, ARunRecordsEachJobsPredictionBesideItsCostAndLaterEstimatesLearnFromIt) {
  TempDir dir;
  const fs::path db = dir / "results" / "results.sqlite";
  const std::string src = std::string(SPH_SOURCE_DIR) + "/studies/";
  auto r = run_runner(dir, "'" + src + "alsph_dt.toml' --tier quick -j 2 --progress plain");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "estimate: ");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE predicted_cpu_s > 0 AND cpu_s > 0"),
            4);
  // The next study of the same case and scheme is estimated from the done jobs' rate: of the two
  // (Algorithms 1 and 2), the one that shares its scheme parameters (alsph_iter's quick tier runs
  // Algorithm 2).
  auto dry = run_runner(dir, "'" + src + "alsph_iter.toml' --tier quick --dry-run");
  ASSERT_EQ(dry.code, 0) << dry.out;
  EXPECT_CONTAINS(dry.out, "per particle-step (median of the 1 finished job(s) of this case in the "
                           "database closest in scheme parameters)");
}

// The progress line names running jobs by their varying parameters, not key prefixes.
TEST(Cost, TheProgressLineNamesRunningJobsByTheirVaryingParameters) {
  TempDir dir;
  // 300 steps x 4 ms = 1.2 s each (step_sleep_us is not part of the job key).
  write_text(dir / "s.toml", "[study]\nname = \"prog\"\ncase = \"checkpoint_demo\"\n[params]\n"
                             "steps = 300\nstep_sleep_us = 4000\n[sweep]\nalpha = [0.25, 0.5]\n");
  auto r = run_runner(dir, "s.toml -j 2 --progress plain --log-every-s 0.3");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "| alpha=0.25 ");
  EXPECT_CONTAINS(r.out, "alpha=0.5 ");
}

// Before any job of the study has finished, the ETA comes from the cost model (not "?").
TEST(Cost, TheFirstRunsEtaComesFromTheCostModel) {
  TempDir dir;
  const std::string study = std::string(SPH_SOURCE_DIR) + "/studies/alsph_dt.toml";
  auto r = run_runner(dir, "'" + study + "' --tier quick -j 2 --progress live");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "\r\033[K[0/4] running ");
  EXPECT_EQ(r.out.find("ETA ?"), std::string::npos) << r.out;
}

// Each job's folder has a readable alias, by-params/<varying params>_<key prefix> -> ../<key>; a
// job that writes nothing leaves neither folder nor alias.
TEST(JobFolders, AReadableAliasPointsToEachJobsFolder) {
  TempDir dir;
  write_text(dir / "s.toml", "[study]\nname = \"tg\"\ncase = \"taylor_green\"\n[params]\n"
                             "t_end = 0.05\n[sweep]\nn_side = [8, 10]\n");
  auto r = run_runner(dir, "s.toml -j 2 --progress plain");
  ASSERT_EQ(r.code, 0) << r.out;
  const fs::path by = dir / "results" / "tg" / "by-params";
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(by)) {
    const std::string name = e.path().filename().string();
    EXPECT_TRUE(name.rfind("n_side=8_", 0) == 0 || name.rfind("n_side=10_", 0) == 0) << name;
    EXPECT_TRUE(fs::is_symlink(e.path()));
    EXPECT_TRUE(fs::exists(e.path() / "taylor_green.h5")) << name;
    EXPECT_EQ(fs::read_symlink(e.path()).parent_path(), fs::path(".."));
    ++n;
  }
  EXPECT_EQ(n, 2u);
  write_text(dir / "p.toml", "[study]\nname = \"p\"\ncase = \"patch_test\"\n[sweep]\n"
                             "n_side = [8, 9]\n");
  ASSERT_EQ(run_runner(dir, "p.toml").code, 0);
  EXPECT_FALSE(fs::exists(dir / "results" / "p" / "by-params") &&
               !fs::is_empty(dir / "results" / "p" / "by-params"));
}
