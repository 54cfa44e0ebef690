// Queries on a 100,000-job study answer in under a second (issue 7, "Asking the database").
//
// The database is generated in the store's own schema (created by Store::open_write): 100,000
// patch_test jobs of one study (4 forms x 25 sizes x 2 lattices x 25 seeds x 20 disorder
// amplitudes), their canonical parameters, the job_params rows the store derives from them (the
// same json_each statement), one done attempt and three metrics each. SQL generates them in a few
// seconds; running 100,000 jobs would take hours, and registering them through the expansion
// (100,000 SHA-256 keys) is measured by Store.ManyJobsSyncInOneTransactionQuickly at 20,000.
// Each query then runs through the `runner` binary, as a user runs it, process start included;
// the best of two runs must be under one second, and every measured time is printed.
// SPH_RUNNER_BENCH=1 adds two timings for the record: an unfiltered pivot of all 100,000 jobs and
// opening the database for writing (PRAGMA quick_check included).
#include "e2e_helpers.hpp"

#include "store.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

struct Timed {
  CmdResult r;
  double best = 1e9;
  std::vector<double> times;
};

// Runs `runner ARGS` n times; keeps the output of the last run and every wall time.
Timed timed(const TempDir& dir, const std::string& args, int n = 2) {
  Timed t;
  for (int i = 0; i < n; ++i) {
    auto t0 = std::chrono::steady_clock::now();
    t.r = run_runner(dir, args, "", "q.txt");
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    t.times.push_back(s);
    t.best = std::min(t.best, s);
  }
  return t;
}

std::size_t lines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

} // namespace

TEST(QueryScale, HundredThousandJobStudyFiltersThroughTheIndexAndReportsTimes) {
  TempDir dir;
  fs::path db = dir / "results" / "results.sqlite";
  auto t0 = std::chrono::steady_clock::now();
  {
    Store store = Store::open_write(db);
    StudyRecord rec{"big", "patch_test", "", (dir / "big.toml").string(), "generated"};
    store.sync_study(rec, "full", {}, false, 3, unix_now());
    // Job i: disorder varies fastest, then seed, lattice, n_side, visc (the expansion's order).
    store.db().exec("PRAGMA cache_size=-65536");
    WriteTx tx(store.db());
    store.db().exec(
        "WITH RECURSIVE n(i) AS (SELECT 0 UNION ALL SELECT i + 1 FROM n WHERE i < 99999) "
        "INSERT INTO jobs(id, key, case_name, scheme, numerics_version, params_json, state, "
        "  attempts, created_at, updated_at, progress) "
        "SELECT i + 1, printf('%064x', i), 'patch_test', '', 1, "
        "  json_object('dim', 2, 'disorder', (i % 20 + 1) / 20.0, 'eta_over_h', 0.0001, "
        "    'h_over_dx', 1.2, 'kernel', 'cubic_spline', "
        "    'lattice', CASE (i / 500) % 2 WHEN 0 THEN 'uniform' ELSE 'disordered' END, "
        "    'n_side', 8 + (i / 1000) % 25, 'seed', 1 + (i / 20) % 25, "
        "    'visc', 'visc0' || (1 + i / 25000)), "
        "  'done', 1, 0, 1, 1.0 FROM n;"
        "INSERT INTO job_params(job_id, name, value) "
        "  SELECT j.id, p.key, p.value FROM jobs j, json_each(j.params_json) p;"
        "INSERT INTO study_jobs(study_id, job_id, tier, ordinal, current) "
        "  SELECT (SELECT id FROM studies WHERE name = 'big'), id, 'full', id - 1, 1 FROM jobs;"
        "INSERT INTO attempts(job_id, attempt, state, started_at, finished_at, wall_s, cpu_s, "
        "  host, pid, threads, code_version, compiler) "
        "  SELECT id, 1, 'done', 0, 1, 1, 1, 'gen', 1, 1, 'gen', 'gen' FROM jobs;"
        "INSERT INTO metrics(job_id, name, value, attempt, ordinal) "
        "  SELECT id, 'err', 1e-3 * (1 + id % 997), 1, 0 FROM jobs;"
        "INSERT INTO metrics(job_id, name, value, attempt, ordinal) "
        "  SELECT id, 'err_l2', 1e-4 * (1 + id % 991), 1, 1 FROM jobs;"
        "INSERT INTO metrics(job_id, name, value, attempt, ordinal) "
        "  SELECT id, 'laplacian_cpu_s', 0.05, 1, 2 FROM jobs;");
    tx.commit();
    store.db().exec("PRAGMA wal_checkpoint(TRUNCATE)");
  }
  double gen_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM job_params"), 100000 * 9);

  // 1. A pivot over a filtered slice: err by n_side x visc for one lattice, seed and amplitude
  //    (25 x 4 cells, each one job), through the job_params index.
  auto table = timed(dir, "table big --rows n_side --cols visc --value err --format csv "
                          "--where lattice=disordered --where seed=7 --where disorder=0.5");
  ASSERT_EQ(table.r.code, 0) << table.r.out;
  EXPECT_EQ(lines(table.r.out), 26u) << table.r.out;
  // The cell for n_side = 20, visc03 is that job's err, as SQL computes it.
  std::string expect_row20 = sql_text(
      db, "SELECT printf('%.6g', m.value) FROM metrics m JOIN jobs j ON j.id = m.job_id WHERE "
          "m.name = 'err' AND json_extract(j.params_json, '$.n_side') = 20 AND "
          "json_extract(j.params_json, '$.visc') = 'visc03' AND json_extract(j.params_json, "
          "'$.lattice') = 'disordered' AND json_extract(j.params_json, '$.seed') = 7 AND "
          "json_extract(j.params_json, '$.disorder') = 0.5");
  ASSERT_FALSE(expect_row20.empty());
  expect_row20.pop_back();
  EXPECT_CONTAINS(table.r.out, "\n20,");
  {
    auto p = table.r.out.find("\n20,");
    std::string row = table.r.out.substr(p + 1, table.r.out.find('\n', p + 1) - p - 1);
    EXPECT_CONTAINS(row, "," + expect_row20 + ",") << row;
  }

  // 2. Raw SQL over the indexed parameters: every job with n_side = 20 and visc03 (1,000 jobs).
  auto indexed = timed(dir, "query \"SELECT j.key, m.value FROM jobs j JOIN metrics m ON "
                            "m.job_id = j.id AND m.name = 'err' WHERE j.id IN (SELECT job_id FROM "
                            "job_params WHERE name = 'n_side' AND value = 20) AND j.id IN (SELECT "
                            "job_id FROM job_params WHERE name = 'visc' AND value = 'visc03')\"");
  ASSERT_EQ(indexed.r.code, 0) << indexed.r.out;
  EXPECT_EQ(lines(indexed.r.out), 1001u);

  // 3. The same through the stable job_metrics view with json_extract: no index, a scan of every
  //    job's JSON (0.25 s on an idle machine), reported but not held to the limit.
  auto view = timed(dir, "query \"SELECT job, value FROM job_metrics WHERE study = 'big' AND "
                         "metric = 'err' AND json_extract(params, '$.n_side') = 20 AND "
                         "json_extract(params, '$.visc') = 'visc03'\"");
  ASSERT_EQ(view.r.code, 0) << view.r.out;
  EXPECT_EQ(lines(view.r.out), 1001u);

  // 4. Status of the whole study.
  auto status = timed(dir, "status big");
  ASSERT_EQ(status.r.code, 0) << status.r.out;
  EXPECT_CONTAINS(status.r.out, "100000");

  auto show = [](const char* what, const Timed& t) {
    std::string all;
    for (double x : t.times)
      all += (all.empty() ? "" : ", ") + std::to_string(x).substr(0, 5);
    std::printf("[ 100k ] %-52s best %.3f s (%s)\n", what, t.best, all.c_str());
  };
  std::printf("[ 100k ] generated 100,000 jobs (900,000 parameter rows, 300,000 metrics) by SQL "
              "in %.1f s; database %.0f MB\n",
              gen_s, static_cast<double>(fs::file_size(db)) / 1e6);
  show("runner table --where x3 (pivot of 100 jobs)", table);
  show("runner query, job_params filter (1,000 rows)", indexed);
  show("runner query, job_metrics + json_extract (1,000 rows)", view);
  show("runner status big", status);
  if (std::getenv("SPH_RUNNER_BENCH")) {
    // For the record, outside CI (no limit asserted): a pivot of all 100,000 jobs, and opening
    // the database for writing (what every `runner STUDY` does first, PRAGMA quick_check included).
    auto full = timed(dir, "table big --rows n_side --cols visc --value err --format csv", 1);
    ASSERT_EQ(full.r.code, 0) << full.r.out;
    EXPECT_EQ(lines(full.r.out), 26u);
    auto open_write = timed(dir, "ingest", 1);
    ASSERT_EQ(open_write.r.code, 0) << open_write.r.out;
    show("runner table, no filter (pivot of 100,000 jobs)", full);
    show("runner ingest (open for writing + quick_check)", open_write);
  }
  // The parameter filter is an index look-up, not a scan: what keeps it fast at any size.
  std::string plan = sql_text(db, "EXPLAIN QUERY PLAN SELECT job_id FROM job_params WHERE name = "
                                  "'n_side' AND value = 20");
  EXPECT_CONTAINS(plan, "job_params_lookup");
  // The goal, under a second, is a speed goal: it is held only when asked for
  // (SPH_RUNNER_BENCH=1, on a quiet machine); CI reports the numbers above.
  if (std::getenv("SPH_RUNNER_BENCH")) {
    EXPECT_LT(table.best, 1.0);
    EXPECT_LT(indexed.best, 1.0);
    EXPECT_LT(status.best, 1.0);
  }
}
