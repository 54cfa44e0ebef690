// Issue 17: the runner under hostile testing. One test (or more) per defect, each failing on the
// code before the fix: an SQLite error in the middle of a sweep (a full disk), a stopped runner
// whose jobs must not run twice, someone else's SQLite files, unbounded expansion, a `query` that
// could write, values that pass validation and fail every job, hostile study files, SIGHUP and
// SIGPIPE, gnuplot strings, a killed report's temporary files, cosmetic messages; and stale
// results (solver fingerprint) and parameters added at a neutral default.
#include "cases/case.hpp"
#include "e2e_helpers.hpp"
#include "expand.hpp"
#include "job_key.hpp"
#include "report.hpp"
#include "store.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <set>
#include <sys/file.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>

using namespace sph;
using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

std::string patch_study(const std::string& name, const std::string& n_sides,
                        const std::string& extra = "") {
  return "[study]\nname = \"" + name + "\"\ncase = \"patch_test\"\n" + extra +
         "\n[sweep]\nvisc = [\"visc01\", \"visc03\"]\nn_side = [" + n_sides + "]\n";
}

std::string range(int from, int to) {
  std::string s;
  for (int i = from; i <= to; ++i)
    s += (s.empty() ? "" : ", ") + std::to_string(i);
  return s;
}

std::string bytes_of(const fs::path& p) {
  return fs::exists(p) ? read_file(p) : std::string("<missing>");
}

void sleep_s(double s) {
  std::this_thread::sleep_for(std::chrono::duration<double>(s));
}

} // namespace

// --- 1. An SQLite error during a sweep (a full disk) -------------------------------------------

TEST(Hostile, FullDiskDuringASweepStopsCleanlyNamingTheDatabase) {
  if (geteuid() != 0)
    GTEST_SKIP() << "needs root to mount a 2 MB tmpfs";
  TempDir dir;
  fs::path mnt = dir / "small";
  fs::create_directories(mnt);
  if (mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=2m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here";
  struct Unmount {
    fs::path p;
    ~Unmount() { umount2(p.c_str(), MNT_DETACH); }
  } unmount{mnt};
  write_text(dir / "small.toml", patch_study("first", "8, 9"));
  ASSERT_EQ(run_runner(dir, "small.toml --db small/f.sqlite").code, 0);
  // Fill most of the disk (as in the issue), then a 300-job study into the same database: its
  // registration fits, its claims and results do not.
  std::system(
      ("dd if=/dev/zero of='" + (mnt / "filler").string() + "' bs=1k count=1400 > /dev/null 2>&1")
          .c_str());
  std::string big = "[study]\nname = \"big\"\ncase = \"patch_test\"\n[sweep]\nvisc = [\"visc01\", "
                    "\"visc02\", \"visc03\"]\nn_side = [" +
                    range(8, 107) + "]\n";
  write_text(dir / "big.toml", big);
  auto r = run_runner(dir, "big.toml --db small/f.sqlite -j 2 --progress plain");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_EQ(r.out.find("terminate"), std::string::npos) << r.out;
  EXPECT_CONTAINS(r.out, "database 'small/f.sqlite'");
  EXPECT_CONTAINS(r.out, "full");
  // Nothing lost: the first study's results are there; after freeing space the study finishes
  // with every job done exactly once and nothing left running.
  fs::remove(mnt / "filler");
  auto again = run_runner(dir, "big.toml --db small/f.sqlite -j 2 --progress plain");
  EXPECT_EQ(again.code, 0) << again.out;
  fs::path db = mnt / "f.sqlite";
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'"), 300); // 4 shared
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE state='running'"), 0);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM (SELECT job_id FROM attempts WHERE state='done' "
                        "GROUP BY job_id HAVING count(*) > 1)"),
            0);
}

TEST(Hostile, TheWalIsCheckpointedAndTruncated) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("walcheck", range(8, 20)));
  fs::path db = dir / "results" / "results.sqlite";
  ASSERT_EQ(run_runner(dir, "s.toml --db results/results.sqlite -j 2").code, 0);
  // A reader connection open (idle) while a second run records 26 more jobs: the runner is not
  // the last connection, so SQLite does not remove the -wal file at close; the runner's own
  // checkpoint must leave it empty.
  Db reader = Db::reader(db.string());
  reader.scalar_int("SELECT count(*) FROM jobs");
  write_text(dir / "s.toml", patch_study("walcheck", range(8, 33)));
  ASSERT_EQ(run_runner(dir, "s.toml --db results/results.sqlite -j 2").code, 0);
  std::error_code ec;
  auto wal = fs::file_size(db.string() + "-wal", ec);
  EXPECT_TRUE(ec || wal == 0) << "-wal has " << wal << " bytes";
}

// --- 2. A stopped runner's jobs never run twice -----------------------------------------------

TEST(Hostile, AStoppedRunnerOnThisHostKeepsItsJobs) {
  TempDir dir;
  write_text(dir / "slow.toml", R"([study]
name = "slow"
case = "checkpoint_demo"
[params]
steps = 3000
step_sleep_us = 1000
[sweep]
n = [16, 32]
)");
  pid_t a =
      spawn_runner(dir.path(), {"slow.toml", "-j", "2", "--heartbeat-s", "0.2"}, {}, dir / "a.log");
  fs::path db = dir / "results" / "results.sqlite";
  for (int i = 0; i < 100 && (!fs::exists(db) || sql_int(db, "SELECT count(*) FROM jobs WHERE "
                                                             "state='running'") < 2);
       ++i)
    sleep_s(0.1);
  ASSERT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='running'"), 2);
  kill(a, SIGSTOP);
  sleep_s(1.5); // the heartbeats are now far older than B's --stale-after-s
  auto b = run_runner(dir, "slow.toml -j 2 --stale-after-s 0.5 --progress plain");
  kill(a, SIGCONT);
  EXPECT_EQ(b.code, 0) << b.out;
  EXPECT_CONTAINS(b.out, "2 running elsewhere, 0 to run");
  EXPECT_EQ(wait_exit(a), 0) << read_file(dir / "a.log");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 2);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done' AND attempts=1"), 2);
}

// A second runner started from a copy of the binary under another name (a stored baseline binary
// for an A/B comparison, say) leaves a live runner's job alone: an owner on this host is
// recognised by its pid and a start before its claim, not by the program's name. (Found when such
// a copy abandoned a 20-minute 3D cavity job of a live runner, whose result was then lost.)
TEST(Hostile, ARunnerOfAnotherNameLeavesALiveRunnersJobAlone) {
  TempDir dir;
  write_text(dir / "slow.toml", R"([study]
name = "slow"
case = "checkpoint_demo"
[params]
steps = 3000
step_sleep_us = 1000
)");
  fs::copy_file(runner_exe(), dir / "baseline_runner_copy");
  pid_t a = spawn_runner(dir.path(), {"slow.toml", "-j", "1"}, {}, dir / "a.log");
  fs::path db = dir / "results" / "results.sqlite";
  for (int i = 0; i < 100 && (!fs::exists(db) || sql_int(db, "SELECT count(*) FROM jobs WHERE "
                                                             "state='running'") < 1);
       ++i)
    sleep_s(0.1);
  ASSERT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='running'"), 1);
  const std::string cmd =
      "cd '" + dir.path().string() +
      "' && ./baseline_runner_copy slow.toml -j 1 --progress plain > b.log 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << read_file(dir / "b.log");
  EXPECT_CONTAINS(read_file(dir / "b.log"), "1 running elsewhere, 0 to run");
  EXPECT_EQ(wait_exit(a), 0) << read_file(dir / "a.log");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), 1);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done' AND attempts=1"), 1);
}

TEST(Hostile, TwoAttemptsNeverShareAnOutputFolder) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("locked", "8"));
  Study st = load_study(dir / "s.toml");
  Expansion ex = expand(st);
  ASSERT_EQ(ex.jobs.size(), 2u);
  // Another attempt (a runner on another host, or one this runner cannot see) holds the folder
  // of the first job.
  fs::path folder = dir / "results" / "locked" / ex.jobs[0].key;
  fs::create_directories(folder);
  int fd = ::open((folder / ".attempt.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(flock(fd, LOCK_EX | LOCK_NB), 0);
  auto r = run_runner(dir, "s.toml --progress plain");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_CONTAINS(r.out, "its output folder is in use by another attempt");
  fs::path db = dir / "results" / "results.sqlite";
  EXPECT_EQ(sql_text(db, "SELECT state FROM jobs WHERE key='" + ex.jobs[0].key + "'"), "pending\n");
  EXPECT_EQ(sql_text(db, "SELECT state FROM jobs WHERE key='" + ex.jobs[1].key + "'"), "done\n");
  ::close(fd);
  auto again = run_runner(dir, "s.toml --progress plain");
  EXPECT_EQ(again.code, 0) << again.out;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'"), 2);
}

// --- 3. Someone else's SQLite files -----------------------------------------------------------

TEST(Hostile, ForeignSqliteFilesAreRefusedUntouched) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("mine", "8"));
  std::vector<std::pair<std::string, std::string>> files = {
      {"v1.sqlite", "CREATE TABLE t(x); PRAGMA user_version=1"},
      {"v2.sqlite", "CREATE TABLE attempts(x); PRAGMA user_version=2"},
      {"v3.sqlite", "CREATE TABLE jobs(key); CREATE TABLE studies(x); PRAGMA user_version=3"},
      {"app.sqlite", "CREATE TABLE t(x); PRAGMA application_id=1234"},
  };
  for (const auto& [name, sql] : files) {
    {
      Db d((dir / name).string(), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
      d.exec(sql);
    }
    const std::string before = bytes_of(dir / name);
    auto r = run_runner(dir, "s.toml --db " + name);
    EXPECT_EQ(r.code, 1) << name << ": " << r.out;
    EXPECT_CONTAINS(r.out, "not a runner database");
    EXPECT_CONTAINS(r.out, name);
    EXPECT_TRUE(bytes_of(dir / name) == before) << name << " was changed";
    EXPECT_FALSE(fs::exists(dir / (name + "-wal"))) << name;
    auto q = run_runner(dir, "status --db " + name);
    EXPECT_EQ(q.code, 1) << q.out;
    EXPECT_TRUE(bytes_of(dir / name) == before) << name << " was changed by status";
  }
}

TEST(Hostile, RunnerDatabasesOfEarlierVersionsAreRecognisedAndMigrated) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("old", "8"));
  ASSERT_EQ(run_runner(dir, "s.toml --db old.sqlite").code, 0);
  {
    // What a version-3 runner wrote: no application id, no solver_fingerprint column, no
    // attempt_metrics (schema 6).
    Db d((dir / "old.sqlite").string(), SQLITE_OPEN_READWRITE);
    d.exec("DROP VIEW job_attempt_metrics; DROP TABLE attempt_metrics; PRAGMA application_id=0; "
           "ALTER TABLE attempts DROP COLUMN solver_fingerprint; PRAGMA user_version=3");
  }
  EXPECT_EQ(sql_int(dir / "old.sqlite", "PRAGMA application_id"), 0);
  auto st = run_runner(dir, "status --db old.sqlite");
  EXPECT_EQ(st.code, 0) << st.out;
  auto r = run_runner(dir, "s.toml --db old.sqlite");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(sql_int(dir / "old.sqlite", "PRAGMA application_id"), Store::application_id);
  EXPECT_EQ(sql_int(dir / "old.sqlite", "PRAGMA user_version"), Store::schema_version);
  // Results made before fingerprints were recorded are shown as stale, not silently reused.
  EXPECT_CONTAINS(r.out, "2 finished job(s) are stale");
}

// --- 4. Bounded expansion ---------------------------------------------------------------------

TEST(Hostile, HugeExpansionsAreRefusedBeforeExpandingWithFileLineAndCount) {
  TempDir dir;
  std::string thousand = range(1, 1000);
  std::string fractions; // 1000 values in [0, 1]
  for (int i = 0; i < 1000; ++i)
    fractions += (i ? ", " : "") + std::to_string(i / 1000.0);
  write_text(dir / "e9.toml",
             "[study]\nname = \"huge\"\ncase = \"patch_test\"\n[sweep]\nn_side = [" +
                 range(4, 1003) + "]\nseed = [" + thousand + "]\ndisorder = [" + fractions + "]\n");
  auto t0 = std::chrono::steady_clock::now();
  auto r = run_runner(dir, "e9.toml --dry-run");
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "e9.toml:5");
  EXPECT_CONTAINS(r.out, "1000000000 jobs");
  EXPECT_CONTAINS(r.out, "--max-jobs");
  EXPECT_LT(s, 5.0);
  // 1e15: five axes of 1000 values (counted in floating point: nothing wraps around).
  std::string axes;
  std::string small;
  for (int i = 0; i < 1000; ++i)
    small += (i ? ", " : "") + std::to_string(i / 4000.0);
  axes += "n_side = [" + range(4, 1003) + "]\nseed = [" + thousand + "]\ndisorder = [" + fractions +
          "]\neta_over_h = [" + small + "]\n";
  std::string h;
  for (int i = 0; i < 1000; ++i)
    h += (i ? ", " : "") + std::to_string(1 + i / 1000.0);
  axes += "h_over_dx = [" + h + "]\n";
  write_text(dir / "e15.toml",
             "[study]\nname = \"huger\"\ncase = \"patch_test\"\n[sweep]\n" + axes);
  auto r15 = run_runner(dir, "e15.toml");
  EXPECT_EQ(r15.code, 2) << r15.out.substr(0, 2000);
  EXPECT_CONTAINS(r15.out, "expands to 1.000e+15 jobs");
  EXPECT_FALSE(fs::exists(dir / "results"));
  // The limit can be raised (and lowered).
  write_text(dir / "six.toml", patch_study("six", "8, 9, 10"));
  auto low = run_runner(dir, "six.toml --max-jobs 5 --dry-run");
  EXPECT_EQ(low.code, 2) << low.out;
  EXPECT_CONTAINS(low.out, "6 jobs");
  EXPECT_EQ(run_runner(dir, "six.toml --max-jobs 6 --dry-run").code, 0);
}

TEST(Hostile, ALargeDryRunStreamsItsJobsInBoundedMemory) {
  // 200,000 jobs (100 x 100 x 20 patch_test axes), listed by --dry-run. The expansion held whole
  // took about 2.2 kB a job (440 MB here, 2.1 GB at 1,000,000); streamed, the runner keeps the
  // 32-byte keys met (for duplicates) and a flag per job (for --where): 34 MB here, 84 MB at
  // 1,000,000. Peak resident memory of the child, from wait4's rusage.
  TempDir dir;
  std::string disorder; // 0.05, 0.1, ..., 1.0
  for (int i = 1; i <= 20; ++i)
    disorder += (i > 1 ? ", " : "") + std::to_string(i / 20.0);
  write_text(dir / "big.toml",
             "[study]\nname = \"big\"\ncase = \"patch_test\"\n[sweep]\nn_side = [" + range(4, 103) +
                 "]\nseed = [" + range(1, 100) + "]\ndisorder = [" + disorder + "]\n");
  pid_t pid = spawn_runner(dir.path(), {"big.toml", "--dry-run"}, {}, dir / "out.txt");
  ASSERT_GT(pid, 0);
  int status = 0;
  struct rusage ru {};
  ASSERT_EQ(wait4(pid, &status, 0, &ru), pid);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << read_file(dir / "out.txt");
  const std::string out = read_file(dir / "out.txt");
  EXPECT_CONTAINS(out.substr(0, 200), "big: 200000 jobs (200000 combinations, 0 excluded");
  // the header, the fixed parameters, a line per job, the estimate (unknown) and its basis
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 200004);
  EXPECT_CONTAINS(out, "\nnew      ");
  EXPECT_CONTAINS(out, " n_side=103 seed=100 disorder=1.0\n");
  const double peak_mb = static_cast<double>(ru.ru_maxrss) / 1024;
  std::printf("--dry-run of 200,000 jobs: peak RSS %.0f MB, %.1f CPU s\n", peak_mb,
              static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
                  1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec));
  EXPECT_LT(peak_mb, 150);
}

// --- 5. `runner query` is read-only -----------------------------------------------------------

TEST(Hostile, QueryCannotWriteAnything) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("ro", "8"));
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  fs::path db = dir / "results" / "results.sqlite";
  const std::string before = bytes_of(db);
  for (const std::string& sql :
       {std::string("PRAGMA journal_mode=DELETE"),
        "VACUUM INTO '" + (dir / "copy.db").string() + "'", std::string("VACUUM"),
        "ATTACH '" + (dir / "new.db").string() + "' AS x", std::string("PRAGMA query_only=0"),
        std::string("PRAGMA user_version=7"), std::string("DELETE FROM jobs"),
        std::string("CREATE TABLE t(x)"), std::string("BEGIN IMMEDIATE"),
        std::string("PRAGMA wal_checkpoint(TRUNCATE)"),
        std::string("UPDATE jobs SET state='failed'")}) {
    auto r = run_runner(dir, "query \"" + sql + "\"");
    EXPECT_EQ(r.code, 1) << sql << ": " << r.out;
    EXPECT_CONTAINS(r.out, "refused");
  }
  EXPECT_FALSE(fs::exists(dir / "copy.db"));
  EXPECT_FALSE(fs::exists(dir / "new.db"));
  EXPECT_TRUE(bytes_of(db) == before);
  Db d = Db::reader(db.string());
  Stmt q = d.prepare("PRAGMA journal_mode");
  ASSERT_TRUE(q.step());
  EXPECT_EQ(q.text(0), "wal");
  // Reads still work, pragmas that read too.
  EXPECT_EQ(run_runner(dir, "query \"SELECT count(*) AS n FROM jobs\"").out, "n\n2\n");
  EXPECT_CONTAINS(run_runner(dir, "query \"PRAGMA table_info(jobs)\"").out, "params_json");
  EXPECT_EQ(run_runner(dir, "query \"PRAGMA user_version\"").code, 0);
}

// --- 6. Values that pass validation and fail every job ----------------------------------------

TEST(Hostile, ValuesThatWouldFailEveryJobAreRefusedBeforeAnythingRuns) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("vals", "8"));
  struct Case {
    std::string args, expect;
  };
  for (const auto& c : std::vector<Case>{
           {"--checkpoint-every-s nan", "--checkpoint-every-s"},
           {"--checkpoint-every-s inf", "finite"},
           {"--threads-per-job 100000", "from 1 to 1024"},
           {"--timeout nan", "--timeout"},
           {"--timeout 0", "omit --timeout for no limit"},
           {"--log-every-s nan", "--log-every-s"},
           {"--jobs abc", "not an integer"},
           {"--max-attempts 0", "from 1 to"},
       }) {
    auto r = run_runner(dir, "s.toml " + c.args);
    EXPECT_NE(r.code, 0) << c.args << ": " << r.out;
    EXPECT_CONTAINS(r.out, c.expect);
    // No DBL_MAX printed in 309 digits, no "not in range" for a word.
    EXPECT_EQ(r.out.find("17976931348623157"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("not in range"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir / "results")) << c.args;
  }
  // A study name too long to be a directory name.
  write_text(dir / "long.toml", patch_study(std::string(256, 'a'), "8"));
  auto l = run_runner(dir, "long.toml");
  EXPECT_EQ(l.code, 2) << l.out;
  EXPECT_CONTAINS(l.out, "long.toml:2");
  EXPECT_CONTAINS(l.out, "at most 200");
  // A case's own constraint: lid_driven_cavity needs 1/dx to be an integer.
  write_text(dir / "cav.toml", "[study]\nname = \"cav\"\ncase = \"lid_driven_cavity\"\n[sweep]\n"
                               "dx = [0.05, 0.03]\n");
  auto cav = run_runner(dir, "cav.toml");
  EXPECT_EQ(cav.code, 2) << cav.out;
  EXPECT_CONTAINS(cav.out, "cav.toml:5");
  EXPECT_CONTAINS(cav.out, "1/dx must be an integer");
  EXPECT_EQ(cav.out.find("dx = 0.05:"), std::string::npos) << cav.out;
  EXPECT_FALSE(fs::exists(dir / "results"));
}

// --- 7. Hostile study files -------------------------------------------------------------------

TEST(Hostile, DeepExpressionsBigFilesFifosAndDevicesAreRefusedClearly) {
  TempDir dir;
  auto derived = [](const std::string& expr) {
    return "[study]\nname = \"deep\"\ncase = \"patch_test\"\n[derived]\nh_over_dx = \"" + expr +
           "\"\n";
  };
  std::string parens = std::string(20000, '(') + "1" + std::string(20000, ')');
  std::string minus = std::string(100000, '-') + "1";
  std::string pow;
  for (int i = 0; i < 20000; ++i)
    pow += "1^";
  pow += "1";
  std::string chain;
  for (int i = 0; i < 50000; ++i)
    chain += "1+";
  chain += "1";
  for (const auto& [name, expr] : std::vector<std::pair<std::string, std::string>>{
           {"parens", parens}, {"minus", minus}, {"pow", pow}, {"chain", chain}}) {
    write_text(dir / (name + ".toml"), derived(expr));
    auto r = run_runner(dir, name + ".toml");
    EXPECT_EQ(r.code, 2) << name << ": " << r.out.substr(0, 500);
    EXPECT_CONTAINS(r.out, name + ".toml:5");
  }
  // Moderate nesting is fine.
  write_text(dir / "ok.toml", derived(std::string(30, '(') + "1.2" + std::string(30, ')')));
  EXPECT_EQ(run_runner(dir, "ok.toml --dry-run").code, 0);
  // A FIFO (no writer: would block forever), a device, a file too big.
  ASSERT_EQ(mkfifo((dir / "fifo.toml").c_str(), 0644), 0);
  auto f = run_runner(dir, "fifo.toml", "timeout 10");
  EXPECT_EQ(f.code, 2) << f.out;
  EXPECT_CONTAINS(f.out, "a FIFO");
  auto z = run_runner(dir, "/dev/zero", "timeout 10");
  EXPECT_EQ(z.code, 2) << z.out;
  EXPECT_CONTAINS(z.out, "character device");
  write_text(dir / "big.toml", "# " + std::string(5 << 20, 'x') + "\n");
  auto b = run_runner(dir, "big.toml");
  EXPECT_EQ(b.code, 2) << b.out.substr(0, 500);
  EXPECT_CONTAINS(b.out, "at most 4194304 bytes");
}

// --- 8. SIGHUP and SIGPIPE stop a run like SIGTERM --------------------------------------------

TEST(Hostile, SighupAndSigpipeStopARunCleanly) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("sig", "8, 9"));
  fs::path db = dir / "results" / "results.sqlite";
  pid_t p = spawn_runner(dir.path(), {"s.toml", "-j", "2", "--progress", "plain"},
                         {{"SPH_RUNNER_FAULT", "hang"}}, dir / "hup.log");
  for (int i = 0; i < 100 && (!fs::exists(db) || sql_int(db, "SELECT count(*) FROM jobs WHERE "
                                                             "state='running'") < 2);
       ++i)
    sleep_s(0.1);
  kill(p, SIGHUP);
  EXPECT_EQ(wait_exit(p), 128 + SIGHUP) << read_file(dir / "hup.log");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='running'"), 0);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE state='interrupted'"), 2);

  // `runner ... | head -1`: the reader goes away, the next line written raises SIGPIPE.
  // The jobs hang; the plain progress line every 0.3 s is the write that meets the closed pipe.
  std::string cmd = "cd '" + dir.path().string() + "' && set -o pipefail; SPH_RUNNER_FAULT=hang '" +
                    runner_exe() + "' s.toml -j 2 --progress plain --log-every-s 0.3 | head -1 > " +
                    "head.txt";
  int status = std::system(("bash -c \"" + cmd + "\"").c_str());
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGPIPE);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='running'"), 0);
  EXPECT_GE(sql_int(db, "SELECT count(*) FROM attempts WHERE state='interrupted' AND error_text "
                        "LIKE '%SIGPIPE%'"),
            1);
}

// --- 9. and 10. Reports: gnuplot strings, leftovers of a killed report ------------------------

TEST(Hostile, GnuplotStringsStartingWithAnApostropheAreQuoted) {
  FigureSpec f;
  f.name = "fig";
  f.title = "'t Hooft \\ \"quoted\"";
  f.x = "n_side";
  f.y = {"err"};
  FigureData d;
  d.spec = &f;
  Curve c;
  c.label = "visc='a'";
  c.points = {{8, 0.1, 0.1, 0.1, 1}, {9, 0.05, 0.05, 0.05, 1}};
  d.curves.push_back(c);
  std::string script = gnuplot_script(d, "fig.svg", "svg");
  EXPECT_CONTAINS(script, "set title \"'t Hooft \\\\ \\\"quoted\\\"\"");
  EXPECT_CONTAINS(script, "set output 'fig.svg'"); // plain strings keep single quotes
  std::string program;
  auto version = gnuplot_version(&program);
  if (!version)
    GTEST_SKIP() << "gnuplot is not installed";
  TempDir dir;
  DrawOutcome out = draw_figure(program, *version, dir.path(), "fig", script, "svg");
  EXPECT_TRUE(out.drawn) << out.error << "\n" << script;
  EXPECT_CONTAINS(read_file(dir / "fig.svg"), "t Hooft");
}

TEST(Hostile, ALaterReportRemovesAKilledReportsTemporaryFiles) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("rep", "8, 9") + R"(
[[figures]]
name = "conv"
x = "n_side"
y = "err"
group = ["visc"]
)");
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  fs::path out = dir / "results" / "report" / "rep";
  fs::create_directories(out);
  for (const char* leftover : {"conv.tmp.svg", "conv.tmp.png", "conv.run.gp", "conv.gp.tmp",
                               "index.html.tmp", "old.sha256.tmp"})
    write_text(out / leftover, "partial");
  auto r = run_runner(dir, "report s.toml");
  ASSERT_EQ(r.code, 0) << r.out;
  for (const auto& e : fs::directory_iterator(out)) {
    std::string n = e.path().filename().string();
    EXPECT_EQ(n.find(".tmp"), std::string::npos) << n;
    EXPECT_EQ(n.find(".run.gp"), std::string::npos) << n;
  }
  EXPECT_TRUE(fs::exists(out / "index.html"));
}

// --- 11. Cosmetic ------------------------------------------------------------------------------

TEST(Hostile, QueryMessagesAndBlobs) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("cos", "8"));
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  auto empty = run_runner(dir, "query \"  \"");
  EXPECT_EQ(empty.code, 1);
  EXPECT_CONTAINS(empty.out, "the SQL statement is empty");
  EXPECT_EQ(empty.out.find("not an error"), std::string::npos) << empty.out;
  auto blob = run_runner(dir, "query \"SELECT x'00ff0a41' AS b\"");
  EXPECT_EQ(blob.code, 0) << blob.out;
  EXPECT_EQ(blob.out, "b\nX'00ff0a41'\n");
}

// --- No result silently reused from older code -------------------------------------------------

TEST(Hostile, ResultsOfOtherSolverCodeAreStaleShownAndRecomputedOnRequest) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("fp", "8, 9"));
  fs::path db = dir / "results" / "results.sqlite";
  const std::string old_code = "SPH_RUNNER_SOLVER_FINGERPRINT=aaaa";
  const std::string new_code = "SPH_RUNNER_SOLVER_FINGERPRINT=bbbb";
  ASSERT_EQ(run_runner(dir, "s.toml", old_code).code, 0);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE solver_fingerprint='aaaa'"), 4);
  // Same code: nothing stale.
  auto same = run_runner(dir, "s.toml", old_code);
  EXPECT_EQ(same.out.find("stale"), std::string::npos) << same.out;
  // Other solver code: the results are kept, and said to be stale everywhere.
  auto run = run_runner(dir, "s.toml", new_code);
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_CONTAINS(run.out, "4 done already");
  EXPECT_CONTAINS(run.out, "4 finished job(s) are stale");
  EXPECT_CONTAINS(run.out, "--rerun-stale");
  auto st = run_runner(dir, "status", new_code);
  EXPECT_CONTAINS(st.out, "stale: 4 finished job(s)");
  auto ex = run_runner(dir, "export fp --format csv", new_code);
  EXPECT_CONTAINS(ex.out, ",stale\n");
  EXPECT_CONTAINS(ex.out, ",1\n");
  auto js = run_runner(dir, "export fp --format json", new_code);
  EXPECT_CONTAINS(js.out, "\"stale\": true");
  auto tb = run_runner(dir, "table fp --rows n_side --cols visc --value err", new_code);
  EXPECT_CONTAINS(tb.out, "4 of the study's finished jobs are stale");
  // --rerun-stale recomputes them under the new code; then nothing is stale.
  auto re = run_runner(dir, "s.toml --rerun-stale", new_code);
  EXPECT_EQ(re.code, 0) << re.out;
  EXPECT_CONTAINS(re.out, "recomputing 4 stale job(s)");
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts WHERE solver_fingerprint='bbbb' AND "
                        "state='done'"),
            4);
  EXPECT_EQ(run_runner(dir, "status", new_code).out.find("stale:"), std::string::npos);
  EXPECT_CONTAINS(run_runner(dir, "export fp --format csv", new_code).out, ",0\n");
}

TEST(Hostile, TheSolverFingerprintChangesWithSolverFilesOnly) {
  TempDir dir;
  fs::path src = dir / "src";
  fs::create_directories(src / "solver" / "cases");
  fs::create_directories(src / "runner");
  write_text(src / "solver" / "cases" / "a.cpp", "int a = 1;\n");
  write_text(src / "solver" / "b.hpp", "#pragma once\n");
  write_text(src / "runner" / "r.cpp", "int r = 1;\n");
  auto fingerprint = [&] {
    std::string cmd = std::string("'") + CMAKE_EXE + "' -DSRC='" + src.string() + "' -DOUT='" +
                      (dir / "fp.hpp").string() + "' -P '" + SPH_SOURCE_DIR +
                      "/cmake/solver_fingerprint.cmake'";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    return read_file(dir / "fp.hpp");
  };
  const std::string first = fingerprint();
  EXPECT_CONTAINS(first, "#define SPH_SOLVER_FINGERPRINT \"");
  write_text(src / "runner" / "r.cpp", "int r = 2; // a runner-only change\n");
  EXPECT_EQ(fingerprint(), first);
  write_text(src / "solver" / "cases" / "a.cpp", "int a = 2;\n");
  const std::string second = fingerprint();
  EXPECT_NE(second, first);
  write_text(src / "solver" / "new.cpp", "\n"); // a new solver file
  EXPECT_NE(fingerprint(), second);
}

// A case's fingerprint (SPH_CASE_FINGERPRINTS) covers the solver without the case files and its
// own file: adding a case or editing another leaves it; a shared file, a helper under cases/ that
// registers no case, or its own file change it.
TEST(Hostile, ACasesFingerprintCoversTheSharedSolverAndItsOwnFileOnly) {
  TempDir dir;
  fs::path src = dir / "src";
  fs::create_directories(src / "solver" / "cases");
  write_text(src / "solver" / "shared.hpp", "int shared = 1;\n");
  write_text(src / "solver" / "cases" / "helper.cpp", "int helper = 1;\n");
  write_text(src / "solver" / "cases" / "a.cpp", "const Registrar<CaseInfo> a(make_a());\n");
  write_text(src / "solver" / "cases" / "b.cpp", "const Registrar<CaseInfo> b(make_b());\n");
  // The fingerprint of case file `name` ("" if not listed), or the whole solver's for "".
  auto fingerprint = [&](const std::string& name) {
    std::string cmd = std::string("'") + CMAKE_EXE + "' -DSRC='" + src.string() + "' -DOUT='" +
                      (dir / "fp.hpp").string() + "' -P '" + SPH_SOURCE_DIR +
                      "/cmake/solver_fingerprint.cmake'";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    const std::string text = read_file(dir / "fp.hpp");
    const std::string at = name.empty() ? "SPH_SOLVER_FINGERPRINT \"" : "{\"" + name + "\", \"";
    const auto k = text.find(at);
    return k == std::string::npos ? std::string() : text.substr(k + at.size(), 16);
  };
  const std::string a0 = fingerprint("a.cpp"), b0 = fingerprint("b.cpp"), s0 = fingerprint("");
  ASSERT_EQ(a0.size(), 16u);
  ASSERT_EQ(b0.size(), 16u);
  EXPECT_NE(a0, b0);
  EXPECT_EQ(fingerprint("helper.cpp"), ""); // registers no case: shared
  write_text(src / "solver" / "cases" / "c.cpp", "const Registrar<CaseInfo> c(make_c());\n");
  EXPECT_EQ(fingerprint("a.cpp"), a0) << "adding a case changed another case's fingerprint";
  EXPECT_EQ(fingerprint("c.cpp").size(), 16u);
  EXPECT_NE(fingerprint(""), s0); // the whole solver's does change
  write_text(src / "solver" / "cases" / "b.cpp", "const Registrar<CaseInfo> b(make_b2());\n");
  EXPECT_EQ(fingerprint("a.cpp"), a0) << "editing case b changed case a's fingerprint";
  EXPECT_NE(fingerprint("b.cpp"), b0);
  write_text(src / "solver" / "cases" / "helper.cpp", "int helper = 2;\n");
  const std::string a1 = fingerprint("a.cpp");
  EXPECT_NE(a1, a0);
  write_text(src / "solver" / "shared.hpp", "int shared = 2;\n");
  EXPECT_NE(fingerprint("a.cpp"), a1);
}

// In this build every case of the solver finds its own fingerprint (its registering file's name
// matches the generated table), rather than falling back silently to the whole solver's.
TEST(Hostile, EveryCaseOfTheSolverHasItsOwnFingerprint) {
  if (std::getenv("SPH_RUNNER_SOLVER_FINGERPRINT"))
    GTEST_SKIP() << "fingerprint overridden";
  std::set<std::string> seen;
  for (const CaseInfo& c : case_registry()) {
    if (c.test_fixture) // checkpoint_demo lives in runner/: the whole solver's
      continue;
    const std::string fp = case_fingerprint(c.name);
    EXPECT_NE(fp, solver_fingerprint()) << c.name << " (" << c.source << ")";
    EXPECT_TRUE(seen.insert(fp).second) << c.name << " shares a fingerprint";
  }
  EXPECT_GE(seen.size(), 10u);
}

// --- A parameter added at a neutral default keeps the keys of finished jobs ---------------------

TEST(Hostile, AParameterAddedAtItsNeutralDefaultKeepsTheJobKeys) {
  CaseInfo before;
  before.name = "demo";
  before.params = {{"a", ParamType::Real, 1.0, "a", {}, {}}};
  CaseInfo after = before;
  ParamSpec ramp{"ramp", ParamType::Real, 0.0, "new, 0 = the old behaviour", 0.0, {}};
  ramp.neutral_default = true;
  after.params.push_back(ramp);
  CaseInfo plain = before; // the same parameter without neutral_default: keys change
  plain.params.push_back({"ramp", ParamType::Real, 0.0, "", 0.0, {}});
  auto key = [](const CaseInfo& info, Params p) {
    Study s;
    s.case_name = info.name;
    s.info = &info;
    return make_job(s, std::move(p));
  };
  const JobSpec old_job = key(before, {{"a", 2.0}});
  const JobSpec at_default = key(after, {{"a", 2.0}, {"ramp", 0.0}});
  EXPECT_EQ(at_default.key, old_job.key);
  EXPECT_EQ(at_default.params_json, old_job.params_json);
  EXPECT_EQ(at_default.params.at("ramp"), ParamValue(0.0)); // the case still receives it
  EXPECT_EQ(key(after, {{"a", 2.0}, {"ramp", std::int64_t{0}}}).key, old_job.key);
  EXPECT_NE(key(after, {{"a", 2.0}, {"ramp", 0.5}}).key, old_job.key);
  EXPECT_NE(key(plain, {{"a", 2.0}, {"ramp", 0.0}}).key, old_job.key);
}

TEST(Hostile, ExistingCasesKeepTheirJobKeys) {
  // The key of a patch_test job computed before this change (regression guard: the neutral
  // default, the validation hook and the fingerprint must not change any existing key).
  Study s = parse_study("[study]\nname = \"k\"\ncase = \"patch_test\"\n", "k.toml");
  Expansion ex = expand(s);
  ASSERT_EQ(ex.jobs.size(), 1u);
  // = SHA-256 of the documented canonical text (docs/runner.md, "Job identity").
  EXPECT_EQ(ex.jobs[0].key, "d25450f316f49551c8083da3e629ff22307e70e4eec511e0324e40ae0d6bf204");
}

TEST(Hostile, OnThisHostALiveOwnerKeepsItsJobWhateverItsHeartbeat) {
  TempDir dir;
  auto store = Store::open_write(dir / "r.sqlite");
  write_text(dir / "s.toml", patch_study("hb", "8, 9"));
  Study st = load_study(dir / "s.toml");
  auto r = store.sync_study({"hb", "patch_test", "", "s.toml", "x"}, "full", expand(st).jobs, false,
                            3, unix_now());
  const double now = unix_now();
  // Both heartbeats 100 s old: this host's live owner keeps its job, another host's is taken.
  store.claim(r.jobs[0].id, {"hostA", 333, 1, "v", "c", now - 100, "fp"});
  store.claim(r.jobs[1].id, {"hostB", 333, 1, "v", "c", now - 100, "fp"});
  auto stale = store.reset_stale("hostA", 999, now, 30, [](int pid, double) { return pid == 333; });
  ASSERT_EQ(stale.size(), 1u);
  EXPECT_CONTAINS(stale[0].reason, "heartbeat stale");
  EXPECT_CONTAINS(stale[0].reason, "hostB");
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM jobs WHERE state='running' AND "
                                  "owner_host='hostA'"),
            1);
}

TEST(Hostile, SubmitShowsStaleJobsAndResubmitsThemOnRequest) {
  TempDir dir;
  write_text(dir / "s.toml", patch_study("fps", "8"));
  ASSERT_EQ(run_runner(dir, "s.toml", "SPH_RUNNER_SOLVER_FINGERPRINT=aaaa").code, 0);
  auto keep =
      run_runner(dir, "submit s.toml --slurm --dry-run", "SPH_RUNNER_SOLVER_FINGERPRINT=bbbb");
  EXPECT_EQ(keep.code, 0) << keep.out;
  EXPECT_CONTAINS(keep.out, "2 finished job(s) are stale");
  EXPECT_CONTAINS(keep.out, "0 to submit");
  auto re = run_runner(dir, "submit s.toml --slurm --dry-run --rerun-stale",
                       "SPH_RUNNER_SOLVER_FINGERPRINT=bbbb");
  EXPECT_EQ(re.code, 0) << re.out;
  EXPECT_CONTAINS(re.out, "resubmitting 2 stale job(s)");
  EXPECT_CONTAINS(re.out, "2 to submit");
}
