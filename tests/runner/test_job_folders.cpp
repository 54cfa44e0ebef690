// Issue 16 part 2: every job folder holds params.json (key, study, tier, typed parameters, code
// version and build, start and end time); export has each job's tier and output folder, and a
// parameter and a metric of the same name get distinct CSV columns.
#include "e2e_helpers.hpp"
#include "expand.hpp"
#include "store.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const char* tiered_study = R"([study]
name = "folders"
case = "patch_test"
[sweep]
visc = ["visc01", "visc03"]
n_side = [8, 10, 12]
[tiers.quick]
sweep = { n_side = [8] }
)";

// The CSV header's column names.
std::vector<std::string> header_of(const std::string& csv) {
  std::vector<std::string> cols;
  std::string line = csv.substr(0, csv.find('\n'));
  for (std::size_t a = 0; a <= line.size();) {
    std::size_t b = std::min(line.find(',', a), line.size());
    cols.push_back(line.substr(a, b - a));
    a = b + 1;
  }
  return cols;
}

} // namespace

TEST(JobFolders, ParamsJsonDescribesEachJob) {
  TempDir dir;
  fs::path db = dir / "results" / "results.sqlite";
  write_text(dir / "s.toml", tiered_study);
  const double before = unix_now();
  // patch_test writes no output files: --keep-logs gives its jobs a folder (their log).
  auto r = run_runner(dir, "s.toml --tier quick --keep-logs --progress plain");
  ASSERT_EQ(r.code, 0) << r.out;
  const double after = unix_now();
  std::string keys = sql_text(db, "SELECT key FROM jobs ORDER BY key");
  ASSERT_EQ(std::count(keys.begin(), keys.end(), '\n'), 2) << keys;
  for (std::size_t a = 0; a < keys.size(); a = keys.find('\n', a) + 1) {
    const std::string key = keys.substr(a, keys.find('\n', a) - a);
    const fs::path folder = dir / "results" / "folders" / key;
    ASSERT_TRUE(fs::exists(folder / "params.json")) << folder;
    EXPECT_TRUE(fs::exists(folder / "attempt-1.log")) << folder;
    json p = json::parse(read_file(folder / "params.json"));
    EXPECT_EQ(p.at("format"), "sph-job-params/1");
    EXPECT_EQ(p.at("job"), key);
    EXPECT_EQ(p.at("study"), "folders");
    EXPECT_EQ(p.at("tier"), "quick");
    EXPECT_EQ(p.at("case"), "patch_test");
    EXPECT_EQ(p.at("state"), "done");
    EXPECT_EQ(p.at("attempt"), 1);
    // Every parameter, typed: integers as integers, reals as reals, strings as strings.
    ASSERT_TRUE(p.at("params").at("n_side").is_number_integer()) << p.dump();
    EXPECT_EQ(p.at("params").at("n_side"), 8);
    EXPECT_TRUE(p.at("params").at("h_over_dx").is_number_float());
    EXPECT_TRUE(p.at("params").at("visc").is_string());
    // The identity parameters are the database's canonical ones.
    EXPECT_EQ(p.at("identity_params"),
              json::parse(sql_text(db, "SELECT params_json FROM jobs WHERE key='" + key + "'")));
    EXPECT_FALSE(p.at("code_version").get<std::string>().empty());
    EXPECT_FALSE(p.at("compiler").get<std::string>().empty());
    EXPECT_FALSE(p.at("solver_fingerprint").get<std::string>().empty());
    EXPECT_TRUE(p.contains("build_type"));
    const double t0 = p.at("started_at_unix"), t1 = p.at("finished_at_unix");
    EXPECT_LE(before - 1, t0);
    EXPECT_LE(t0, t1);
    EXPECT_LE(t1, after + 1);
    EXPECT_EQ(p.at("started_at").get<std::string>().back(), 'Z'); // ISO 8601, UTC
    EXPECT_EQ(p.at("started_at").get<std::string>().substr(0, 2), "20");
  }
  // The database records the folder of every job.
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE output_dir LIKE '%/folders/' || key"), 2);
}

TEST(JobFolders, ExportHasEachJobsTierAndOutputFolder) {
  TempDir dir;
  write_text(dir / "s.toml", tiered_study);
  ASSERT_EQ(run_runner(dir, "s.toml --tier quick --keep-logs").code, 0);
  // The quick jobs are in the full study too; the others leave no folder (no outputs, no log).
  ASSERT_EQ(run_runner(dir, "s.toml").code, 0);
  auto csv = run_runner(dir, "export folders --format csv");
  ASSERT_EQ(csv.code, 0) << csv.out;
  auto cols = header_of(csv.out);
  ASSERT_GE(cols.size(), 6u);
  EXPECT_EQ(std::vector<std::string>(cols.begin(), cols.begin() + 5),
            (std::vector<std::string>{"job", "status", "scheme", "tier", "output_dir"}));
  EXPECT_CONTAINS(csv.out, ",full;quick,results/folders/"); // n_side = 8: both tiers, a folder
  EXPECT_CONTAINS(csv.out, ",full,,");                      // n_side = 10, 12: no folder
  auto js = run_runner(dir, "export folders --format json");
  ASSERT_EQ(js.code, 0) << js.out;
  json arr = json::parse(js.out);
  ASSERT_EQ(arr.size(), 6u);
  for (const auto& j : arr) {
    const bool quick = j.at("params").at("n_side") == 8;
    EXPECT_EQ(j.at("tier"), quick ? "full;quick" : "full");
    if (!quick) {
      EXPECT_TRUE(j.at("output_dir").is_null()) << j.dump();
      continue;
    }
    const std::string folder = j.at("output_dir");
    EXPECT_EQ(folder, "results/folders/" + j.at("job").get<std::string>());
    EXPECT_TRUE(fs::exists(dir / folder / "params.json")) << folder;
  }
}

TEST(JobFolders, AParameterAndAMetricOfTheSameNameGetDistinctColumns) {
  TempDir dir;
  // A job whose case reports a metric named like one of its parameters (as checkpoint_demo's
  // t_end would be if t_end were a parameter): n_side here.
  {
    Store store = Store::open_write(dir / "r.sqlite");
    Expansion ex = expand(parse_study("[study]\nname = \"clash\"\ncase = \"patch_test\"\n"
                                      "[sweep]\nn_side = [8, 10]\n",
                                      "s.toml"));
    auto sync = store.sync_study({"clash", "patch_test", "", "/x/s.toml", "abc"}, "full", ex.jobs,
                                 false, 3, unix_now());
    for (const auto& row : sync.jobs) {
      int attempt = *store.claim(row.id, {"hostA", 1, 1, "v", "c", unix_now()});
      Finish f;
      f.state = JobState::done;
      f.finished_at = unix_now();
      f.metrics = {{"err", 0.5}, {"n_side", 99.0}, {"status", 1.0}};
      ASSERT_TRUE(store.finish(row.id, attempt, "hostA", 1, f));
    }
  }
  auto csv = run_runner(dir, "export clash --format csv --db r.sqlite");
  ASSERT_EQ(csv.code, 0) << csv.out;
  auto cols = header_of(csv.out);
  std::set<std::string> unique(cols.begin(), cols.end());
  EXPECT_EQ(unique.size(), cols.size()) << csv.out; // no column name twice
  EXPECT_TRUE(unique.count("param.n_side")) << csv.out;
  EXPECT_TRUE(unique.count("metric.n_side")) << csv.out;
  EXPECT_TRUE(unique.count("metric.status")) << csv.out; // a fixed column's name
  EXPECT_FALSE(unique.count("n_side")) << csv.out;
  EXPECT_TRUE(unique.count("err")) << csv.out;  // no collision: the plain name
  EXPECT_TRUE(unique.count("seed")) << csv.out; // a parameter without a collision
  // The values are under the right columns: the parameter 8 or 10, the metric 99.
  const std::size_t p = std::find(cols.begin(), cols.end(), "param.n_side") - cols.begin();
  const std::size_t m = std::find(cols.begin(), cols.end(), "metric.n_side") - cols.begin();
  std::string row = csv.out.substr(csv.out.find('\n') + 1);
  row = row.substr(0, row.find('\n'));
  auto cells = header_of(row);
  ASSERT_EQ(cells.size(), cols.size());
  EXPECT_EQ(cells[p], "8");
  EXPECT_EQ(cells[m], "99.0");
}
