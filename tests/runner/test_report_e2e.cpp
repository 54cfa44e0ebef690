// End-to-end tests of `runner report` on tiny patch_test studies: the page and its figures, only
// changed figures are redrawn, diverged jobs are marked, the page without gnuplot, invalid
// [[figures]] rejected with file:line by both `runner report` and `runner run`.
#include "e2e_helpers.hpp"
#include "helpers.hpp"
#include "io/hdf5.hpp"
#include "sqlite.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

// `runner ARGS` in dir, stdout+stderr captured (e2e_helpers.hpp).
CmdResult run(const TempDir& dir, const std::string& args, const std::string& env = "") {
  return run_runner(dir, args, env);
}

bool have_gnuplot() {
  return std::system("gnuplot --version > /dev/null 2>&1") == 0;
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + 1))
    ++n;
  return n;
}

std::string study(const std::string& n_sides) {
  return R"([study]
name = "figs"
case = "patch_test"
[params]
lattice = "uniform"
[sweep]
visc = ["visc01", "visc03"]
n_side = [)" +
         n_sides + R"(]

[[figures]]
name = "small"
x = "n_side"
y = "err"
group = ["visc"]
where = { n_side = [8, 9] }
log_x = true
log_y = true
fit = "power"

[[figures]]
name = "all"
title = "Every resolution"
x = "n_side"
y = ["err", "err_l2"]
group = ["visc"]
log_y = true
fit = "linear"
mark = ["diverged"]
[[figures.reference]]
label = "x^-2"
expr = "0.5 * x^-2"
citation = "a guide to the eye"
)";
}

} // namespace

TEST(ReportE2E, WritesThePageAndRedrawsOnlyWhatChanged) {
  TempDir dir;
  write_text(dir / "figs.toml", study("8, 9"));
  ASSERT_EQ(run(dir, "figs.toml -j 2 --db r/db.sqlite").code, 0);
  auto r = run(dir, "report figs.toml --db r/db.sqlite");
  ASSERT_EQ(r.code, 0) << r.out;
  fs::path out = dir / "r" / "report" / "figs";
  std::string page = read_file(out / "index.html");
  EXPECT_CONTAINS(page, "<h1>figs</h1>");
  EXPECT_CONTAINS(page, "Every resolution");
  EXPECT_CONTAINS(page, "a guide to the eye");
  // One pivot table per metric of each figure, one cell per (n_side, visc).
  EXPECT_EQ(count(page, "<table class=\"pivot\""), 3u);
  EXPECT_EQ(count(page, "data-params="), 4u + 8u);
  EXPECT_TRUE(fs::exists(out / "small.csv"));
  if (!have_gnuplot()) {
    EXPECT_CONTAINS(page, "gnuplot was not found");
    GTEST_SKIP() << "gnuplot is not installed (Debian package gnuplot-nox): figures not drawn";
  }
  EXPECT_CONTAINS(r.out, "2 figures (2 drawn, 0 unchanged)");
  EXPECT_CONTAINS(page, "<img src=\"small.svg\"");
  EXPECT_CONTAINS(page, "<img src=\"all.svg\"");
  EXPECT_CONTAINS(read_file(out / "small.svg"), "<svg");
  EXPECT_CONTAINS(read_file(out / "all.gp"), "set logscale y 10");

  // Nothing changed: nothing redrawn.
  r = run(dir, "report figs --db r/db.sqlite"); // by name, as recorded in the database
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "2 figures (0 drawn, 2 unchanged)");

  // A new resolution changes the figure of every resolution, not the one of n_side 8 and 9.
  write_text(dir / "figs.toml", study("8, 9, 10"));
  ASSERT_EQ(run(dir, "figs.toml -j 2 --db r/db.sqlite").code, 0);
  r = run(dir, "report figs.toml --db r/db.sqlite");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "2 figures (1 drawn, 1 unchanged)");
  EXPECT_EQ(count(read_file(out / "index.html"), "data-params="), 4u + 12u);

  // --tier: the jobs of one tier ("full": the study without a tier).
  r = run(dir, "report figs.toml --db r/db.sqlite --tier full --out full");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "6 jobs");
  r = run(dir, "report figs.toml --db r/db.sqlite --tier quick");
  EXPECT_EQ(r.code, 1);
  EXPECT_CONTAINS(r.out, "no jobs in tier 'quick'");

  // PNG output into another directory.
  r = run(dir, "report figs.toml --db r/db.sqlite --out png --image-format png");
  ASSERT_EQ(r.code, 0) << r.out;
  std::string png = read_file(dir / "png" / "all.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
}

TEST(ReportE2E, MarksDivergedJobs) {
  TempDir dir;
  write_text(dir / "figs.toml", study("8, 9"));
  ASSERT_EQ(run(dir, "figs.toml -j 2 --db r/db.sqlite",
                "SPH_RUNNER_FAULT=nan "
                "SPH_RUNNER_FAULT_MATCH=n_side=9")
                .code,
            0);
  auto r = run(dir, "report figs.toml --db r/db.sqlite --out rep");
  ASSERT_EQ(r.code, 0) << r.out;
  std::string page = read_file(dir / "rep" / "index.html");
  EXPECT_CONTAINS(page, "2 diverged");
  EXPECT_CONTAINS(page, "Marked (2 jobs)");
  // The diverged jobs have no value in the tables.
  EXPECT_EQ(count(page, "data-params="), 2u + 4u);
  EXPECT_CONTAINS(read_file(dir / "rep" / "all.gp"), "diverged (2 jobs)");
}

TEST(ReportE2E, WithoutGnuplotThePageStillHasTheTables) {
  TempDir dir;
  write_text(dir / "figs.toml", study("8, 9"));
  ASSERT_EQ(run(dir, "figs.toml -j 2 --db r/db.sqlite").code, 0);
  auto r = run(dir, "report figs.toml --db r/db.sqlite", "SPH_GNUPLOT=/nonexistent/gnuplot");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "gnuplot not found");
  std::string page = read_file(dir / "r" / "report" / "figs" / "index.html");
  EXPECT_CONTAINS(page, "gnuplot was not found");
  EXPECT_EQ(count(page, "<img"), 0u);
  EXPECT_EQ(count(page, "data-params="), 4u + 8u);
  EXPECT_TRUE(fs::exists(dir / "r" / "report" / "figs" / "all.gp")); // for whoever has gnuplot
}

TEST(ReportE2E, InvalidFiguresAreRejectedWithTheirLine) {
  TempDir dir;
  write_text(dir / "figs.toml", study("8, 9"));
  ASSERT_EQ(run(dir, "figs.toml -j 2 --db r/db.sqlite").code, 0);
  std::string bad = study("8, 9") + "\n[[figures]]\nname = \"oops\"\nx = \"nside\"\ny = \"err\"\n";
  write_text(dir / "figs.toml", bad);
  auto r = run(dir, "report figs.toml --db r/db.sqlite");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "figs.toml:36:");
  EXPECT_CONTAINS(r.out, "did you mean 'n_side'?");
  r = run(dir, "figs.toml --db r/db.sqlite");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "figs.toml:36:");
  // A study that was never run, or an unknown name.
  r = run(dir, "report nothing --db r/db.sqlite");
  EXPECT_EQ(r.code, 1);
  EXPECT_CONTAINS(r.out, "neither a study file nor a study");
}

// A series figure reads each job's HDF5 output (here written by the test into the jobs' output
// directories, as a time-dependent case would) and draws an analytic reference that uses a
// parameter of the job.
// Issue 16 part 5: a figure without data says why, in the words of its declaration.
TEST(ReportE2E, AFigureWithoutDataSaysWhy) {
  TempDir dir;
  write_text(dir / "figs.toml", study("10, 11"));
  ASSERT_EQ(run(dir, "figs.toml -j 2 --db r/db.sqlite").code, 0);
  auto r = run(dir, "report figs.toml --db r/db.sqlite --out page");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string page = read_file(dir / "page" / "index.html");
  // "small" keeps n_side 8 and 9, which this run does not have.
  EXPECT_CONTAINS(page, "No data: none of the 4 finished jobs has n_side = 8 or 9.");
}

// A reference whose expression uses a parameter that every group shares is one curve, not one per
// group (issue 16 part 5).
TEST(ReportE2E, AReferenceSharedByTheGroupsIsDrawnOnce) {
  TempDir dir;
  std::string toml = study("8, 9") + R"(
[[figures]]
name = "guide"
x = "n_side"
y = "err"
group = ["visc"]
[[figures.reference]]
label = "guide"
expr = "x^-2 * h_over_dx"
)";
  write_text(dir / "figs.toml", toml);
  ASSERT_EQ(run(dir, "figs.toml -j 2 --db r/db.sqlite").code, 0);
  auto r = run(dir, "report figs.toml --db r/db.sqlite --out page");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string gp = read_file(dir / "page" / "guide.gp");
  EXPECT_EQ(count(gp, "$r0 << EOD"), 1u) << gp;
  EXPECT_EQ(count(gp, "$r1 << EOD"), 0u) << gp;
  EXPECT_CONTAINS(gp, "title 'guide'");
}

TEST(ReportE2E, SeriesFiguresReadTheJobsHdf5Outputs) {
  TempDir dir;
  std::string text = R"toml([study]
name = "series"
case = "patch_test"
[sweep]
h_over_dx = [1.2, 1.5]

[[figures]]
name = "energy"
kind = "series"
file = "series.h5"
x = "time"
y = "energy"
group = ["h_over_dx"]
log_y = true
[[figures.reference]]
label = "exp(-h_over_dx t)"
expr = "exp(-h_over_dx * x)"
)toml";
  write_text(dir / "series.toml", text);
  ASSERT_EQ(run(dir, "series.toml -j 2 --db r/db.sqlite").code, 0);
  {
    Db db((dir / "r" / "db.sqlite").string(), SQLITE_OPEN_READWRITE);
    Stmt q = db.prepare("SELECT key, json_extract(params_json, '$.h_over_dx') FROM jobs");
    std::vector<std::pair<std::string, double>> jobs;
    while (q.step())
      jobs.emplace_back(q.text(0), q.real(1));
    ASSERT_EQ(jobs.size(), 2u);
    for (const auto& [key, h] : jobs) {
      fs::path out = dir / "r" / "series" / key;
      fs::create_directories(out);
      std::vector<double> t, e;
      for (int i = 0; i <= 20; ++i)
        t.push_back(0.1 * i), e.push_back(std::exp(-h * 0.1 * i));
      sph::io::H5Writer w(out / "series.h5");
      w.write("time", t);
      w.write("energy", e);
      w.close();
      Stmt u = db.prepare("UPDATE jobs SET output_dir=? WHERE key=?");
      u.bind(1, out.string()).bind(2, key);
      u.run();
    }
  }
  auto r = run(dir, "report series.toml --db r/db.sqlite --out rep");
  ASSERT_EQ(r.code, 0) << r.out;
  std::string page = read_file(dir / "rep" / "index.html");
  EXPECT_EQ(count(page, "<table class=\"series\""), 1u);
  EXPECT_EQ(count(page, "<td>energy</td><td>21</td>"), 2u);
  std::string gp = read_file(dir / "rep" / "energy.gp");
  EXPECT_CONTAINS(gp, "exp(-h_over_dx t) (h_over_dx=1.2)");
  EXPECT_CONTAINS(gp, "exp(-h_over_dx t) (h_over_dx=1.5)");
  EXPECT_CONTAINS(gp, "with lines");
  if (have_gnuplot())
    EXPECT_CONTAINS(read_file(dir / "rep" / "energy.svg"), "<svg");
}

// The runner records a job's folder relative to the directory it ran in (`--db r/db.sqlite`:
// r/<study>/<key>); a report made from another directory finds it through the database's own.
TEST(ReportE2E, SeriesFiguresFindRelativeJobFoldersFromAnotherDirectory) {
  TempDir dir;
  write_text(dir / "series.toml", R"toml([study]
name = "series"
case = "patch_test"
[sweep]
h_over_dx = [1.2, 1.5]

[[figures]]
name = "energy"
kind = "series"
file = "series.h5"
x = "time"
y = "energy"
group = ["h_over_dx"]
)toml");
  ASSERT_EQ(run(dir, "series.toml -j 2 --db r/db.sqlite").code, 0);
  {
    Db db((dir / "r" / "db.sqlite").string(), SQLITE_OPEN_READWRITE);
    Stmt q = db.prepare("SELECT key FROM jobs");
    std::vector<std::string> keys;
    while (q.step())
      keys.push_back(q.text(0));
    ASSERT_EQ(keys.size(), 2u);
    for (const auto& key : keys) {
      fs::create_directories(dir / "r" / "series" / key);
      sph::io::H5Writer w(dir / "r" / "series" / key / "series.h5");
      w.write("time", {0.0, 0.1, 0.2});
      w.write("energy", {1.0, 0.9, 0.8});
      w.close();
      Stmt u = db.prepare("UPDATE jobs SET output_dir=? WHERE key=?");
      u.bind(1, "r/series/" + key).bind(2, key); // as a run in dir records it
      u.run();
    }
  }
  fs::create_directories(dir / "elsewhere");
  const int status =
      std::system(("cd '" + (dir / "elsewhere").string() + "' && '" + runner_exe() +
                   "' report ../series.toml --db ../r/db.sqlite --out rep > " + "out.txt 2>&1")
                      .c_str());
  ASSERT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0)
      << read_file(dir / "elsewhere" / "out.txt");
  std::string page = read_file(dir / "elsewhere" / "rep" / "index.html");
  EXPECT_EQ(count(page, "<td>energy</td><td>3</td>"), 2u) << page;
}

// A study without [[figures]] still gets a page with figures: each metric its jobs recorded (the
// case declares none here) against the first swept parameter, one curve per value of the next.
TEST(ReportE2E, AStudyWithoutFiguresGetsEachMetricAgainstItsFirstAxis) {
  TempDir dir;
  write_text(dir / "bare.toml", "[study]\nname = \"bare\"\ncase = \"patch_test\"\n[params]\n"
                                "lattice = \"uniform\"\n[sweep]\nn_side = [8, 9]\n"
                                "visc = [\"visc01\", \"visc03\"]\n");
  ASSERT_EQ(run(dir, "bare.toml -j 2 --db r/db.sqlite").code, 0);
  auto r = run(dir, "report bare.toml --db r/db.sqlite --out rep");
  ASSERT_EQ(r.code, 0) << r.out;
  std::string page = read_file(dir / "rep" / "index.html");
  EXPECT_CONTAINS(page, "This study declares no figures: each metric against the first swept");
  EXPECT_CONTAINS(page, "err against n_side (default figure");
  EXPECT_TRUE(fs::exists(dir / "rep" / "default_err.gp"));
  EXPECT_CONTAINS(read_file(dir / "rep" / "default_err.gp"), "visc");
  if (have_gnuplot())
    EXPECT_TRUE(fs::exists(dir / "rep" / "default_err.svg") ||
                fs::exists(dir / "rep" / "default_err.png"));
}
