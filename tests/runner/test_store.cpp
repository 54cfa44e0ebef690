// The SQLite store: schema and version, study sync, the job_metrics view, atomic claims,
// finishing (metrics and state together), stale-job recovery, retries.
#include "expand.hpp"
#include "helpers.hpp"
#include "provenance.hpp"
#include "schema.hpp"
#include "slurm.hpp"
#include "store.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

using namespace sph::runner;
using namespace sph::runner::test;

namespace {

Expansion small_expansion(int n = 3) {
  std::string seeds;
  for (int i = 1; i <= n; ++i)
    seeds += (i > 1 ? ", " : "") + std::to_string(i);
  return expand(parse_study(
      "[study]\nname = \"s\"\ncase = \"patch_test\"\n[sweep]\nseed = [" + seeds + "]\n", "s.toml"));
}

StudyRecord record(const std::string& name = "s") {
  return {name, "patch_test", "", "/x/s.toml", "abc"};
}

AttemptStart starter(int pid = 4242) {
  return {"hostA", pid, 1, "v1", "gcc", unix_now()};
}

std::string state_of(Store& s, std::int64_t id) {
  Stmt q = s.db().prepare("SELECT state FROM jobs WHERE id=?");
  q.bind(1, id);
  q.step();
  return q.text(0);
}

} // namespace

TEST(Store, CreatesVersionedSchemaInWalMode) {
  TempDir dir;
  auto store = Store::open_write(dir / "sub" / "r.sqlite");
  EXPECT_EQ(store.db().scalar_int("PRAGMA user_version"), Store::schema_version);
  Stmt q = store.db().prepare("PRAGMA journal_mode");
  ASSERT_TRUE(q.step());
  EXPECT_EQ(q.text(0), "wal");
  EXPECT_EQ(store.db().scalar_int("PRAGMA foreign_keys"), 1);
  // Opening again is harmless.
  auto again = Store::open_write(dir / "sub" / "r.sqlite");
  EXPECT_EQ(again.db().scalar_int("SELECT count(*) FROM jobs"), 0);
}

TEST(Store, RefusesNewerSchemaAndForeignDatabases) {
  TempDir dir;
  {
    auto s = Store::open_write(dir / "r.sqlite");
    s.db().exec("PRAGMA user_version=99");
  }
  try {
    Store::open_write(dir / "r.sqlite");
    FAIL();
  } catch (const std::exception& e) {
    EXPECT_CONTAINS(e.what(), "schema version 99, newer than this runner supports");
  }
  {
    Db other((dir / "other.sqlite").string(), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
    other.exec("CREATE TABLE t(x)");
  }
  EXPECT_THROW(Store::open_write(dir / "other.sqlite"), std::runtime_error);
  EXPECT_THROW(Store::open_read(dir / "missing.sqlite"), std::runtime_error);
}

TEST(Store, SyncIsIdempotentAndKeepsOrder) {
  TempDir dir;
  auto store = Store::open_write(dir / "r.sqlite");
  auto ex = small_expansion(3);
  auto r1 = store.sync_study(record(), "full", ex.jobs, false, 3, unix_now());
  EXPECT_EQ(r1.inserted, 3u);
  EXPECT_TRUE(r1.study_is_new);
  ASSERT_EQ(r1.jobs.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(r1.jobs[i].ordinal, i);
    EXPECT_EQ(r1.jobs[i].state, "pending");
  }
  auto r2 = store.sync_study(record(), "full", ex.jobs, false, 3, unix_now());
  EXPECT_EQ(r2.inserted, 0u);
  EXPECT_FALSE(r2.study_is_new);
  // Same jobs in another study and tier: shared rows, separate membership.
  auto r3 = store.sync_study(record("other"), "quick", ex.jobs, false, 3, unix_now());
  EXPECT_EQ(r3.inserted, 0u);
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM jobs"), 3);
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM study_jobs"), 6);
  // A smaller study drops the membership of removed jobs, not the jobs.
  auto smaller = small_expansion(2);
  auto r4 = store.sync_study(record(), "full", smaller.jobs, false, 3, unix_now());
  EXPECT_EQ(r4.removed, 1u);
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM jobs"), 3);
  // The stored params are the canonical identity JSON.
  Stmt q = store.db().prepare("SELECT params_json FROM jobs WHERE key=?");
  q.bind(1, ex.jobs[0].key);
  ASSERT_TRUE(q.step());
  EXPECT_EQ(q.text(0), ex.jobs[0].params_json);
}

TEST(Store, ManyJobsSyncInOneTransactionQuickly) {
  TempDir dir;
  auto store = Store::open_write(dir / "r.sqlite");
  auto ex = small_expansion(20000);
  auto t0 = std::chrono::steady_clock::now();
  auto r = store.sync_study(record(), "full", ex.jobs, false, 3, unix_now());
  auto r2 = store.sync_study(record(), "full", ex.jobs, false, 3, unix_now());
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.inserted, 20000u);
  EXPECT_EQ(r2.jobs.size(), 20000u);
  EXPECT_LT(s, 10.0);
}

// Bytes this process has passed to write(2) and pwrite(2) so far (/proc/self/io wchar).
std::int64_t bytes_written() {
  std::ifstream in("/proc/self/io");
  std::string name;
  std::int64_t value = -1;
  while (in >> name >> value)
    if (name == "wchar:")
      return value;
  return -1;
}

TEST(Store, RegisteringManyJobsWritesEachPageAboutOnce) {
  // Registering jobs wrote each changed page again to a statement journal (a temporary file) at
  // every INSERT that could abort half-way (18 pages of 4 kB a job, 1.5 GB for 20,000 jobs): most
  // of the time that a million new jobs took. Now the transaction writes its pages to the WAL
  // about once: a few times the size of the database, whatever the machine's load.
  TempDir dir;
  auto store = Store::open_write(dir / "r.sqlite");
  auto ex = small_expansion(20000);
  const std::int64_t before = bytes_written();
  if (before < 0)
    GTEST_SKIP() << "no /proc/self/io";
  auto r = store.sync_study(record(), "full", ex.jobs, false, 3, unix_now());
  const std::int64_t written = bytes_written() - before;
  store.checkpoint_wal(true);
  const auto db_bytes = static_cast<std::int64_t>(std::filesystem::file_size(dir / "r.sqlite"));
  EXPECT_EQ(r.inserted, 20000u);
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM job_params"), 20000 * 9);
  std::printf("registering 20,000 jobs wrote %.1f MB (database %.1f MB)\n", written / 1e6,
              db_bytes / 1e6);
  EXPECT_LT(written, 4 * db_bytes);
  // Foreign keys are enforced again after the registration.
  EXPECT_EQ(store.db().scalar_int("PRAGMA foreign_keys"), 1);
}

TEST(Store, ClaimIsAtomicAcrossConnections) {
  TempDir dir;
  auto a = Store::open_write(dir / "r.sqlite");
  auto b = Store::open_write(dir / "r.sqlite");
  auto ex = small_expansion(1);
  auto r = a.sync_study(record(), "full", ex.jobs, false, 3, unix_now());
  std::int64_t id = r.jobs[0].id;
  auto first = a.claim(id, starter(1));
  auto second = b.claim(id, starter(2));
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(*first, 1);
  EXPECT_FALSE(second.has_value());
  EXPECT_EQ(state_of(a, id), "running");
  EXPECT_EQ(a.db().scalar_int("SELECT count(*) FROM attempts WHERE state='running'"), 1);
}

TEST(Store, FinishRecordsMetricsAndStateTogether) {
  TempDir dir;
  auto store = Store::open_write(dir / "r.sqlite");
  auto ex = small_expansion(2);
  auto r = store.sync_study(record(), "full", ex.jobs, false, 3, unix_now());
  std::int64_t id = r.jobs[0].id;
  int attempt = *store.claim(id, starter());
  Finish f;
  f.state = "done";
  f.finished_at = unix_now();
  f.wall_s = 0.5;
  f.cpu_s = 0.4;
  f.metrics = {{"err", 0.25}, {"err_l2", std::nan("")}};
  // Someone else's finish (wrong owner) writes nothing.
  EXPECT_FALSE(store.finish(id, attempt, "hostA", 999, f));
  EXPECT_EQ(state_of(store, id), "running");
  EXPECT_TRUE(store.finish(id, attempt, "hostA", 4242, f));
  EXPECT_EQ(state_of(store, id), "done");
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM metrics"), 2);
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM metrics WHERE value IS NULL"), 1);

  // The stable view, with its exact column names.
  Stmt v = store.db().prepare("SELECT * FROM job_metrics ORDER BY metric");
  ASSERT_EQ(v.columns(), 6);
  const char* names[] = {"study", "job", "status", "params", "metric", "value"};
  for (int i = 0; i < 6; ++i)
    EXPECT_EQ(v.column_name(i), names[i]);
  ASSERT_TRUE(v.step());
  EXPECT_EQ(v.text(0), "s");
  EXPECT_EQ(v.text(1), ex.jobs[0].key);
  EXPECT_EQ(v.text(2), "done");
  EXPECT_EQ(v.text(3), ex.jobs[0].params_json);
  EXPECT_EQ(v.text(4), "err");
  EXPECT_DOUBLE_EQ(v.real(5), 0.25);
  // A job in two tiers of a study appears once.
  store.sync_study(record(), "quick", ex.jobs, false, 3, unix_now());
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM job_metrics"), 2);
}

TEST(Store, StaleRunningJobsGoBackToPending) {
  TempDir dir;
  auto store = Store::open_write(dir / "r.sqlite");
  auto ex = small_expansion(3);
  auto r = store.sync_study(record(), "full", ex.jobs, false, 3, unix_now());
  double now = unix_now();
  // Job 0: this host, dead pid. Job 1: other host, stale heartbeat. Job 2: this host, alive.
  store.claim(r.jobs[0].id, {"hostA", 111, 1, "v", "c", now});
  store.claim(r.jobs[1].id, {"hostB", 222, 1, "v", "c", now - 100});
  store.claim(r.jobs[2].id, {"hostA", 333, 1, "v", "c", now});
  auto alive = [](int pid, double) { return pid == 333; };
  auto stale = store.reset_stale("hostA", 999, now, 30, alive);
  ASSERT_EQ(stale.size(), 2u);
  EXPECT_EQ(state_of(store, r.jobs[0].id), "pending");
  EXPECT_EQ(state_of(store, r.jobs[1].id), "pending");
  EXPECT_EQ(state_of(store, r.jobs[2].id), "running");
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM attempts WHERE state='abandoned' AND "
                                  "error_text LIKE 'abandoned: owner process gone%'"),
            1);
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM attempts WHERE state='abandoned' AND "
                                  "error_text LIKE 'abandoned: owner heartbeat stale%'"),
            1);
  // The next claim is attempt 2; the abandoned attempt row is kept.
  EXPECT_EQ(store.claim(r.jobs[0].id, starter()), 2);
  // Our own pid on this host cannot own anything at start: a previous runner with that pid died.
  auto ours = store.reset_stale("hostA", 4242, unix_now(), 30, [](int, double) { return true; });
  EXPECT_EQ(ours.size(), 1u);
}

TEST(Store, HeartbeatAndRelease) {
  TempDir dir;
  auto store = Store::open_write(dir / "r.sqlite");
  auto r = store.sync_study(record(), "full", small_expansion(1).jobs, false, 3, unix_now());
  auto id = r.jobs[0].id;
  int attempt = *store.claim(id, {"hostA", 7, 1, "v", "c", 1000.0});
  store.heartbeat({{id, 0.5}}, "hostA", 7, 2000.0);
  EXPECT_EQ(store.db().scalar_int("SELECT heartbeat_at FROM jobs"), 2000);
  EXPECT_EQ(store.db().scalar_int("SELECT CAST(progress * 10 AS INTEGER) FROM jobs"), 5);
  store.release(id, attempt, "hostA", 7, "interrupted: test", 2001.0);
  EXPECT_EQ(state_of(store, id), "pending");
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM attempts WHERE state='interrupted'"), 1);
}

TEST(Store, RetryFailedRespectsMaxAttempts) {
  TempDir dir;
  auto store = Store::open_write(dir / "r.sqlite");
  auto ex = small_expansion(1);
  auto r = store.sync_study(record(), "full", ex.jobs, false, 2, unix_now());
  auto id = r.jobs[0].id;
  Finish f;
  f.state = "failed";
  f.finished_at = unix_now();
  f.error_text = "boom";
  for (int k = 0; k < 2; ++k) {
    int attempt = *store.claim(id, starter());
    ASSERT_TRUE(store.finish(id, attempt, "hostA", 4242, f));
    auto s = store.sync_study(record(), "full", ex.jobs, false, 2, unix_now());
    EXPECT_EQ(s.jobs[0].state, "failed"); // not retried without the flag
    s = store.sync_study(record(), "full", ex.jobs, true, 2, unix_now());
    EXPECT_EQ(s.jobs[0].state, k == 0 ? "pending" : "failed");
    EXPECT_EQ(s.exhausted, k == 0 ? 0u : 1u);
  }
}

// A `runner submit` killed between marking its jobs submitted and recording the array id leaves
// jobs no array will report: the next ingestion puts them back to pending (attempt kept as stale).
TEST(Store, JobsOfASubmitterThatDiedBeforeSbatchGoBackToPending) {
  TempDir dir;
  auto store = Store::open_write(dir / "r.sqlite");
  auto r = store.sync_study(record(), "full", small_expansion(3).jobs, false, 3, unix_now());
  pid_t dead = fork();
  if (dead == 0)
    _exit(0);
  waitpid(dead, nullptr, 0);
  const std::string host = host_name();
  double now = unix_now();
  auto mark = [&](std::int64_t id, int pid, const char* array_id) {
    Stmt u = store.db().prepare("UPDATE jobs SET state='submitted', attempts=1, owner_host=?, "
                                "owner_pid=?, updated_at=?, slurm_job_id=? WHERE id=?");
    u.bind(1, host).bind(2, pid).bind(3, now).bind(5, id);
    if (array_id)
      u.bind(4, std::string(array_id));
    else
      u.bind_null(4);
    u.run();
    Stmt a = store.db().prepare("INSERT INTO attempts(job_id, attempt, state, started_at, host, "
                                "pid, threads, code_version, compiler) VALUES(?,1,'running',?,"
                                "'slurm',?,1,'v','c')");
    a.bind(1, id).bind(2, now).bind(3, pid).run();
  };
  mark(r.jobs[0].id, static_cast<int>(dead), nullptr);      // submitter gone: orphan
  mark(r.jobs[1].id, static_cast<int>(getppid()), nullptr); // submitter alive: still submitting
  std::ostringstream out;
  IngestReport rep = ingest_slurm(store, out);
  EXPECT_EQ(rep.lost, 1u);
  EXPECT_EQ(state_of(store, r.jobs[0].id), "pending");
  EXPECT_EQ(state_of(store, r.jobs[1].id), "submitted");
  EXPECT_EQ(store.db().scalar_int("SELECT count(*) FROM attempts WHERE state='abandoned' AND "
                                  "failure_class='stale' AND error_text LIKE '%before sbatch%'"),
            1);
}
