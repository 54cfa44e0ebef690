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
#include <thread>

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
  EXPECT_EQ(crash.code, 1) << crash.out; // the attempts failed; the results are kept
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
  EXPECT_EQ(crash.code, 1) << crash.out; // the attempts failed; the results are kept
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

// Every command that writes output exits non-zero when the output cannot be written.
TEST(LongJobs, CommandsWhoseOutputCannotBeWrittenFail) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("full"));
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  for (const std::string cmd :
       {"export full --format csv", "export full --format json",
        "query \"SELECT * FROM job_metrics\"", "table full --rows n_side --cols visc --value err",
        "status", "status full", "cases", "s.toml"}) {
    EXPECT_EQ(shell(dir, exe() + " " + cmd + " > out.txt 2> err.txt"), 0)
        << cmd << ": " << read_file(dir / "err.txt");
    EXPECT_NE(shell(dir, exe() + " " + cmd + " > /dev/full 2> err.txt"), 0) << cmd;
    EXPECT_CONTAINS(read_file(dir / "err.txt"), "cannot write the output");
  }
}

// publish --out a device or a link: refused at once (it read /dev/full forever, growing, and
// waited on /dev/stdout); a regular file is written.
TEST(LongJobs, PublishTakesRegularFilesOnly) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("pub"));
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  for (const std::string out : {"/dev/full", "/dev/stdout", "/dev/null"}) {
    const int code =
        shell(dir, "timeout 20 " + exe() + " publish pub --out " + out + " > log.txt 2>&1");
    EXPECT_NE(code, 124) << out << ": still running after 20 s";
    EXPECT_NE(code, 0) << out;
    EXPECT_CONTAINS(read_file(dir / "log.txt"), "is not a regular file");
  }
  EXPECT_EQ(shell(dir, exe() + " publish pub --out pub.csv > log.txt 2>&1"), 0)
      << read_file(dir / "log.txt");
  EXPECT_CONTAINS(read_file(dir / "pub.csv"), "study,job,tier,code_version,params,metric,value\n");
}

// A runner that is PID 1 (the first process of a container) runs its jobs: a worker whose parent
// is PID 1 is not one whose parent died. Skipped where PID namespaces are not permitted.
TEST(LongJobs, TheRunnerWorksAsPid1) {
  TempDir dir;
  if (shell(dir, "unshare --fork --pid --mount-proc true > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "unshare --fork --pid --mount-proc is not permitted here";
  write_text(dir / "s.toml", patch_study("pid1"));
  EXPECT_EQ(shell(dir, "unshare --fork --pid --mount-proc " + exe() + " s.toml > out.txt 2>&1"), 0)
      << read_file(dir / "out.txt");
  fs::path db = dir / "results" / "results.sqlite";
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'"), 4)
      << sql_text(db, "SELECT attempt, state, error_text FROM attempts");
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

// An #SBATCH value with a line break would put a line of shell into job.sbatch: refused before
// anything is written.
TEST(LongJobs, SbatchValuesWithLineBreaksAreRefused) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("sb"));
  for (const std::string opt : {"--sbatch-arg", "--partition"}) {
    const int code = shell(dir, exe() + " submit s.toml --slurm --dry-run " + opt +
                                    "=\"$(printf -- '--account=x\\ntouch pwned')\" > out.txt 2>&1");
    EXPECT_NE(code, 0) << opt << ": " << read_file(dir / "out.txt");
    EXPECT_CONTAINS(read_file(dir / "out.txt"), "line break");
    EXPECT_EQ(shell(dir, "grep -rqs 'touch pwned' ."), 1) << opt; // in no file
  }
  EXPECT_EQ(shell(dir, exe() + " submit s.toml --slurm --dry-run --sbatch-arg=--account=x " +
                           "> out.txt 2>&1"),
            0)
      << read_file(dir / "out.txt");
}

// A query that never ends (an unbounded recursive CTE) is stopped at its time limit with an
// error saying so.
TEST(LongJobs, QueryStopsAtItsTimeLimit) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("q"));
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  const auto t0 = std::chrono::steady_clock::now();
  const int code = shell(dir, "timeout 60 " + exe() +
                                  " query --timeout 1 \"WITH RECURSIVE c(x) AS (SELECT 1 UNION "
                                  "ALL SELECT x + 1 FROM c) SELECT count(*) FROM c\" > out.txt "
                                  "2> err.txt");
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_NE(code, 124) << "still running after 60 s";
  EXPECT_NE(code, 0);
  EXPECT_CONTAINS(read_file(dir / "err.txt"), "the query was stopped after 1 s");
  EXPECT_LT(s, 30);
  // Rows streamed by an endless query: stopped too.
  EXPECT_NE(shell(dir, "timeout 60 " + exe() +
                           " query --timeout 1 \"WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL "
                           "SELECT x + 1 FROM c) SELECT x FROM c\" > /dev/null 2> err.txt"),
            0);
  EXPECT_CONTAINS(read_file(dir / "err.txt"), "the query was stopped after 1 s");
  EXPECT_EQ(shell(dir, exe() + " query \"SELECT count(*) FROM jobs\" > out.txt 2>&1"), 0);
  EXPECT_EQ(read_file(dir / "out.txt"), "count(*)\n4\n");
}

// A database of the first schema (no study_jobs.current, no failure classes, ...): the read
// commands upgrade it and work, instead of failing with SQLite's "no such column".
TEST(LongJobs, ReadCommandsWorkOnTheFirstSchema) {
  TempDir dir;
  const fs::path db = dir / "v1.sqlite";
  {
    Db d(db.string(), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
    d.exec(migrations().at(0));
    d.exec("PRAGMA user_version=1");
    d.exec("INSERT INTO studies(id, name, case_name, file, definition_sha256, created_at, "
           "updated_at) VALUES(1, 'old', 'patch_test', 's.toml', 'x', 0, 0);"
           "INSERT INTO jobs(id, key, case_name, numerics_version, params_json, state, attempts, "
           "created_at, updated_at) VALUES(1, 'k1', 'patch_test', 1, '{\"n_side\":8}', 'done', "
           "1, 0, 0);"
           "INSERT INTO study_jobs VALUES(1, 1, 'full', 0);"
           "INSERT INTO attempts(job_id, attempt, state, started_at, finished_at, host, pid, "
           "threads, code_version, compiler) VALUES(1, 1, 'done', 0, 1, 'h', 1, 1, 'v', 'c');"
           "INSERT INTO metrics VALUES(1, 'err', 0.5, 1, 0);");
  }
  auto st = run_runner(dir, "status --db v1.sqlite");
  EXPECT_EQ(st.code, 0) << st.out;
  EXPECT_CONTAINS(st.out, "old");
  auto ex = run_runner(dir, "export old --db v1.sqlite --format csv");
  EXPECT_EQ(ex.code, 0) << ex.out;
  EXPECT_CONTAINS(ex.out, "k1,done,");
  EXPECT_CONTAINS(ex.out, "0.5");
  auto q = run_runner(dir, "query --db v1.sqlite \"SELECT job, metric, value FROM job_metrics\"");
  EXPECT_EQ(q.code, 0) << q.out;
  EXPECT_CONTAINS(q.out, "k1,err,0.5");
  EXPECT_EQ(sql_int(db, "PRAGMA user_version"), Store::schema_version);
}

// Command-line values that meant something else than what ran: an unknown --rows/--cols
// parameter (a one-row pivot), a --set KEY given twice (the last value kept), --tier '' (the
// whole study). Each is refused before anything runs, saying what to do.
TEST(LongJobs, AmbiguousCommandLineValuesAreRefused) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("amb"));
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  auto rows = run_runner(dir, "table amb --rows nside --cols visc --value err");
  EXPECT_NE(rows.code, 0) << rows.out;
  EXPECT_CONTAINS(rows.out, "--rows 'nside' is not a parameter of this study's jobs");
  EXPECT_CONTAINS(rows.out, "n_side");
  auto cols = run_runner(dir, "table amb --rows n_side --cols vsic --value err");
  EXPECT_NE(cols.code, 0) << cols.out;
  EXPECT_CONTAINS(cols.out, "--cols 'vsic' is not a parameter");
  EXPECT_EQ(run_runner(dir, "table amb --rows n_side --cols scheme --value err").code, 0);

  fs::path db = dir / "results" / "results.sqlite";
  const std::int64_t attempts = sql_int(db, "SELECT count(*) FROM attempts");
  auto twice = run_runner(dir, "s.toml --set n_side=10 --set n_side=11");
  EXPECT_NE(twice.code, 0) << twice.out;
  EXPECT_CONTAINS(twice.out, "'n_side' is given twice");
  auto tier = run_runner(dir, "s.toml --tier ''");
  EXPECT_NE(tier.code, 0) << tier.out;
  EXPECT_CONTAINS(tier.out, "an empty tier name");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), attempts); // nothing ran
}

// `runner one` runs a failed job again with --retry-failed and a stale one with --rerun-stale,
// as a study run does; without them the recorded outcome is shown and nothing runs.
TEST(LongJobs, RunnerOneRetriesAndRecomputesOnRequest) {
  TempDir dir;
  fs::path db = dir / "results" / "results.sqlite";
  run_runner(dir, "one patch_test n_side=8", "SPH_RUNNER_FAULT=segv");
  ASSERT_EQ(sql_text(db, "SELECT state FROM jobs"), "failed\n");
  run_runner(dir, "one patch_test n_side=8");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 1);
  auto retry = run_runner(dir, "one patch_test n_side=8 --retry-failed");
  EXPECT_EQ(retry.code, 0) << retry.out;
  EXPECT_EQ(sql_text(db, "SELECT state FROM jobs"), "done\n");
  auto stale = run_runner(dir, "one patch_test n_side=8 --rerun-stale",
                          "SPH_RUNNER_SOLVER_FINGERPRINT=cccc");
  EXPECT_EQ(stale.code, 0) << stale.out;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE state='done' AND "
                        "solver_fingerprint='cccc'"),
            1);
}

// The -wal and -shm files deleted in the middle of a sweep: the runner would go on recording into
// a -wal file no other connection reads (results lost to them, jobs run twice). It stops at its
// next heartbeat, naming the file and what to do.
TEST(LongJobs, DeletedWalFilesStopTheSweep) {
  TempDir dir;
  write_text(dir / "s.toml", "[study]\nname = \"wal\"\ncase = \"patch_test\"\n[sweep]\nn_side = "
                             "[8, 9, 10, 11, 12, 13, 14, 15]\n");
  fs::path db = dir / "results" / "results.sqlite";
  pid_t pid = spawn_runner(dir.path(), {"s.toml", "-j", "1", "--heartbeat-s", "0.2"},
                           {{"SPH_RUNNER_FAULT", "slow=0.5"}}, dir / "bg.txt");
  ASSERT_GT(pid, 0);
  for (int i = 0; i < 200 && !(fs::exists(db) && sql_int(db, "SELECT count(*) FROM jobs WHERE "
                                                             "state='done'") >= 1);
       ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(fs::exists(db.string() + "-wal"));
  fs::remove(db.string() + "-wal");
  fs::remove(db.string() + "-shm");
  const int code = wait_exit(pid);
  const std::string log = read_file(dir / "bg.txt");
  EXPECT_NE(code, 0) << log;
  EXPECT_CONTAINS(log, "results.sqlite-wal' was deleted while this runner used it");
  EXPECT_CONTAINS(log, "Stop every runner on this database");
}
