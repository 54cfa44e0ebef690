// The runner's commands on small studies: studies that change (new axis values run alone, an
// identity change keeps the old jobs queryable), --dry-run with keys and states, table filters
// and formats, classified failures with every attempt kept, status.
#include "e2e_helpers.hpp"

#include <gtest/gtest.h>

#include <sstream>

using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

std::string sweep_study(const std::string& n_sides, const std::string& fixed = "") {
  return "[study]\nname = \"grow\"\ncase = \"patch_test\"\n[params]\n" + fixed +
         "\n[sweep]\nvisc = [\"visc01\", \"visc03\"]\nn_side = [" + n_sides + "]\n";
}

} // namespace

TEST(StudyChanges, NewAxisValuesRunAloneAndIdentityChangesKeepOldJobs) {
  TempDir dir;
  fs::path db = dir / "results" / "results.sqlite";
  write_text(dir / "s.toml", sweep_study("8, 9"));
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 4);

  // Adding a value to an axis runs only the new jobs.
  write_text(dir / "s.toml", sweep_study("8, 9, 10"));
  auto dry = run_runner(dir, "s.toml --dry-run");
  ASSERT_EQ(dry.code, 0) << dry.out;
  EXPECT_CONTAINS(dry.out, "grow: 6 jobs");
  std::string key8 = sql_text(db, "SELECT substr(j.key, 1, 12) FROM jobs j JOIN job_params p ON "
                                  "p.job_id=j.id WHERE p.name='n_side' AND p.value=8 LIMIT 1");
  key8.pop_back();
  EXPECT_CONTAINS(dry.out, "done     " + key8); // keys and states
  EXPECT_CONTAINS(dry.out, "new      ");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 4); // dry run wrote nothing
  auto r = run_runner(dir, "s.toml");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "grow: 6 jobs: 4 done already, 2 to run (2 new)");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 6);
  EXPECT_CONTAINS(r.out, "note: the study file changed since the last run");

  // A change of identity (a fixed parameter) makes new jobs; the old ones stay queryable.
  write_text(dir / "s.toml", sweep_study("8, 9, 10", "h_over_dx = 1.5"));
  auto c = run_runner(dir, "s.toml");
  ASSERT_EQ(c.code, 0) << c.out;
  EXPECT_CONTAINS(c.out, "grow: 6 jobs: 0 done already, 6 to run (6 new)");
  EXPECT_CONTAINS(c.out, "6 job(s) of an earlier version of this study are no longer in it");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs"), 12);
  // job_metrics (the stable view) still has the old results under the study's name...
  EXPECT_EQ(sql_int(db, "SELECT count(DISTINCT job) FROM job_metrics WHERE study='grow' AND "
                        "metric='err'"),
            12);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM job_metrics WHERE study='grow' AND metric='err' AND "
                        "json_extract(params, '$.h_over_dx') = 1.2"),
            6);
  // ... while status, table and export show the current version.
  auto st = run_runner(dir, "status grow");
  EXPECT_CONTAINS(st.out, "grow                     full           6");
  auto t = run_runner(dir, "table grow --rows n_side --cols visc --value h --format csv");
  ASSERT_EQ(t.code, 0) << t.out;
  EXPECT_CONTAINS(t.out, "8,0.1875,0.1875"); // h = 1.5 / 8
  // Going back to the old definition finds the old results: nothing runs.
  write_text(dir / "s.toml", sweep_study("8, 9, 10"));
  auto back = run_runner(dir, "s.toml");
  EXPECT_CONTAINS(back.out, "grow: 6 jobs: 6 done already, 0 to run");
}

TEST(Table, WhereFiltersAndMarkdown) {
  TempDir dir;
  write_text(dir / "s.toml", R"([study]
name = "lat"
case = "patch_test"
[sweep]
visc = ["visc01", "visc03"]
n_side = [8, 10]
lattice = ["uniform", "disordered"]
)");
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  auto all =
      run_runner(dir, "table lat --rows n_side --cols visc --value err --agg count --format csv");
  EXPECT_CONTAINS(all.out, "8,2,2\n");
  auto u = run_runner(dir, "table lat --rows n_side --cols visc --value err --agg count --format "
                           "csv --where lattice=uniform");
  ASSERT_EQ(u.code, 0) << u.out;
  EXPECT_CONTAINS(u.out, "8,1,1\n10,1,1\n");
  auto two = run_runner(dir, "table lat --rows n_side --cols visc --value err --agg count "
                             "--format csv --where lattice=uniform --where n_side=10");
  EXPECT_EQ(two.out, "n_side \\ visc,visc01,visc03\n10,1,1\n");
  auto none = run_runner(dir, "table lat --rows n_side --cols visc --value err --where n_side=12");
  EXPECT_EQ(none.code, 1);
  EXPECT_CONTAINS(none.out, "no values of metric 'err' in study 'lat' with n_side=12");
  auto md = run_runner(dir, "table lat --rows n_side --cols visc --value err --agg count "
                            "--format markdown --where \"lattice=disordered\"");
  ASSERT_EQ(md.code, 0) << md.out;
  EXPECT_EQ(md.out, "| n_side \\ visc | visc01 | visc03 |\n| --- | ---: | ---: |\n"
                    "| 8 | 1 | 1 |\n| 10 | 1 | 1 |\n");
  auto text = run_runner(dir, "table lat --rows lattice --cols visc --value err --where n_side=8");
  EXPECT_CONTAINS(text.out, "mean(err) for study lat where n_side=8");
  auto csv = run_runner(dir, "export lat --format csv");
  EXPECT_CONTAINS(csv.out, "job,status,scheme,");
  EXPECT_EQ(std::count(csv.out.begin(), csv.out.end(), '\n'), 9);
}

// Issue 16 part 5: a cell that aggregates several jobs says so, with the parameters they differ
// in, and --agg median gives the middle value (one outlier seed cannot carry it).
TEST(Table, CellsOfSeveralJobsAreNotedAndHaveAMedian) {
  TempDir dir;
  write_text(dir / "s.toml", R"([study]
name = "seeds"
case = "patch_test"
[params]
lattice = "disordered"
[sweep]
visc = ["visc01"]
n_side = [8]
seed = [1, 2, 3]
)");
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  auto mean = run_runner(dir, "table seeds --rows n_side --cols visc --value err");
  ASSERT_EQ(mean.code, 0) << mean.out;
  EXPECT_CONTAINS(mean.out, "note: each cell is the mean of 3 jobs that differ in seed");
  auto vals = run_runner(dir, "query --db results/results.sqlite \"SELECT printf('%.17g', value) "
                              "FROM job_metrics WHERE metric = 'err' ORDER BY value\"");
  std::vector<double> errs;
  std::istringstream in(vals.out);
  std::string line;
  std::getline(in, line); // header
  while (std::getline(in, line))
    errs.push_back(std::stod(line));
  ASSERT_EQ(errs.size(), 3u) << vals.out;
  ASSERT_LT(errs[0], errs[1]);
  auto median = run_runner(
      dir, "table seeds --rows n_side --cols visc --value err --agg median --format csv");
  ASSERT_EQ(median.code, 0) << median.out;
  const std::string head = "n_side \\ visc,visc01\n8,";
  ASSERT_EQ(median.out.rfind(head, 0), 0u) << median.out;
  EXPECT_NEAR(std::stod(median.out.substr(head.size())), errs[1], 1e-5 * errs[1]) << median.out;
  auto one = run_runner(dir, "table seeds --rows n_side --cols visc --value err --where seed=2");
  EXPECT_EQ(one.out.find("note: each cell"), std::string::npos) << one.out;
}

// Rows and columns come in the order the study lists their values, not sorted (issue 16 part 5).
TEST(Table, RowsAndColumnsFollowTheStudysOrder) {
  TempDir dir;
  write_text(dir / "s.toml", R"([study]
name = "order"
case = "patch_test"
[params]
lattice = "uniform"
[sweep]
visc = ["visc04", "visc01"]
n_side = [10, 8]
)");
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  auto t = run_runner(dir, "table order --rows n_side --cols visc --value err --agg count "
                           "--format csv");
  ASSERT_EQ(t.code, 0) << t.out;
  EXPECT_EQ(t.out, "n_side \\ visc,visc04,visc01\n10,1,1\n8,1,1\n");
}

TEST(Failures, AttemptsAreClassifiedAndKeptAcrossRetries) {
  TempDir dir;
  write_text(dir / "s.toml", R"([study]
name = "f"
case = "patch_test"
[sweep]
n_side = [8, 9, 10, 11, 12]
)");
  fs::path db = dir / "results" / "results.sqlite";
  // Different faults for different jobs, one run each (the match picks one job).
  auto r1 = run_runner(dir, "s.toml", "SPH_RUNNER_FAULT=exit3 SPH_RUNNER_FAULT_MATCH=n_side=8");
  EXPECT_EQ(r1.code, 1) << r1.out;
  auto r2 = run_runner(dir, "s.toml --retry-failed --max-attempts 1",
                       "SPH_RUNNER_FAULT=segv SPH_RUNNER_FAULT_MATCH=n_side=8");
  EXPECT_CONTAINS(r2.out, "reached --max-attempts 1");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 5); // nothing retried
  auto r3 = run_runner(dir, "s.toml --retry-failed",
                       "SPH_RUNNER_FAULT=segv SPH_RUNNER_FAULT_MATCH=n_side=8");
  EXPECT_EQ(r3.code, 1);
  auto r4 = run_runner(dir, "s.toml --retry-failed",
                       "SPH_RUNNER_FAULT=throw SPH_RUNNER_FAULT_MATCH=n_side=8");
  auto r5 = run_runner(dir, "s.toml --retry-failed --max-attempts 5 --timeout 0.3",
                       "SPH_RUNNER_FAULT=hang SPH_RUNNER_FAULT_MATCH=n_side=8");
  EXPECT_EQ(r5.code, 1);
  EXPECT_EQ(sql_text(db, "SELECT a.attempt, a.state, a.failure_class FROM attempts a JOIN jobs j "
                         "ON j.id=a.job_id JOIN job_params p ON p.job_id=j.id AND "
                         "p.name='n_side' WHERE p.value=8 ORDER BY a.attempt"),
            "1|failed|exit\n2|failed|signal\n3|failed|exception\n4|timeout|timeout\n");
  // Every attempt keeps its error text.
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE state != 'done' AND (error_text IS "
                        "NULL OR error_text = '')"),
            0);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE error_text LIKE '%exited with code "
                        "3%' OR error_text LIKE '%SIGSEGV%' OR error_text LIKE '%injected "
                        "failure%' OR error_text LIKE '%wall-clock limit%'"),
            4);
  auto st = run_runner(dir, "status f");
  EXPECT_CONTAINS(st.out, "[timeout]");
  EXPECT_CONTAINS(st.out, "[exception]");
  EXPECT_CONTAINS(st.out, "[signal]");
  // Retried once more without a fault: done, the four failed attempts stay.
  auto ok = run_runner(dir, "s.toml --retry-failed --max-attempts 5");
  EXPECT_EQ(ok.code, 0) << ok.out;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 9);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'"), 5);
}

// Seeing what happens: the live line on request (a terminal by default) and plain progress lines
// otherwise, both with the running jobs' simulated-time fractions and an ETA.
TEST(Progress, LiveLineAndPlainLogLinesShowRunningFractionsAndEta) {
  TempDir dir;
  // Jobs of 300 steps x 4 ms = 1.2 s each (step_sleep_us is not part of the job key).
  auto study = [](const std::string& alphas) {
    return "[study]\nname = \"prog\"\ncase = \"checkpoint_demo\"\n[params]\nsteps = 300\n"
           "step_sleep_us = 4000\n[sweep]\nalpha = [" +
           alphas + "]\n";
  };
  write_text(dir / "s.toml", study("0.25, 0.5"));
  auto plain = run_runner(dir, "s.toml -j 2 --progress plain --log-every-s 0.3");
  ASSERT_EQ(plain.code, 0) << plain.out;
  EXPECT_EQ(plain.out.find('\r'), std::string::npos) << plain.out;
  EXPECT_CONTAINS(plain.out, "progress: [0/2] running 2, failed 0, diverged 0, elapsed ");
  EXPECT_CONTAINS(plain.out, "%, "); // the two jobs' fractions
  EXPECT_CONTAINS(plain.out, "[1/2] done ");
  EXPECT_CONTAINS(plain.out, "[2/2] done ");

  // One more value: the new job runs alone, with a live line whose ETA comes from the job times
  // measured by the first run.
  write_text(dir / "s.toml", study("0.25, 0.5, 0.75"));
  auto live = run_runner(dir, "s.toml -j 2 --progress live");
  ASSERT_EQ(live.code, 0) << live.out;
  EXPECT_CONTAINS(live.out, "\r\033[K[0/1] running 1, failed 0, diverged 0, elapsed ");
  EXPECT_CONTAINS(live.out, "%");
  EXPECT_CONTAINS(live.out, " | ");
  EXPECT_EQ(live.out.find("ETA ?"), std::string::npos) << live.out;
  // A finished job's line stays above the live line (cleared, printed, line redrawn below).
  EXPECT_CONTAINS(live.out, "\r\033[K[1/1] done ");
  EXPECT_CONTAINS(live.out, "prog: 3 jobs: 3 done");
}
