// End-to-end tests of the `runner` binary on tiny patch_test studies in temporary directories:
// full run and resume, CSV queries, rejected studies leave the database untouched, crashes,
// timeouts and NaNs are recorded while the sweep goes on, kill -9 and SIGINT mid-sweep.
#include "e2e_helpers.hpp"
#include "helpers.hpp"
#include "sqlite.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <thread>

using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

// `runner ARGS` in dir, stdout+stderr captured (e2e_helpers.hpp).
CmdResult run(const TempDir& dir, const std::string& args, const std::string& env = "") {
  return run_runner(dir, args, env);
}

const char* tiny_study = R"([study]
name = "tiny"
case = "patch_test"
[params]
kernel = "cubic_spline"
[sweep]
visc = ["visc01", "visc03"]
n_side = [8, 9]
)";

std::string study_with(const std::string& name, const std::string& n_sides) {
  return "[study]\nname = \"" + name + "\"\ncase = \"patch_test\"\n[sweep]\nn_side = [" + n_sides +
         "]\n";
}

} // namespace

TEST(RunnerE2E, RunsEveryJobThenNothing) {
  TempDir dir;
  write_text(dir / "tiny.toml", tiny_study);
  auto r = run(dir, "tiny.toml -j 2");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "tiny: 4 jobs: 0 done already, 4 to run");
  EXPECT_CONTAINS(r.out, "tiny: 4 jobs: 4 done");
  fs::path db = dir / "results" / "results.sqlite";
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'"), 4);
  EXPECT_EQ(sql_int(db, "SELECT count(DISTINCT job) FROM job_metrics WHERE metric='err'"), 4);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE state='done' AND cpu_s >= 0 AND "
                        "wall_s > 0 AND peak_rss_kb > 0 AND code_version != '' AND host != ''"),
            4);
  EXPECT_FALSE(fs::exists(dir / "results" / ".runner")); // scratch cleaned up

  auto t0 = std::chrono::steady_clock::now();
  auto again = run(dir, "run tiny.toml"); // explicit `run` works too
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_CONTAINS(again.out, "tiny: 4 jobs: 4 done already, 0 to run");
  EXPECT_LT(s, 5.0);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 4);
}

TEST(RunnerE2E, QueryPrintsCsvWithHeader) {
  TempDir dir;
  write_text(dir / "tiny.toml", tiny_study);
  ASSERT_EQ(run(dir, "tiny.toml").code, 0);
  auto q = run(dir, "query \"SELECT study, status, metric FROM job_metrics WHERE metric='err' "
                    "LIMIT 1\"");
  ASSERT_EQ(q.code, 0) << q.out;
  EXPECT_EQ(q.out, "study,status,metric\ntiny,done,err\n");
  auto quoting = run(dir, "query \"SELECT 'a,b' AS x, 'say \\\"hi\\\"' AS y, NULL AS z\"");
  EXPECT_EQ(quoting.out, "x,y,z\n\"a,b\",\"say \"\"hi\"\"\",\n");
  // Read-only: writes are refused.
  auto w = run(dir, "query \"DELETE FROM jobs\"");
  EXPECT_NE(w.code, 0);
  EXPECT_EQ(sql_int(dir / "results" / "results.sqlite", "SELECT count(*) FROM jobs"), 4);
  // The other read commands.
  auto st = run(dir, "status tiny");
  EXPECT_EQ(st.code, 0);
  EXPECT_CONTAINS(st.out, "tiny");
  auto tb = run(dir, "table tiny --rows n_side --cols visc --value err --format csv");
  ASSERT_EQ(tb.code, 0) << tb.out;
  EXPECT_CONTAINS(tb.out, "n_side \\ visc,visc01,visc03\n8,");
  auto ex = run(dir, "export tiny --format json");
  EXPECT_EQ(ex.code, 0);
  EXPECT_CONTAINS(ex.out, "\"n_side\": 9");
  auto cases = run(dir, "cases");
  EXPECT_CONTAINS(cases.out, "patch_test");
  // Every scheme's parameters, with default, range and doc (from the scheme's ParamTable).
  EXPECT_CONTAINS(cases.out, "scheme wcsph_tvf: ");
  EXPECT_CONTAINS(cases.out, "cfl_ad         real   default 0.25             (0.0, 1.0]; advection CFL");
  EXPECT_CONTAINS(cases.out, "scheme isph: ");
  EXPECT_CONTAINS(cases.out, "visc           string default \"visc04\"         one of ");
}

TEST(RunnerE2E, BadStudyIsRejectedAndTheDatabaseIsUntouched) {
  TempDir dir;
  write_text(dir / "bad.toml", std::string(tiny_study) + "kernal = [\"x\"]\n");
  auto r = run(dir, "bad.toml");
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "bad.toml:9");
  EXPECT_CONTAINS(r.out, "did you mean 'kernel'");
  EXPECT_FALSE(fs::exists(dir / "results")); // nothing created

  write_text(dir / "tiny.toml", tiny_study);
  ASSERT_EQ(run(dir, "tiny.toml").code, 0);
  fs::path db = dir / "results" / "results.sqlite";
  std::string before = read_file(db) + read_file(db.string() + "-wal");
  auto r2 = run(dir, "bad.toml");
  EXPECT_EQ(r2.code, 2);
  EXPECT_EQ(before, read_file(db) + read_file(db.string() + "-wal"));
  EXPECT_NE(run(dir, "missing.toml").code, 0);
  auto tier = run(dir, "tiny.toml --tier nope");
  EXPECT_EQ(tier.code, 2);
  EXPECT_CONTAINS(tier.out, "no tier named 'nope'");
  EXPECT_EQ(before, read_file(db) + read_file(db.string() + "-wal"));
}

TEST(RunnerE2E, DryRunListsJobsAndWritesNothing) {
  TempDir dir;
  write_text(dir / "tiny.toml", tiny_study);
  auto r = run(dir, "tiny.toml --dry-run");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "tiny: 4 jobs");
  EXPECT_CONTAINS(r.out, "new      ");
  EXPECT_CONTAINS(r.out, "visc=visc03 n_side=9");
  EXPECT_FALSE(fs::exists(dir / "results"));
}

TEST(RunnerE2E, CrashIsRecordedAndTheSweepGoesOn) {
  TempDir dir;
  write_text(dir / "s.toml", study_with("crash", "8, 9, 10, 11"));
  auto r = run(dir, "s.toml -j 2", "SPH_RUNNER_FAULT=segv SPH_RUNNER_FAULT_MATCH=n_side=9");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "SIGSEGV");
  fs::path db = dir / "results" / "results.sqlite";
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'"), 3);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE state='failed' AND signal=11 AND "
                        "error_text LIKE '%SIGSEGV%'"),
            1);
  // Not retried by default; retried with --retry-failed.
  auto again = run(dir, "s.toml");
  EXPECT_EQ(again.code, 1);
  EXPECT_CONTAINS(again.out,
                  "1 failed/diverged/timed out (not retried; use --retry-failed), 0 to run");
  auto retry = run(dir, "s.toml --retry-failed");
  EXPECT_EQ(retry.code, 0) << retry.out;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'"), 4);
  EXPECT_EQ(sql_int(db, "SELECT max(attempts) FROM jobs"), 2);
}

TEST(RunnerE2E, ExceptionTimeoutAndNanAreClassified) {
  TempDir dir;
  write_text(dir / "s.toml", study_with("faults", "8, 9"));
  fs::path db = dir / "results" / "results.sqlite";
  auto t = run(dir, "s.toml --db results/t.sqlite",
               "SPH_RUNNER_FAULT=throw SPH_RUNNER_FAULT_MATCH=n_side=8");
  EXPECT_EQ(t.code, 1) << t.out;
  EXPECT_EQ(sql_int(dir / "results" / "t.sqlite",
                    "SELECT count(*) FROM attempts WHERE state='failed' AND error_text LIKE "
                    "'exception: injected failure%'"),
            1);

  auto h = run(dir, "s.toml --db results/h.sqlite --timeout 0.5",
               "SPH_RUNNER_FAULT=hang SPH_RUNNER_FAULT_MATCH=n_side=8");
  EXPECT_EQ(h.code, 1) << h.out;
  EXPECT_EQ(
      sql_int(dir / "results" / "h.sqlite", "SELECT count(*) FROM jobs WHERE state='timeout'"), 1);
  EXPECT_EQ(sql_int(dir / "results" / "h.sqlite", "SELECT count(*) FROM jobs WHERE state='done'"),
            1);

  auto n = run(dir, "s.toml --db results/n.sqlite",
               "SPH_RUNNER_FAULT=nan SPH_RUNNER_FAULT_MATCH=n_side=9");
  EXPECT_EQ(n.code, 0) << n.out; // diverged is a result, not a failure
  EXPECT_EQ(
      sql_int(dir / "results" / "n.sqlite", "SELECT count(*) FROM jobs WHERE state='diverged'"), 1);
  EXPECT_EQ(sql_int(dir / "results" / "n.sqlite",
                    "SELECT count(*) FROM job_metrics WHERE status='diverged' AND metric='err'"),
            1);
}

TEST(RunnerE2E, KillNineMidSweepThenResumeRunsEachJobOnce) {
  TempDir dir;
  write_text(dir / "s.toml", study_with("killed", "8, 9, 10, 11, 12, 13, 14, 15"));
  fs::path db = dir / "results" / "results.sqlite";
  std::string cmd = "cd '" + dir.path().string() +
                    "'; SPH_RUNNER_FAULT=slow=0.4 '" RUNNER_EXE
                    "' s.toml -j 2 > bg.txt 2>&1 & echo $! > pid.txt";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  // Wait until some jobs are done, then kill the runner hard.
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    try {
      if (fs::exists(db) && sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'") >= 2 &&
          sql_int(db, "SELECT count(*) FROM jobs WHERE state='running'") >= 1)
        break;
    } catch (...) {
    }
  }
  int pid = std::stoi(read_file(dir / "pid.txt"));
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  auto done_before = sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'");
  EXPECT_GE(done_before, 2);
  EXPECT_LT(done_before, 8);

  auto r = run(dir, "s.toml -j 2");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "recovered");
  EXPECT_CONTAINS(r.out, std::to_string(done_before) + " done already");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'"), 8);
  // Every job completed exactly once; the interrupted attempts are kept as abandoned.
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE state='done'"), 8);
  EXPECT_EQ(sql_int(db, "SELECT max(c) FROM (SELECT count(*) c FROM attempts WHERE "
                        "state='done' GROUP BY job_id)"),
            1);
  EXPECT_GE(sql_int(db, "SELECT count(*) FROM attempts WHERE state='abandoned'"), 1);
  EXPECT_EQ(sql_int(db, "PRAGMA integrity_check"), 0); // "ok" is not an integer
}

TEST(RunnerE2E, SigintPutsRunningJobsBackToPending) {
  TempDir dir;
  write_text(dir / "s.toml", study_with("interrupted", "8, 9, 10, 11"));
  fs::path db = dir / "results" / "results.sqlite";
  std::string cmd =
      "cd '" + dir.path().string() +
      "' && (sh -c 'echo $$ > pid.txt; SPH_RUNNER_FAULT=hang exec \"$0\" s.toml -j 2' "
      "'" RUNNER_EXE "' > bg.txt 2>&1; echo $? > rc.txt) &";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    try {
      if (fs::exists(db) && sql_int(db, "SELECT count(*) FROM jobs WHERE state='running'") == 2)
        break;
    } catch (...) {
    }
  }
  ASSERT_EQ(::kill(std::stoi(read_file(dir / "pid.txt")), SIGINT), 0);
  deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!fs::exists(dir / "rc.txt") && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(std::stoi(read_file(dir / "rc.txt")), 130) << read_file(dir / "bg.txt");
  EXPECT_CONTAINS(read_file(dir / "bg.txt"), "put back to pending");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='pending'"), 4);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE state='interrupted'"), 2);
}
