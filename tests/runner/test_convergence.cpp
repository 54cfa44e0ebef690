// Grid-convergence verification (runner/convergence.hpp, `runner converge`): the observed order,
// the Richardson-extrapolated value and Roache's GCI on manufactured sequences of known order,
// then the command on the patch test's uniform lattice (VISC-03/04 are second order in dx there).
#include "commands.hpp"
#include "convergence.hpp"
#include "e2e_helpers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

using namespace sph::runner;
using namespace sph::runner::test;

namespace {

std::vector<GridValue> manufactured(double f0, double c, double p, std::vector<double> hs) {
  std::vector<GridValue> g;
  for (double h : hs)
    g.push_back({h, f0 + c * std::pow(h, p)});
  return g;
}

} // namespace

TEST(Convergence, ConstantRatioGivesOrderExtrapolationAndGci) {
  // f = 1 + 0.5 h^2 at h = 0.1, 0.05, 0.025, listed coarse first (the order is not assumed).
  const Convergence r = self_convergence(manufactured(1.0, 0.5, 2.0, {0.1, 0.05, 0.025}));
  ASSERT_TRUE(r.p && r.f_ext && r.gci_fine);
  EXPECT_NEAR(*r.p, 2.0, 1e-10);
  EXPECT_NEAR(*r.f_ext, 1.0, 1e-12);
  const double f1 = 1.0 + 0.5 * 0.025 * 0.025, f2 = 1.0 + 0.5 * 0.05 * 0.05;
  EXPECT_DOUBLE_EQ(r.safety, 1.25);
  EXPECT_NEAR(*r.gci_fine, 1.25 * std::abs((f1 - f2) / f1) / 3.0, 1e-14);
  EXPECT_FALSE(r.oscillatory);
}

TEST(Convergence, UnequalRatiosAreIteratedToTheTrueOrder) {
  // The patch test's counts 60, 80, 100 (ratios 1.333 and 1.25) with f = 3 - 2 h^1.5: the
  // one-step estimate ln(e32/e21)/ln(r21) is off by the ratio mismatch; the iteration is not.
  auto g = manufactured(3.0, -2.0, 1.5, {1.0 / 60, 1.0 / 80, 1.0 / 100});
  const Convergence r = self_convergence(g);
  ASSERT_TRUE(r.p && r.f_ext);
  EXPECT_NEAR(*r.p, 1.5, 1e-9);
  EXPECT_NEAR(*r.f_ext, 3.0, 1e-11);
  const double naive = std::log((g[1].f - g[0].f) / (g[2].f - g[1].f)) / std::log(100.0 / 80.0);
  EXPECT_GT(std::abs(naive - 1.5), 0.05); // so the case does test the iteration
  // Only the three finest count: a wrong coarse grid changes nothing.
  g.push_back({1.0 / 20, 1e3});
  EXPECT_NEAR(*self_convergence(g).p, 1.5, 1e-9);
}

TEST(Convergence, DifferencesThatGrowUnderRefinementGiveNoOrder) {
  // C_D of three cylinder runs: 1.611, 1.604, 1.538 at D/dx = 10, 20, 30: the last change is the
  // largest. |ln|e32/e21|| would make this p = 5.3; it is no convergence at all.
  const Convergence r = self_convergence({{0.1, 1.611}, {0.05, 1.604}, {1.0 / 30, 1.538}});
  EXPECT_FALSE(r.p.has_value());
  EXPECT_NE(r.note.find("not converging"), std::string::npos) << r.note;
  // The same with equal ratios: f = 1 + h^-0.5 grows as h falls.
  EXPECT_FALSE(self_convergence(manufactured(1.0, 1.0, -0.5, {0.4, 0.2, 0.1})).p.has_value());
}

TEST(Convergence, AnOrderOutsideTheAsymptoticRangeIsFlagged) {
  // A big step from the coarsest grid and almost none after: p = 18, a GCI of 0.003 %.
  const Convergence r = self_convergence({{0.1, 1.611}, {0.05, 1.540}, {1.0 / 30, 1.538}});
  ASSERT_TRUE(r.p);
  EXPECT_GT(*r.p, 4.0);
  EXPECT_NE(r.note.find("not in the asymptotic range"), std::string::npos) << r.note;
  // With a formal order of 2 the ceiling is 4; a clean second-order sequence is not flagged.
  EXPECT_EQ(self_convergence(manufactured(1.0, 0.5, 2.0, {0.1, 0.05, 0.025})).note, "");
}

TEST(Convergence, OscillatoryAndTwoGridCasesAreSaid) {
  const Convergence osc = self_convergence({{0.1, 1.2}, {0.05, 0.9}, {0.025, 1.05}});
  EXPECT_TRUE(osc.oscillatory);
  EXPECT_NE(osc.note.find("oscillatory"), std::string::npos);
  // Two grids: no observed order unless a formal one is given; then Fs = 3.
  const auto two = manufactured(2.0, 1.0, 2.0, {0.1, 0.05});
  EXPECT_FALSE(self_convergence(two).p.has_value());
  const Convergence f = self_convergence(two, 2.0);
  ASSERT_TRUE(f.gci_fine && f.f_ext);
  EXPECT_DOUBLE_EQ(f.safety, 3.0);
  EXPECT_NEAR(*f.f_ext, 2.0, 1e-12);
  const double f1 = 2.0 + 0.0025, f2 = 2.0 + 0.01;
  EXPECT_NEAR(*f.gci_fine, 3.0 * (f2 - f1) / f1 / 3.0, 1e-14);
  EXPECT_THROW(self_convergence({{0.1, 1.0}}), std::invalid_argument);
  EXPECT_THROW(self_convergence({{0.1, 1.0}, {0.1, 2.0}}), std::invalid_argument);
}

TEST(Convergence, ErrorOrderFromFinestPairAndFit) {
  const Convergence e = error_convergence(manufactured(0.0, 0.7, 2.0, {0.08, 0.04, 0.02, 0.01}));
  ASSERT_TRUE(e.p && e.p_fit);
  EXPECT_NEAR(*e.p, 2.0, 1e-12);
  EXPECT_NEAR(*e.p_fit, 2.0, 1e-12);
  // A coarse outlier moves the fit, not the finest pair.
  const Convergence o =
      error_convergence({{0.08, 1.0}, {0.04, 0.7 * 0.0016}, {0.02, 0.7 * 0.0004}});
  EXPECT_NEAR(*o.p, 2.0, 1e-12);
  EXPECT_GT(std::abs(*o.p_fit - 2.0), 0.5);
}

// `runner converge` on the patch test: uniform lattice, err_l2 (seed 001 eq. 21's L2 variant)
// at n_side = 40, 60, 80: VISC-03 and VISC-04 are exact on quadratics, so their error is the
// O(dx^2) truncation of the quartic test function: an observed order within 0.05 of 2.
TEST(Convergence, CommandGivesSecondOrderForVisc03And04OnTheUniformPatch) {
  TempDir dir;
  write_text(dir / "p.toml", R"([study]
name = "conv"
case = "patch_test"
[params]
kernel = "cubic_spline"
h_over_dx = 1.2
lattice = "uniform"
[sweep]
visc = ["visc03", "visc04"]
n_side = [40, 60, 80]

[[figures]]
name = "order"
kind = "convergence"
x = "n_side"
y = "err_l2"
group = ["visc"]
where = { lattice = "uniform" }
)");
  ASSERT_EQ(run_runner(dir, "p.toml -j 1").code, 0);
  const CmdResult r = run_runner(
      dir, "converge conv --param n_side --value err_l2 --where lattice=uniform --format csv");
  ASSERT_EQ(r.code, 0) << r.out;
  std::istringstream in(r.out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "group,resolutions,n_side finest,err_l2 finest,p,extrapolated,GCI_fine %,note");
  int rows = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> f = csv_split(line);
    ASSERT_EQ(f.size(), 8u) << line;
    EXPECT_TRUE(f[0] == "visc=visc03" || f[0] == "visc=visc04") << f[0];
    EXPECT_EQ(f[1], "40 60 80");
    EXPECT_NEAR(std::stod(f[4]), 2.0, 0.05) << line;
    EXPECT_LT(std::abs(std::stod(f[5])), 0.2 * std::stod(f[3])) << line; // extrapolates to ~0
    EXPECT_GT(std::stod(f[6]), 0.0) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 2);
  // The report's convergence figure holds the same table (the same jobs, the same numbers).
  const CmdResult rep = run_runner(dir, "report p.toml --out rep");
  ASSERT_EQ(rep.code, 0) << rep.out;
  const std::string page = read_file(dir / "rep" / "index.html");
  const auto table_at = page.find("<table class=\"convergence\" data-figure=\"order\">");
  ASSERT_NE(table_at, std::string::npos) << page;
  const std::string table = page.substr(table_at, page.find("</table>", table_at) - table_at);
  std::istringstream again(r.out);
  std::getline(again, line);
  while (std::getline(again, line)) {
    const std::vector<std::string> f = csv_split(line);
    std::string cells = "<tr>";
    for (std::size_t k = 0; k < f.size(); ++k)
      cells +=
          std::string(k < 2 || k + 1 == f.size() ? "<td>" : "<td class=\"num\">") + f[k] + "</td>";
    EXPECT_NE(table.find(cells + "</tr>"), std::string::npos) << cells << "\n" << table;
  }
  // The error kind on the same rows: the finest pair's order.
  const CmdResult e = run_runner(dir, "converge conv --param n_side --value err_l2 --kind error");
  ASSERT_EQ(e.code, 0) << e.out;
  EXPECT_NE(e.out.find("visc=visc03"), std::string::npos) << e.out;
  // Bad names are refused with a suggestion.
  const CmdResult bad = run_runner(dir, "converge conv --param nside --value err_l2");
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.out.find("n_side"), std::string::npos) << bad.out;
}

// From a published record (docs/results/STUDY.csv): rows of one study and metric; a parameter that
// differs between resolutions (here the run length) splits the sequence unless --ignore'd.
TEST(Convergence, PublishedRecordAndIgnoredParameter) {
  TempDir dir;
  std::string csv = "study,job,tier,code_version,params,metric,value\n";
  const double hs[] = {0.04, 0.02, 0.01};
  for (int k = 0; k < 3; ++k) {
    const double f = 1.5 + 0.8 * hs[k] * hs[k];
    char params[200];
    std::snprintf(params, sizeof params, R"({""dx"":%g,""t_end"":%d,""form"":""a""})", hs[k],
                  k == 2 ? 200 : 100);
    csv +=
        "s,job" + std::to_string(k) + ",full,v,\"" + params + "\",cd," + std::to_string(f) + "\n";
    csv += "s,job" + std::to_string(k) + ",full,v,\"" + params + "\",other,1\n";
  }
  // Another form at the finest spacing with the shorter run: t_end is then not a function of dx
  // (which alone would not split a sequence) but a parameter of its own.
  csv += "s,job3,full,v,\"{\"\"dx\"\":0.01,\"\"t_end\"\":100,\"\"form\"\":\"\"b\"\"}\",cd,2\n";
  csv += "t,jobx,full,v,\"{\"\"dx\"\":0.5}\",cd,9\n"; // another study: not read
  write_text(dir / "s.csv", csv);
  const CmdResult split = run_runner(dir, "converge s --published s.csv --param dx --value cd");
  ASSERT_EQ(split.code, 0) << split.out;
  EXPECT_NE(split.out.find("one resolution"), std::string::npos) << split.out;
  const CmdResult one = run_runner(
      dir, "converge s --published s.csv --param dx --value cd --ignore t_end --format csv");
  ASSERT_EQ(one.code, 0) << one.out;
  std::istringstream in(one.out);
  std::string line;
  std::getline(in, line);
  ASSERT_TRUE(std::getline(in, line)) << one.out;
  std::vector<std::string> f = csv_split(line);
  EXPECT_EQ(f[0], "form=a");
  ASSERT_EQ(f.size(), 8u) << line;
  EXPECT_EQ(f[1], "0.01 0.02 0.04");
  EXPECT_NEAR(std::stod(f[4]), 2.0, 1e-3) << line;
  EXPECT_NEAR(std::stod(f[5]), 1.5, 1e-5) << line;
  ASSERT_TRUE(std::getline(in, line)) << one.out; // form b: one resolution
  f = csv_split(line);
  EXPECT_EQ(f[0], "form=b");
  EXPECT_EQ(f[7], "one resolution");
  EXPECT_FALSE(std::getline(in, line)) << one.out;
  // A metric or parameter the record does not have is named.
  const CmdResult bad = run_runner(dir, "converge s --published s.csv --param dx --value cdd");
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.out.find("did you mean 'cd'"), std::string::npos) << bad.out;
}
