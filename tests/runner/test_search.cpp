// Stability-edge search ([search], runner/search.hpp): the bisection on a known edge, its end
// states, the study-file checks, and a search through the binary that resumes after an
// interruption without re-running a finished probe.
#include "e2e_helpers.hpp"
#include "search.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <regex>
#include <thread>

using namespace sph::runner;
using namespace sph::runner::test;

namespace {

// Bisects a known edge: stable below `edge`, unstable at and above; returns the final bracket.
Bracket bisect(const Search& s, double edge, std::vector<Probe>& probes) {
  for (int i = 0; i < 100; ++i) {
    Bracket b = bracket_of(s, probes);
    if (!b.next)
      return b;
    probes.push_back({*b.next, *b.next < edge ? Verdict::stable : Verdict::unstable});
  }
  ADD_FAILURE() << "no end after 100 probes";
  return {};
}

Search search(double lo, double hi, double until, bool log) {
  Search s;
  s.param = "dt";
  s.lo = lo, s.hi = hi, s.until = until, s.log = log;
  return s;
}

} // namespace

TEST(Search, BisectionBracketsAKnownEdgeWithinUntil) {
  for (bool log : {false, true})
    for (double edge : {0.0123, 0.037, 0.0991}) {
      std::vector<Probe> probes;
      const Search s = search(0.001, 0.2, 0.05, log);
      const Bracket b = bisect(s, edge, probes);
      ASSERT_TRUE(b.a && b.b) << b.state;
      EXPECT_EQ(b.state, "bracketed");
      EXPECT_LT(*b.a, edge);
      EXPECT_GE(*b.b, edge);
      EXPECT_LE(*b.b - *b.a, 0.05 * *b.a);
      // lo and hi, then halving: log2(span / final width) + 2 probes at most (+1 for rounding).
      const double span = log ? std::log(200.0) : 0.199, width = log ? std::log(1.05) : 0.05 * *b.a;
      EXPECT_LE(static_cast<double>(probes.size()), std::ceil(std::log2(span / width)) + 3)
          << "log " << log << " edge " << edge;
      EXPECT_FALSE(b.non_monotone);
    }
}

TEST(Search, EndStatesAreSaid) {
  const Search s = search(0.01, 0.1, 0.05, true);
  // Nothing yet: lo first, then hi.
  EXPECT_DOUBLE_EQ(*bracket_of(s, {}).next, 0.01);
  EXPECT_DOUBLE_EQ(*bracket_of(s, {{0.01, Verdict::stable}}).next, 0.1);
  // lo unstable, hi stable, a failed probe: finished, with the reason.
  Bracket b = bracket_of(s, {{0.01, Verdict::unstable}});
  EXPECT_FALSE(b.next);
  EXPECT_NE(b.state.find("unstable at lo"), std::string::npos);
  b = bracket_of(s, {{0.01, Verdict::stable}, {0.1, Verdict::stable}});
  EXPECT_FALSE(b.next);
  EXPECT_NE(b.state.find("stable at hi"), std::string::npos);
  b = bracket_of(s, {{0.01, Verdict::stable}, {0.1, Verdict::unstable}, {0.0316, Verdict::failed}});
  EXPECT_FALSE(b.next);
  EXPECT_NE(b.state.find("failed"), std::string::npos);
  // The midpoint on a log scale is geometric; a stable probe beyond an unstable one is flagged.
  b = bracket_of(s, {{0.01, Verdict::stable}, {0.1, Verdict::unstable}});
  EXPECT_NEAR(*b.next, std::sqrt(0.001), 1e-15);
  b = bracket_of(s, {{0.01, Verdict::stable},
                     {0.1, Verdict::unstable},
                     {0.02, Verdict::unstable},
                     {0.05, Verdict::stable}});
  EXPECT_TRUE(b.non_monotone);
  EXPECT_DOUBLE_EQ(*b.b, 0.02);
  EXPECT_DOUBLE_EQ(*b.a, 0.01);
}

TEST(Search, StudyFileErrorsNameTheLine) {
  const std::string head = R"([study]
name = "s"
case = "cylinder_channel"
scheme = "alsph"
[sweep]
dt_star = [0.01, 0.02]
)";
  try {
    parse_study(head + "[search]\nparam = \"dt_star\"\nlo = 0.01\nhi = 0.1\n", "s.toml");
    ADD_FAILURE() << "a swept searched parameter was accepted";
  } catch (const StudyError& e) {
    EXPECT_NE(std::string(e.what()).find("s.toml:7"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[sweep]"), std::string::npos) << e.what();
  }
  const std::string ok = R"([study]
name = "s"
case = "cylinder_channel"
scheme = "alsph"
[search]
)";
  for (const std::string& bad :
       {std::string("param = \"dt_stra\"\nlo = 0.01\nhi = 0.1\n"),
        std::string("param = \"dt_star\"\nlo = 0.01\n"),
        std::string("param = \"dt_star\"\nlo = 0.01\nhi = 0.1\nuntil = 2\n"),
        std::string("param = \"dt_star\"\nlo = -1\nhi = 0.1\nscale = \"log\"\n"),
        std::string("param = \"dt_star\"\nlo = 0.01\nhi = 0.1\nuntill = 0.1\n")})
    EXPECT_THROW(parse_study(ok + bad, "s.toml"), StudyError) << bad;
  EXPECT_NO_THROW(parse_study(ok + "param = \"dt_star\"\nlo = 0.01\nhi = 0.1\nscale = \"log\"\n"
                                   "unstable_above = { cd_mean = 10.0 }\n",
                              "s.toml"));
}

// Through the binary: the ALSPH channel of the alsph_dt quick tier (D/dx = 6, 0.5 D/U), the edge of
// dt U/dx between 0.0254 (stable there) and 2.0 (diverges in a few steps). Interrupted after its
// first probes, the search resumes: every job ends with exactly one finished attempt.
TEST(Search, ResumesWithoutRerunningAFinishedProbe) {
  TempDir dir;
  write_text(dir / "edge.toml", R"([study]
name = "edge"
case = "cylinder_channel"
scheme = "alsph"
[params]
Re = 200
max_iterations = 5
t_end = 0.5
ramp_time = 0.0
channel_length = 6.0
channel_height = 4.0
upstream_length = 2.0
D_over_dx = 6
[sweep]
algorithm = [1, 2]
[search]
param = "dt_star"
lo = 0.0254
hi = 2.0
until = 0.25
scale = "log"
)");
  const auto db = dir / "results" / "results.sqlite";
  pid_t pid = spawn_runner(dir.path(), {"edge.toml", "-j", "2", "--progress", "plain"}, {},
                           dir / "first.log");
  // Stop it once some probes have finished (or let it end if it is that fast).
  for (int i = 0; i < 600; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (std::filesystem::exists(db) &&
        sql_int(db, "SELECT count(*) FROM jobs WHERE state IN ('done','diverged')") >= 3)
      break;
  }
  ::kill(pid, SIGINT);
  wait_exit(pid);
  const std::int64_t finished_before =
      sql_int(db, "SELECT count(*) FROM jobs WHERE state IN ('done','diverged')");
  ASSERT_GE(finished_before, 2);
  const CmdResult r = run_runner(dir, "edge.toml -j 2 --progress plain");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("edge_lo"), std::string::npos) << r.out;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state NOT IN ('done','diverged')"), 0);
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM (SELECT job_id FROM attempts WHERE state IN "
                        "('done','diverged') GROUP BY job_id HAVING count(*) > 1)"),
            0);
  // Each group ends bracketed: its widest finished bracket is within `until`.
  for (int alg : {1, 2}) {
    const std::string g = "json_extract(params_json,'$.algorithm')=" + std::to_string(alg);
    const double a = std::stod(sql_text(
        db,
        "SELECT max(json_extract(params_json,'$.dt_star')) FROM jobs WHERE state='done' AND " + g));
    const double b = std::stod(sql_text(db, "SELECT min(json_extract(params_json,'$.dt_star')) "
                                            "FROM jobs WHERE state='diverged' AND " +
                                                g));
    EXPECT_LT(a, b);
    EXPECT_LE(b - a, 0.25 * a) << "algorithm " << alg;
  }
  // The report shows each group's bracket, the same as the database's probes give.
  const CmdResult rep = run_runner(dir, "report edge.toml --out rep");
  ASSERT_EQ(rep.code, 0) << rep.out;
  const std::string page = read_file(dir / "rep" / "index.html");
  ASSERT_NE(page.find("Stability edge of dt_star"), std::string::npos) << page;
  for (int alg : {1, 2}) {
    const std::string g = "json_extract(params_json,'$.algorithm')=" + std::to_string(alg);
    const std::string a = sql_text(
        db,
        "SELECT max(json_extract(params_json,'$.dt_star')) FROM jobs WHERE state='done' AND " + g);
    const std::string b = sql_text(db, "SELECT min(json_extract(params_json,'$.dt_star')) FROM "
                                       "jobs WHERE state='diverged' AND " +
                                           g);
    const std::string row = "<tr><td>algorithm=" + std::to_string(alg) + "</td>";
    const auto at = page.find(row);
    ASSERT_NE(at, std::string::npos) << row << "\n" << page;
    const std::string line = page.substr(at, page.find("</tr>", at) - at);
    // Its numeric cells: probes, edge_lo, edge_hi.
    std::vector<double> num;
    const std::regex cell("<td class=\"num\">([^<]*)</td>");
    for (std::sregex_iterator m(line.begin(), line.end(), cell), end; m != end; ++m)
      num.push_back(std::stod((*m)[1]));
    ASSERT_EQ(num.size(), 3u) << line;
    EXPECT_NEAR(num[1], std::stod(a), 1e-12 * std::stod(a)) << line;
    EXPECT_NEAR(num[2], std::stod(b), 1e-12 * std::stod(b)) << line;
    EXPECT_NE(line.find("bracketed"), std::string::npos) << line;
  }
  // A second run finds nothing to do.
  const std::int64_t attempts = sql_int(db, "SELECT count(*) FROM attempts");
  const CmdResult again = run_runner(dir, "edge.toml");
  EXPECT_EQ(again.code, 0) << again.out;
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM attempts"), attempts);
  EXPECT_NE(again.out.find("bracketed"), std::string::npos) << again.out;
}
