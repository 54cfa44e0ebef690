// Browser test of `runner report`: runs the quick tier of studies/visc_patch.toml, renders its
// report, opens the page in headless Chromium with tests/browser/check_report.js attached, and
// checks what the browser saw: the page loads, every image loads (naturalWidth > 0), and every
// number in the figures' tables equals the database's (compared with `runner query`).
// Also checks `runner status` and `runner table` on that database. The browser part is skipped,
// with a message, only when chromium or gnuplot is not installed.
#include "helpers.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <sys/wait.h>

using namespace sph::runner::test;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int sh(const std::string& cmd) {
  int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

fs::path source_dir() {
  const char* s = std::getenv("SPH_SOURCE_DIR");
  return s ? fs::path(s) : fs::path(SPH_SOURCE_DIR_FALLBACK);
}

std::string unescape(std::string s) {
  for (auto [from, to] : {std::pair<std::string, std::string>{"&lt;", "<"},
                          {"&gt;", ">"},
                          {"&quot;", "\""},
                          {"&nbsp;", " "},
                          {"&amp;", "&"}}) {
    for (auto p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
      s.replace(p, from.size(), to);
  }
  return s;
}

// Minimal CSV (as printed by `runner query`: no embedded commas in these columns).
std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream ls(line);
    while (std::getline(ls, cell, ','))
      cells.push_back(cell);
    if (!line.empty() && line.back() == ',')
      cells.push_back("");
    rows.push_back(cells);
  }
  return rows;
}

} // namespace

TEST(ReportBrowser, QuickTierPageLoadsWithItsImagesAndTheDatabaseNumbers) {
  TempDir dir;
  const fs::path study = source_dir() / "studies" / "visc_patch.toml";
  const std::string runner = RUNNER_EXE;
  const std::string db = (dir / "results.sqlite").string();
  ASSERT_EQ(sh("'" + runner + "' '" + study.string() + "' --tier quick -j 2 --db '" + db + "' > '" +
               (dir / "run.txt").string() + "' 2>&1"),
            0)
      << read_file(dir / "run.txt");
  // The default study's status and pivot (issue 7: "runner status and runner table work on the
  // default study").
  ASSERT_EQ(sh("'" + runner + "' status visc_patch --db '" + db + "' > '" +
               (dir / "status.txt").string() + "' 2>&1"),
            0);
  EXPECT_NE(
      read_file(dir / "status.txt").find("visc_patch               quick         24        0"),
      std::string::npos)
      << read_file(dir / "status.txt");
  ASSERT_EQ(sh("'" + runner +
               "' table visc_patch --rows n_side --cols visc --value err --where "
               "lattice=uniform --format csv --db '" +
               db + "' > '" + (dir / "table.txt").string() + "' 2>&1"),
            0)
      << read_file(dir / "table.txt");
  const std::string table = read_file(dir / "table.txt");
  EXPECT_EQ(table.substr(0, table.find('\n')), "n_side \\ visc,visc01,visc02,visc03,visc04");
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 3); // header, N = 20, N = 40

  const fs::path out = dir / "report";
  ASSERT_EQ(sh("'" + runner + "' report '" + study.string() + "' --db '" + db + "' --out '" +
               out.string() + "' > '" + (dir / "report.txt").string() + "' 2>&1"),
            0)
      << read_file(dir / "report.txt");

  if (sh("command -v chromium > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "chromium is not installed (Debian package chromium): browser check skipped";
  if (sh("command -v gnuplot > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "gnuplot is not installed (Debian package gnuplot-nox): browser check skipped";

  // The page as shipped plus the check script (kept out of the product's page).
  std::string page = read_file(out / "index.html");
  auto body_end = page.rfind("</body>");
  ASSERT_NE(body_end, std::string::npos);
  page.insert(body_end, "<script src=\"check_report.js\"></script>\n");
  write_text(out / "check.html", page);
  fs::copy_file(source_dir() / "tests" / "browser" / "check_report.js", out / "check_report.js");

  const fs::path profile = dir / "chromium-profile";
  fs::create_directories(profile);
  const fs::path dom = dir / "dom.html";
  std::string cmd = "timeout 120 chromium --headless --no-sandbox --disable-gpu --no-first-run "
                    "--disable-background-networking --disable-component-update --disable-sync "
                    "--user-data-dir='" +
                    profile.string() + "' --virtual-time-budget=10000 --dump-dom 'file://" +
                    fs::absolute(out / "check.html").string() + "' > '" + dom.string() + "' 2> '" +
                    (dir / "chromium.txt").string() + "'";
  ASSERT_EQ(sh(cmd), 0) << read_file(dir / "chromium.txt");
  std::string text = read_file(dom);
  const std::string open = "<pre id=\"report-check\">";
  auto a = text.find(open);
  ASSERT_NE(a, std::string::npos) << "the check script did not run; DOM:\n"
                                  << text.substr(0, 2000) << "\nchromium:\n"
                                  << read_file(dir / "chromium.txt");
  auto b = text.find("</pre>", a);
  json check = json::parse(unescape(text.substr(a + open.size(), b - a - open.size())));

  EXPECT_EQ(check["title"], "visc_patch report");
  EXPECT_EQ(check["sections"], 3); // err_uniform, order_uniform (convergence), err_disordered
  EXPECT_TRUE(check["notices"].empty()) << check["notices"].dump();
  ASSERT_EQ(check["images"].size(), 3u);
  for (const auto& img : check["images"]) {
    EXPECT_TRUE(img["complete"].get<bool>()) << img.dump();
    EXPECT_GT(img["width"].get<int>(), 0) << img.dump();
    EXPECT_GT(img["height"].get<int>(), 0) << img.dump();
  }

  // The database's numbers, through `runner query`: mean over seeds per lattice, form, N, metric.
  const fs::path q = dir / "query.csv";
  ASSERT_EQ(sh("'" + runner + "' query --db '" + db +
               "' \"SELECT json_extract(params, '$.lattice'), json_extract(params, '$.visc'), "
               "json_extract(params, '$.n_side'), metric, avg(value), count(value) FROM "
               "job_metrics WHERE study = 'visc_patch' AND status = 'done' AND metric IN "
               "('err', 'err_l2') GROUP BY 1, 2, 3, 4\" > '" +
               q.string() + "'"),
            0);
  auto rows = csv_rows(read_file(q));
  ASSERT_GT(rows.size(), 1u);
  std::map<std::string, std::pair<double, int>> expected;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), 6u);
    expected[rows[i][0] + "|" + rows[i][1] + "|" + rows[i][2] + "|" + rows[i][3]] = {
        std::stod(rows[i][4]), std::stoi(rows[i][5])};
  }
  // quick tier: 4 forms x 2 N x 2 lattices x 2 metrics
  EXPECT_EQ(expected.size(), 32u);
  // The convergence figure order_uniform repeats the uniform lattice's err_l2 cells (4 forms x 2
  // N).
  ASSERT_EQ(check["cells"].size(), expected.size() + 8u);
  std::size_t compared = 0;
  for (const auto& c : check["cells"]) {
    const auto& p = c["params"];
    std::string k = p["lattice"].get<std::string>() + "|" + p["visc"].get<std::string>() + "|" +
                    std::to_string(p["n_side"].get<int>()) + "|" + c["metric"].get<std::string>();
    auto it = expected.find(k);
    ASSERT_NE(it, expected.end()) << k;
    double shown = std::stod(c["value"].get<std::string>());
    EXPECT_NEAR(shown, it->second.first, 1e-12 * std::abs(it->second.first)) << k;
    EXPECT_EQ(c["n"].get<int>(), it->second.second) << k;
    // The visible text is the same number, rounded to 4 significant digits.
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", shown);
    EXPECT_EQ(c["text"].get<std::string>(), buf) << k;
    ++compared;
  }
  EXPECT_EQ(compared, 40u);
}
