// Issue 16 part 3: `runner STUDY --set KEY=VALUE` (overrides; a differing value is a new job),
// `--where KEY=VALUE` (only the matching jobs run) and `runner one CASE KEY=VALUE ...` (one job
// in the foreground, study `adhoc`). Bad input is refused before anything runs, naming the key.
#include "e2e_helpers.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

const char* grid_study = R"([study]
name = "grid"
case = "patch_test"
[sweep]
visc = ["visc01", "visc03"]
n_side = [8, 10]
)";

const fs::path db_of(const TempDir& dir) {
  return dir / "results" / "results.sqlite";
}

} // namespace

TEST(Overrides, SetOverridesEveryJobAndADifferingValueIsANewJob) {
  TempDir dir;
  const fs::path db = db_of(dir);
  write_text(dir / "s.toml", grid_study);
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  ASSERT_EQ(sql_int(db, "SELECT count(*) FROM jobs"), 4);

  // n_side = 12 is not in the study: two new jobs (one per visc), registered under their own tier.
  auto r = run_runner(dir, "s.toml --set n_side=12 --progress plain");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "grid [full+n_side=12]: 2 jobs: 0 done already, 2 to run (2 new)");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs"), 6);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE json_extract(params_json, '$.n_side') = "
                        "12 AND state='done'"),
            2);
  // The study's own jobs stay its current jobs.
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM study_jobs WHERE tier='full' AND current"), 4);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM study_jobs WHERE tier='full+n_side=12' AND current"),
            2);

  // The same override again runs nothing; a value the study has is the same job as the study's.
  auto again = run_runner(dir, "s.toml --set n_side=12");
  EXPECT_CONTAINS(again.out, "2 done already, 0 to run");
  auto same = run_runner(dir, "s.toml --set n_side=8");
  ASSERT_EQ(same.code, 0) << same.out;
  EXPECT_CONTAINS(same.out, "grid [full+n_side=8]: 2 jobs: 2 done already, 0 to run");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs"), 6);

  // Two overrides together, one of a fixed parameter (h_over_dx is not swept): 1 x 1 job.
  auto two = run_runner(dir, "s.toml --set visc=visc03 --set h_over_dx=1.5");
  ASSERT_EQ(two.code, 0) << two.out;
  EXPECT_CONTAINS(two.out, "[full+visc=visc03,h_over_dx=1.5]: 2 jobs");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE json_extract(params_json, "
                        "'$.h_over_dx') = 1.5 AND json_extract(params_json, '$.visc') = 'visc03'"),
            2);
}

TEST(Overrides, WhereRunsOnlyTheMatchingJobs) {
  TempDir dir;
  const fs::path db = db_of(dir);
  write_text(dir / "s.toml", grid_study);
  auto dry = run_runner(dir, "s.toml --where visc=visc03 --dry-run");
  ASSERT_EQ(dry.code, 0) << dry.out;
  EXPECT_CONTAINS(dry.out, "2 of them match --where visc=visc03");
  EXPECT_EQ(dry.out.find("visc=visc01"), std::string::npos) << dry.out;

  auto r = run_runner(dir, "s.toml --where visc=visc03 --progress plain");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "only the 2 job(s) matching --where visc=visc03 run");
  // The whole study is registered; only the matching jobs ran.
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs"), 4);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 2);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done' AND "
                        "json_extract(params_json, '$.visc') = 'visc03'"),
            2);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='pending' AND "
                        "json_extract(params_json, '$.visc') = 'visc01'"),
            2);
  // Two filters together select one job; then the plain run does the rest.
  auto one = run_runner(dir, "s.toml --where visc=visc01 --where n_side=10");
  ASSERT_EQ(one.code, 0) << one.out;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 3);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done' AND "
                        "json_extract(params_json, '$.visc') = 'visc01' AND "
                        "json_extract(params_json, '$.n_side') = 10"),
            1);
  auto rest = run_runner(dir, "s.toml");
  EXPECT_CONTAINS(rest.out, "3 done already, 1 to run");
  // --set and --where together: the override first, then the filter on the overridden jobs.
  auto both = run_runner(dir, "s.toml --set n_side=12 --where visc=visc01");
  ASSERT_EQ(both.code, 0) << both.out;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done' AND "
                        "json_extract(params_json, '$.n_side') = 12"),
            1);
}

TEST(Overrides, BadSetAndWhereAreRefusedBeforeAnythingRuns) {
  TempDir dir;
  write_text(dir / "s.toml", grid_study);
  struct Case {
    std::string args;
    std::vector<std::string> says;
  };
  const std::vector<Case> cases = {
      {"--set nside=12", {"--set nside=12", "unknown parameter 'nside'", "did you mean 'n_side'"}},
      {"--set n_side=abc", {"--set n_side=abc", "expected an integer", "n_side is an integer"}},
      {"--set n_side=1.5", {"--set n_side=1.5", "expected an integer"}},
      {"--set n_side=2", {"n_side=2", "out of range", "[4, 2000]"}},
      {"--set visc=visc9", {"--set visc=visc9", "is not one of 'visc01'"}},
      {"--set n_side", {"--set 'n_side': expected KEY=VALUE"}},
      {"--where visc=visc02",
       {"--where visc=visc02", "no job of the study has visc = visc02",
        "its values: 'visc01', 'visc03'"}},
      {"--where n_sid=8", {"--where n_sid=8", "unknown parameter 'n_sid'"}},
      {"--where n_side=eight", {"--where n_side=eight", "expected an integer"}},
  };
  for (const auto& c : cases) {
    auto r = run_runner(dir, "s.toml " + c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.out;
    for (const auto& s : c.says)
      EXPECT_CONTAINS(r.out, s) << c.args;
    EXPECT_FALSE(fs::exists(dir / "results")) << c.args; // nothing ran, nothing was written
  }
}

TEST(One, RunsOneJobInTheForegroundAndPrintsItsMetricsAndPaths) {
  TempDir dir;
  const fs::path db = db_of(dir);
  auto r = run_runner(dir, "one patch_test visc=visc03 n_side=40");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "patch_test visc=visc03 n_side=40: done");
  EXPECT_CONTAINS(r.out, "metrics:\n");
  EXPECT_CONTAINS(r.out, "  err ");
  EXPECT_CONTAINS(r.out, "  n_particles ");
  const std::string key = sql_text(db, "SELECT key FROM jobs").substr(0, 64);
  const std::string folder = "results/adhoc/" + key;
  EXPECT_CONTAINS(r.out, "log:     " + folder + "/attempt-1.log\n");
  EXPECT_CONTAINS(r.out, "outputs: " + folder + "/ (params.json)");
  EXPECT_TRUE(fs::exists(dir / folder / "attempt-1.log"));
  EXPECT_TRUE(fs::exists(dir / folder / "params.json"));
  // Recorded like any job: study adhoc, its parameters, its metrics (the printed err is the
  // database's value).
  EXPECT_EQ(sql_text(db, "SELECT study, status FROM job_metrics WHERE metric='err'"),
            "adhoc|done\n");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE json_extract(params_json, '$.n_side') = "
                        "40 AND json_extract(params_json, '$.visc') = 'visc03'"),
            1);
  std::string err = sql_text(db, "SELECT printf('%.10g', value) FROM metrics WHERE name='err'");
  err.pop_back();
  EXPECT_CONTAINS(r.out, err + "\n");

  // Another job joins the adhoc study; the first stays in it. The first again runs nothing.
  ASSERT_EQ(run_runner(dir, "one patch_test n_side=20").code, 0);
  auto ex = run_runner(dir, "export adhoc --format json");
  ASSERT_EQ(ex.code, 0) << ex.out;
  EXPECT_EQ(nlohmann::json::parse(ex.out).size(), 2u);
  auto again = run_runner(dir, "one patch_test visc=visc03 n_side=40");
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_CONTAINS(again.out, "1 done already, 0 to run");
  EXPECT_CONTAINS(again.out, err + "\n");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 2);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM study_jobs WHERE current"), 2);
}

TEST(One, BadCaseKeyOrValueIsRefusedBeforeAnythingRuns) {
  TempDir dir;
  struct Case {
    std::string args;
    std::vector<std::string> says;
  };
  const std::vector<Case> cases = {
      {"one patch_tst", {"unknown case 'patch_tst'", "did you mean 'patch_test'"}},
      {"one patch_test n_sid=40", {"runner one n_sid=40", "unknown parameter 'n_sid'"}},
      {"one patch_test n_side=forty", {"runner one n_side=forty", "expected an integer"}},
      {"one patch_test visc=visc9", {"visc=visc9", "is not one of"}},
      {"one patch_test n_side=40 n_side=20", {"'n_side' is given twice"}},
      {"one patch_test --scheme isph", {"case 'patch_test' takes no scheme"}},
      {"one taylor_green --scheme nope", {"--scheme scheme=nope", "is not one of"}},
      {"one patch_test n_side", {"'n_side': expected KEY=VALUE"}},
  };
  for (const auto& c : cases) {
    auto r = run_runner(dir, c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.out;
    for (const auto& s : c.says)
      EXPECT_CONTAINS(r.out, s) << c.args;
    EXPECT_FALSE(fs::exists(dir / "results")) << c.args;
  }
}

TEST(Overrides, SubmitTakesSetAndWhereToo) {
  TempDir dir;
  write_text(dir / "s.toml", grid_study);
  // --dry-run: the manifest and batch script are written, sbatch is not called (no cluster
  // needed); the jobs given back are pending again.
  auto r = run_runner(dir, "submit s.toml --slurm --dry-run --where visc=visc03 --set n_side=12");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "grid [full+n_side=12]: 2 jobs: 0 done, 0 already submitted, 1 to submit");
  EXPECT_CONTAINS(r.out, "(1 jobs in 1 array tasks); not submitted (--dry-run)");
  const fs::path db = db_of(dir);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE failure_class='submit'"), 1);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs j JOIN attempts a ON a.job_id=j.id WHERE "
                        "json_extract(j.params_json, '$.visc') = 'visc03' AND "
                        "json_extract(j.params_json, '$.n_side') = 12"),
            1);
}
