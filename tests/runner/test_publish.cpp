// Issue 15 section 4: `runner publish STUDY` writes the committed record of a study's runs,
// docs/results/<study>.csv, one row per job and metric with exactly the header
// `study,job,tier,code_version,params,metric,value`; values round-trip; a second database adds
// its jobs and keeps the file's others; a job published again from a database that ran it for
// another tier keeps both tier labels; a file of another shape is refused and left unchanged.
#include "commands.hpp"
#include "e2e_helpers.hpp"

#include <gtest/gtest.h>

#include <map>

using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

const char* study = R"([study]
name = "pub"
case = "patch_test"
[sweep]
visc = ["visc01", "visc03"]
n_side = [8, 10]
[tiers.quick]
sweep = { n_side = [8] }
)";

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    out.push_back(l);
  return out;
}

// One value of a query (sql_text ends each row with a line break).
std::string one(const fs::path& db, const std::string& sql) {
  std::string s = sql_text(db, sql);
  return s.substr(0, s.find('\n'));
}

} // namespace

TEST(Publish, OneRowPerJobAndMetricThatRoundTrips) {
  TempDir dir;
  write_text(dir / "s.toml", study);
  ASSERT_EQ(run_runner(dir, "s.toml --tier quick").code, 0);
  fs::create_directories(dir / "docs" / "results");
  auto r = run_runner(dir, "publish pub");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "2 jobs added");
  const auto lines = lines_of(read_file(dir / "docs" / "results" / "pub.csv"));
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0], "study,job,tier,code_version,params,metric,value");
  const fs::path db = dir / "results" / "results.sqlite";
  // Every metric of every done job, once, in the file.
  EXPECT_EQ(static_cast<std::int64_t>(lines.size()) - 1,
            sql_int(db, "SELECT count(*) FROM metrics"));
  // A row carries the job's key, its tier, the attempt's code version, the canonical JSON and the
  // value to the last bit (shortest round-trip form).
  const std::string key = one(db, "SELECT key FROM jobs WHERE params_json LIKE "
                                  "'%\"n_side\":8%' AND params_json LIKE '%visc03%'");
  const std::string params = one(db, "SELECT params_json FROM jobs WHERE key='" + key + "'");
  const std::string version = one(db, "SELECT code_version FROM attempts LIMIT 1");
  const double err = std::stod(one(
      db,
      "SELECT printf('%.17g', value) FROM metrics m JOIN jobs j ON j.id=m.job_id WHERE j.key='" +
          key + "' AND m.name='err'"));
  const std::string prefix = "pub," + key + ",quick," + version + "," + csv_field(params) + ",err,";
  bool found = false;
  for (const auto& l : lines)
    if (l.rfind(prefix, 0) == 0) {
      found = true;
      EXPECT_EQ(std::stod(l.substr(prefix.size())), err) << l;
    }
  EXPECT_TRUE(found) << prefix;
}

TEST(Publish, ASecondDatabaseAddsItsJobsAndKeepsTheOthers) {
  TempDir dir;
  write_text(dir / "s.toml", study);
  ASSERT_EQ(run_runner(dir, "s.toml --tier quick --db a.sqlite").code, 0);
  ASSERT_EQ(run_runner(dir, "s.toml --where n_side=10 --db b.sqlite").code, 0);
  ASSERT_EQ(run_runner(dir, "publish pub --db a.sqlite --out pub.csv").code, 0);
  const auto first = lines_of(read_file(dir / "pub.csv"));
  auto r = run_runner(dir, "publish pub --db b.sqlite --out pub.csv");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "2 jobs added, 0 replaced, 2 kept");
  const auto both = lines_of(read_file(dir / "pub.csv"));
  // The first database's rows are still there, unchanged and first; the second's follow.
  ASSERT_GT(both.size(), first.size());
  EXPECT_EQ(std::vector<std::string>(both.begin(), both.begin() + first.size()), first);
  std::map<std::string, int> jobs;
  for (std::size_t i = 1; i < both.size(); ++i)
    ++jobs[both[i].substr(4, 64)];
  EXPECT_EQ(jobs.size(), 4u);
  // Publishing the first again replaces its jobs in place: the file does not change.
  r = run_runner(dir, "publish pub --db a.sqlite --out pub.csv");
  EXPECT_CONTAINS(r.out, "0 jobs added, 2 replaced, 2 kept");
  EXPECT_EQ(lines_of(read_file(dir / "pub.csv")), both);
}

TEST(Publish, AJobPublishedAgainForAnotherTierKeepsBothTierLabels) {
  TempDir dir;
  write_text(dir / "s.toml", study + std::string("[tiers.coarse]\nsweep = { n_side = [8] }\n"));
  ASSERT_EQ(run_runner(dir, "s.toml --tier quick --db a.sqlite").code, 0);
  ASSERT_EQ(run_runner(dir, "s.toml --tier coarse --db b.sqlite").code, 0);
  ASSERT_EQ(run_runner(dir, "publish pub --db a.sqlite --out pub.csv").code, 0);
  auto r = run_runner(dir, "publish pub --db b.sqlite --out pub.csv");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "0 jobs added, 2 replaced, 0 kept");
  const auto lines = lines_of(read_file(dir / "pub.csv"));
  ASSERT_GT(lines.size(), 1u);
  for (std::size_t i = 1; i < lines.size(); ++i)
    EXPECT_EQ(csv_split(lines[i])[2], "quick;coarse") << lines[i];
  // Publishing the same database again changes nothing; publishing the first again takes its
  // values (its own CPU timings) and keeps both labels.
  ASSERT_EQ(run_runner(dir, "publish pub --db b.sqlite --out pub.csv").code, 0);
  EXPECT_EQ(lines_of(read_file(dir / "pub.csv")), lines);
  ASSERT_EQ(run_runner(dir, "publish pub --db a.sqlite --out pub.csv").code, 0);
  const auto again = lines_of(read_file(dir / "pub.csv"));
  ASSERT_EQ(again.size(), lines.size());
  for (std::size_t i = 1; i < again.size(); ++i)
    EXPECT_EQ(csv_split(again[i])[2], "quick;coarse") << again[i];
}

TEST(Publish, AFileOfAnotherShapeIsRefusedAndLeftUnchanged) {
  TempDir dir;
  write_text(dir / "s.toml", study);
  ASSERT_EQ(run_runner(dir, "s.toml --tier quick").code, 0);
  write_text(dir / "pub.csv", "job,metric,value\nx,err,1\n");
  auto r = run_runner(dir, "publish pub --out pub.csv");
  EXPECT_NE(r.code, 0);
  EXPECT_CONTAINS(r.out, "pub.csv: line 1: expected the header");
  EXPECT_EQ(read_file(dir / "pub.csv"), "job,metric,value\nx,err,1\n");
  write_text(dir / "pub.csv",
             "study,job,tier,code_version,params,metric,value\nother,k,,,{},e,1\n");
  r = run_runner(dir, "publish pub --out pub.csv");
  EXPECT_NE(r.code, 0);
  EXPECT_CONTAINS(r.out, "pub.csv: line 2: expected 7 fields of study 'pub'");
  EXPECT_CONTAINS(run_runner(dir, "publish nosuch --out x.csv").out, "no study named 'nosuch'");
}
