// What long jobs rely on, and commands that fail loudly: a recomputation that fails or diverges
// never takes a result away (its attempt and metrics are kept beside the result); commands whose
// output cannot be written fail; `publish` takes regular files only and leaves out retired jobs;
// the runner works as PID 1 (a plain container); #SBATCH values are single lines; `query` has a
// time limit; read commands work on the first schema; ambiguous command-line values are refused.
// Each test fails on the code before its fix (run it with SPH_RUNNER_EXE=<older build>).
#include "e2e_helpers.hpp"
#include "schema.hpp"
#include "store.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <set>
#include <sstream>
#include <sys/wait.h>

using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

// Four patch_test jobs (two viscous operators x two resolutions).
std::string patch_study(const std::string& name) {
  return "[study]\nname = \"" + name +
         "\"\ncase = \"patch_test\"\n[sweep]\nvisc = [\"visc01\", \"visc03\"]\nn_side = [8, 9]\n";
}

// Exit code of a shell command line run in dir (stdout and stderr as the line says).
int shell(const TempDir& dir, const std::string& line) {
  const std::string cmd = "cd '" + dir.path().string() + "' && " + line;
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string exe() {
  return "'" + runner_exe() + "'";
}

} // namespace

// --rerun-stale with a build that crashes every job: the done results stay (state, metrics, the
// job_metrics view, export); the failed attempts are recorded beside them. A later recomputation
// that finishes replaces them, and the first attempts' metrics stay queryable.
TEST(LongJobs, AFailingRecomputationKeepsTheDoneResult) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("keep"));
  fs::path db = dir / "results" / "results.sqlite";
  ASSERT_EQ(run_runner(dir, "s.toml", "SPH_RUNNER_SOLVER_FINGERPRINT=aaaa").code, 0);
  const std::int64_t rows = sql_int(db, "SELECT count(*) FROM metrics");
  ASSERT_GT(rows, 4);
  const std::string before = sql_text(db, "SELECT * FROM job_metrics ORDER BY job, metric");

  auto crash = run_runner(dir, "s.toml --rerun-stale",
                          "SPH_RUNNER_SOLVER_FINGERPRINT=bbbb SPH_RUNNER_FAULT=segv");
  EXPECT_CONTAINS(crash.out, "killed by SIGSEGV");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM metrics"), rows);
  EXPECT_EQ(sql_text(db, "SELECT * FROM job_metrics ORDER BY job, metric"), before);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'"), 4);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE attempt=2 AND state='failed' AND "
                        "failure_class='signal'"),
            4);
  // Still stale (made by aaaa), and export still has every result.
  EXPECT_CONTAINS(run_runner(dir, "status", "SPH_RUNNER_SOLVER_FINGERPRINT=bbbb").out,
                  "stale: 4 finished job(s)");
  auto ex = run_runner(dir, "export keep --format json", "SPH_RUNNER_SOLVER_FINGERPRINT=bbbb");
  EXPECT_EQ(ex.code, 0) << ex.out;
  EXPECT_CONTAINS(ex.out, "\"err\"");

  auto again = run_runner(dir, "s.toml --rerun-stale", "SPH_RUNNER_SOLVER_FINGERPRINT=bbbb");
  EXPECT_EQ(again.code, 0) << again.out;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM metrics WHERE attempt=3"), rows);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM job_attempt_metrics WHERE attempt=1 AND "
                        "solver_fingerprint='aaaa' AND attempt_state='done'"),
            rows);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM job_attempt_metrics WHERE attempt=3 AND "
                        "solver_fingerprint='bbbb'"),
            rows);
  EXPECT_EQ(run_runner(dir, "status", "SPH_RUNNER_SOLVER_FINGERPRINT=bbbb").out.find("stale:"),
            std::string::npos);
}

// --retry-failed of diverged jobs with a build that crashes them: the diverged results and their
// metrics stay; a retry that finishes done replaces them.
TEST(LongJobs, AFailingRetryKeepsTheDivergedResult) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("div"));
  fs::path db = dir / "results" / "results.sqlite";
  run_runner(dir, "s.toml", "SPH_RUNNER_FAULT=nan");
  ASSERT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='diverged'"), 4);
  const std::int64_t rows = sql_int(db, "SELECT count(*) FROM metrics");
  ASSERT_GT(rows, 4);
  auto crash = run_runner(dir, "s.toml --retry-failed", "SPH_RUNNER_FAULT=segv");
  EXPECT_CONTAINS(crash.out, "killed by SIGSEGV");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM metrics"), rows);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='diverged'"), 4);
  auto fixed = run_runner(dir, "s.toml --retry-failed");
  EXPECT_EQ(fixed.code, 0) << fixed.out;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'"), 4);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM metrics WHERE attempt<>3 OR name='injected_nan'"), 0);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM job_attempt_metrics WHERE attempt=1 AND "
                        "metric='injected_nan'"),
            4);
}

// Jobs retired by a change of the study file (still in the database, hidden by export and
// status) are not published, and leave a file that had them.
TEST(LongJobs, PublishLeavesOutJobsRetiredByAChangedStudyFile) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("ret"));
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  auto first = run_runner(dir, "publish ret --out pub.csv");
  ASSERT_EQ(first.code, 0) << first.out;
  EXPECT_CONTAINS(first.out, "4 jobs added");
  write_text(dir / "s.toml", "[study]\nname = \"ret\"\ncase = \"patch_test\"\n[sweep]\nvisc = "
                             "[\"visc01\", \"visc03\"]\nn_side = [8]\n");
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  const std::string exported = run_runner(dir, "export ret --format csv").out;
  auto again = run_runner(dir, "publish ret --out pub.csv");
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_CONTAINS(again.out, "0 jobs added, 2 replaced, 0 kept from the file, 2 removed");
  auto fresh = run_runner(dir, "publish ret --out fresh.csv");
  EXPECT_CONTAINS(fresh.out, "2 jobs added, 0 replaced, 0 kept");
  // The same jobs as export: two of them.
  std::set<std::string> published;
  std::istringstream rows(read_file(dir / "fresh.csv"));
  std::string line;
  std::getline(rows, line);
  while (std::getline(rows, line))
    published.insert(line.substr(4, 64)); // "ret,<key>,..."
  EXPECT_EQ(published.size(), 2u);
  for (const auto& key : published)
    EXPECT_CONTAINS(exported, key);
  auto sorted_lines = [](const std::string& text) {
    std::multiset<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);)
      out.insert(l);
    return out;
  };
  EXPECT_EQ(sorted_lines(read_file(dir / "pub.csv")), sorted_lines(read_file(dir / "fresh.csv")));
}
