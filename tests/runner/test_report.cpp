// Unit tests of `runner report`'s pieces: the [[figures]] schema (accepted forms and file:line
// errors, through the study parser), the least-squares fits, and the generated gnuplot script.
#include "helpers.hpp"
#include "report.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

const std::string head = R"([study]
name = "figs"
case = "patch_test"
[sweep]
visc = ["visc01", "visc03"]
n_side = [8, 9]
)";

std::vector<FigureSpec> figures_of(const std::string& text) {
  Study s = parse_study(text, "test.toml"); // validates the figures too
  return parse_figures_text(text, "test.toml", s.specs);
}

fs::path source_dir() {
  const char* s = std::getenv("SPH_SOURCE_DIR");
  return s ? fs::path(s) : fs::path(SPH_SOURCE_DIR_FALLBACK);
}

} // namespace

TEST(ReportFigures, ParsesAFullDeclaration) {
  auto figs = figures_of(head + R"(
[[figures]]
name = "conv"
title = "Convergence"
x = "n_side"
y = ["err", "err_l2"]
group = ["visc"]
where = { lattice = "uniform", seed = [1, 2] }
log_x = true
log_y = true
fit = "power"
fit_range = [8, 100]
agg = "median"
mark = ["diverged", "failed"]

[[figures.reference]]
label = "second order"
expr = "0.5 * x^-2"
citation = "analytic"

[[figures]]
name = "by_form"
x = "visc"
y = "err"
)");
  ASSERT_EQ(figs.size(), 2u);
  const auto& f = figs[0];
  EXPECT_EQ(f.name, "conv");
  EXPECT_EQ(f.x, "n_side");
  EXPECT_EQ(f.y, (std::vector<std::string>{"err", "err_l2"}));
  EXPECT_EQ(f.group, (std::vector<std::string>{"visc"}));
  ASSERT_EQ(f.where.size(), 2u);
  EXPECT_TRUE(f.log_x && f.log_y);
  EXPECT_EQ(f.fit, "power");
  ASSERT_TRUE(f.fit_range);
  EXPECT_EQ(f.fit_range->second, 100.0);
  EXPECT_EQ(f.agg, "median");
  EXPECT_EQ(f.mark.size(), 2u);
  ASSERT_EQ(f.references.size(), 1u);
  EXPECT_TRUE(f.references[0].expr);
  EXPECT_EQ(f.references[0].style, "line");
  EXPECT_TRUE(figs[1].x_is_string);
  EXPECT_EQ(figs[1].y, (std::vector<std::string>{"err"}));
}

TEST(ReportFigures, ErrorsNameTheLine) {
  std::string text = head + R"(
[[figures]]
name = "bad"
x = "n_sid"
y = "err"
group = ["visk"]
where = { lattice = "hexagonal" }
fitt = "power"
fit = "cubic"
)";
  std::string err = study_error(text);
  EXPECT_CONTAINS(err, "test.toml:10:");
  EXPECT_CONTAINS(err, "x: unknown parameter 'n_sid' (did you mean 'n_side'?)");
  EXPECT_CONTAINS(err, "test.toml:12:");
  EXPECT_CONTAINS(err, "group: unknown parameter 'visk'");
  EXPECT_CONTAINS(err, "test.toml:13:");
  EXPECT_CONTAINS(err, "where lattice:");
  EXPECT_CONTAINS(err, "test.toml:14:");
  EXPECT_CONTAINS(err, "unknown key 'fitt' (did you mean 'fit'?)");
  EXPECT_CONTAINS(err, "test.toml:15:");
  EXPECT_CONTAINS(err, "fit: \"cubic\" is not one of 'none', 'power', 'linear'");
}

TEST(ReportFigures, RejectsInconsistentDeclarations) {
  EXPECT_CONTAINS(study_error(head + "[[figures]]\nname = \"a\"\nx = \"n_side\"\n"),
                  "missing key 'y'");
  EXPECT_CONTAINS(study_error(head + "[[figures]]\nx = \"n_side\"\ny = \"err\"\n"),
                  "missing key 'name'");
  EXPECT_CONTAINS(study_error(head + "[[figures]]\nname = \"a\"\nx = \"visc\"\ny = \"err\"\n"
                                     "log_x = true\n"),
                  "cannot be on a log axis");
  EXPECT_CONTAINS(study_error(head + "[[figures]]\nname = \"a b\"\nx = \"n_side\"\ny = \"e\"\n"),
                  "must be letters, digits");
  EXPECT_CONTAINS(study_error(head + "[[figures]]\nname = \"a\"\nx = \"n_side\"\ny = \"e\"\n"
                                     "[[figures]]\nname = \"a\"\nx = \"n_side\"\ny = \"e\"\n"),
                  "is used by another figure");
  EXPECT_CONTAINS(study_error(head + "[[figures]]\nname = \"a\"\nx = \"n_side\"\ny = \"e\"\n"
                                     "group = \"n_side\"\n"),
                  "is already the x axis");
  EXPECT_CONTAINS(study_error(head + "[[figures]]\nname = \"a\"\nx = \"n_side\"\ny = \"e\"\n"
                                     "fit_range = [2, 1]\nfit = \"power\"\n"),
                  "fit_range: expected [low, high]");
  EXPECT_CONTAINS(study_error(head + "[[figures]]\nname = \"a\"\nkind = \"series\"\n"
                                     "x = \"time\"\ny = \"energy\"\n"),
                  "missing key 'file'");
  EXPECT_CONTAINS(study_error(head + "[[figures]]\nname = \"a\"\nx = \"n_side\"\ny = \"e\"\n"
                                     "mark = [\"exploded\"]\n"),
                  "mark: \"exploded\" is not one of");
  // References: an expression in x and numeric parameters, or a CSV with both columns.
  std::string fig = head + "[[figures]]\nname = \"a\"\nx = \"n_side\"\ny = \"e\"\n"
                           "[[figures.reference]]\n";
  EXPECT_CONTAINS(study_error(fig + "label = \"r\"\nexpr = \"x * q\"\n"), "unknown name 'q'");
  EXPECT_CONTAINS(study_error(fig + "label = \"r\"\nexpr = \"x * \"\n"), "expr:");
  EXPECT_EQ(study_error(fig + "label = \"r\"\nexpr = \"h_over_dx * x^-2\"\n"), "");
  EXPECT_CONTAINS(study_error(fig + "label = \"r\"\n"), "give either expr");
  EXPECT_CONTAINS(study_error(fig + "label = \"r\"\ncsv = \"nope.csv\"\nx = \"a\"\ny = \"b\"\n"),
                  "cannot read");
  EXPECT_CONTAINS(study_error(fig + "expr = \"x\"\n"), "missing key 'label'");
}

TEST(ReportFigures, CsvReferencesAreCheckedAgainstTheirColumns) {
  TempDir dir;
  write_text(dir / "ref.csv", "# Ghia, Ghia & Shin (1982), J. Comput. Phys. 48, 387\ny,u\n0,0\n"
                              "0.5,-0.06\n1,1\n");
  std::string fig = head + "[[figures]]\nname = \"a\"\nx = \"n_side\"\ny = \"e\"\n"
                           "[[figures.reference]]\nlabel = \"Ghia\"\ncsv = \"ref.csv\"\n";
  write_text(dir / "s.toml", fig + "x = \"y\"\ny = \"u\"\n");
  Study s = load_study(dir / "s.toml");
  auto figs = load_figures(dir / "s.toml", s.specs);
  ASSERT_EQ(figs.size(), 1u);
  ASSERT_EQ(figs[0].references.size(), 1u);
  EXPECT_EQ(figs[0].references[0].style, "points");
  auto t = read_reference_csv(figs[0].references[0].csv);
  ASSERT_EQ(t.rows.size(), 3u);
  EXPECT_DOUBLE_EQ(t.rows[1][1], -0.06);

  write_text(dir / "bad.toml", fig + "x = \"y\"\ny = \"v\"\n");
  try {
    load_study(dir / "bad.toml");
    FAIL() << "expected an error";
  } catch (const StudyError& e) {
    EXPECT_CONTAINS(e.what(), "has no column 'v'");
    EXPECT_CONTAINS(e.what(), "bad.toml:");
  }
}

TEST(ReportFigures, TheShippedStudiesDeclareValidFigures) {
  for (const char* name : {"visc_patch", "visc_patch_disorder", "visc_patch_h"}) {
    fs::path file = source_dir() / "studies" / (std::string(name) + ".toml");
    Study s = load_study(file);
    auto figs = load_figures(file, s.specs);
    EXPECT_FALSE(figs.empty()) << name;
  }
  fs::path vp = source_dir() / "studies" / "visc_patch.toml";
  auto figs = load_figures(vp, load_study(vp).specs);
  ASSERT_EQ(figs.size(), 3u);
  for (const auto& f : figs) {
    EXPECT_TRUE(f.log_x && f.log_y);
    if (f.convergence) { // the grid-convergence figure of err_l2 (kind = "convergence")
      EXPECT_EQ(f.name, "order_uniform");
      EXPECT_EQ(*f.convergence, "self");
      EXPECT_EQ(f.kind, "metric");
      EXPECT_EQ(f.y, (std::vector<std::string>{"err_l2"}));
      continue;
    }
    EXPECT_EQ(f.fit, "power");
    EXPECT_EQ(f.y, (std::vector<std::string>{"err", "err_l2"}));
  }
  // A convergence key on another kind, or two metrics in a convergence figure, are refused.
  const std::string base = "[[figures]]\nname = \"a\"\nx = \"n_side\"\n";
  for (const std::string bad : {base + "y = \"err\"\nconvergence = \"self\"\n",
                                base + "kind = \"convergence\"\ny = [\"err\", \"err_l2\"]\n",
                                base + "kind = \"convergence\"\ny = \"err\"\nconvergence = "
                                       "\"order\"\n"})
    EXPECT_THROW(parse_figures_text(bad, "f.toml", load_study(vp).specs), StudyError) << bad;
}

TEST(ReportFit, PowerLawRecoversTheExponent) {
  std::vector<double> x{20, 40, 60, 80, 100}, y;
  for (double v : x)
    y.push_back(3.5 * std::pow(v, -2.0));
  auto f = fit_points("power", x, y);
  ASSERT_TRUE(f);
  EXPECT_NEAR(f->slope, -2.0, 1e-12);
  EXPECT_NEAR(std::exp(f->intercept), 3.5, 1e-10);
  EXPECT_NEAR(f->r2, 1.0, 1e-12);
  EXPECT_EQ(f->n, 5u);
  EXPECT_NEAR(f->eval(50), 3.5 / 2500, 1e-15);
  // Non-positive values cannot be on log axes: skipped; one point left is no fit.
  EXPECT_FALSE(fit_points("power", {1, 2}, {1, -1}));
  EXPECT_FALSE(fit_points("power", {1, 1}, {1, 2}));
}

TEST(ReportFit, LinearFit) {
  auto f = fit_points("linear", {0, 1, 2, 3}, {1, 3, 5, 7.0});
  ASSERT_TRUE(f);
  EXPECT_NEAR(f->slope, 2.0, 1e-12);
  EXPECT_NEAR(f->intercept, 1.0, 1e-12);
  // Noisy data: R^2 below one, still the least-squares line.
  auto g = fit_points("linear", {0, 1, 2, 3}, {0, 1.2, 1.8, 3.1});
  ASSERT_TRUE(g);
  EXPECT_LT(g->r2, 1.0);
  EXPECT_NEAR(g->slope, 0.99, 1e-12);
}

TEST(ReportScript, HoldsTheDataAndTheAxes) {
  FigureSpec f;
  f.name = "conv";
  f.x = "n_side";
  f.y = {"err"};
  f.log_x = f.log_y = true;
  f.fit = "power";
  FigureData d;
  d.spec = &f;
  Curve c;
  c.label = "visc=visc01";
  c.points = {{20, 0.01, 0.009, 0.011, 2}, {40, 0.0025, 0.0025, 0.0025, 1}};
  c.fit = fit_points("power", {20, 40}, {0.01, 0.0025});
  d.curves.push_back(c);
  d.markers.push_back({60, 0, "diverged"});
  std::string s = gnuplot_script(d, "conv.svg", "svg");
  EXPECT_CONTAINS(s, "set terminal svg");
  EXPECT_CONTAINS(s, "set output 'conv.svg'");
  EXPECT_CONTAINS(s, "set logscale x 10");
  EXPECT_CONTAINS(s, "set logscale y 10");
  EXPECT_CONTAINS(s, "20 0.01 0.0089999999999999993 0.010999999999999999");
  EXPECT_CONTAINS(s, "yerrorbars");
  EXPECT_CONTAINS(s, "visc=visc01, slope -2");
  EXPECT_CONTAINS(s, "diverged (1 jobs)");
  // Same data, same script: the hash that decides redrawing is stable.
  EXPECT_EQ(s, gnuplot_script(d, "conv.svg", "svg"));
  FigureData empty;
  empty.spec = &f;
  EXPECT_EQ(gnuplot_script(empty, "conv.svg", "svg"), "");
}
