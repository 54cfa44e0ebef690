// Bad input: malformed study files and command lines. Each must fail with a clear error naming
// what is wrong and where (file:line, option, parameter), and leave existing results untouched
// (the database files' bytes are compared before and after).
#include "e2e_helpers.hpp"

#include <gtest/gtest.h>

using namespace sph::runner;
using namespace sph::runner::test;
namespace fs = std::filesystem;

namespace {

const char* good = R"([study]
name = "good"
case = "patch_test"
[params]
kernel = "cubic_spline"
[sweep]
n_side = [8, 9]
)";

struct Bad {
  std::string what;                // description of the mistake
  std::string study;               // study file text ("" : no file written, args only)
  std::string args;                // command line after `runner`; {f} is the study file
  std::vector<std::string> expect; // substrings of the error output
  int code = 2;
};

std::string study(const std::string& body) {
  return "[study]\nname = \"bad\"\ncase = \"patch_test\"\n" + body;
}

} // namespace

TEST(BadInput, EachMistakeIsNamedAndResultsStayIntact) {
  TempDir dir;
  write_text(dir / "good.toml", good);
  ASSERT_EQ(run_runner(dir, "good.toml").code, 0);
  fs::path db = dir / "results" / "results.sqlite";
  auto snapshot = [&] { return read_file(db) + "|" + read_file(db.string() + "-wal"); };
  const std::string before = snapshot();

  // Databases to misuse: one with a newer schema, one that is garbage, one that is not ours.
  fs::create_directories(dir / "other");
  {
    Db d((dir / "other" / "newer.sqlite").string(), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
    d.exec("CREATE TABLE x(y); PRAGMA user_version=99");
  }
  write_text(dir / "other" / "corrupt.sqlite", std::string(4096, 'x') + "garbage");
  {
    Db d((dir / "other" / "foreign.sqlite").string(), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
    d.exec("CREATE TABLE customers(name)");
  }
  // A runner database with an overwritten page (a torn write, a bad disk block), and one cut in
  // half (a copy that did not finish).
  ASSERT_EQ(run_runner(dir, "good.toml --db other/damaged.sqlite").code, 0);
  {
    Db d((dir / "other" / "damaged.sqlite").string(), SQLITE_OPEN_READWRITE);
    d.exec("PRAGMA wal_checkpoint(TRUNCATE); PRAGMA journal_mode=DELETE");
  }
  fs::copy_file(dir / "other" / "damaged.sqlite", dir / "other" / "truncated.sqlite");
  {
    std::string bytes = read_file(dir / "other" / "damaged.sqlite");
    ASSERT_GT(bytes.size(), 5u * 4096u);
    for (std::size_t i = 3 * 4096; i < 4 * 4096; ++i)
      bytes[i] = static_cast<char>(0xde);
    write_text(dir / "other" / "damaged.sqlite", bytes);
    std::string whole = read_file(dir / "other" / "truncated.sqlite");
    write_text(dir / "other" / "truncated.sqlite", whole.substr(0, whole.size() / 2));
  }
  write_text(dir / "afile", "not a directory");
  const std::string newer_before = read_file(dir / "other" / "newer.sqlite");
  const std::string corrupt_before = read_file(dir / "other" / "corrupt.sqlite");
  const std::string foreign_before = read_file(dir / "other" / "foreign.sqlite");
  const std::string damaged_before = read_file(dir / "other" / "damaged.sqlite");
  const std::string truncated_before = read_file(dir / "other" / "truncated.sqlite");

  const std::vector<Bad> cases = {
      // TOML syntax
      {"unclosed table header", "[study\nname = \"x\"\n", "{f}", {"{f}:1:", "error"}},
      {"unterminated string", study("[params]\nkernel = \"cubic\n"), "{f}", {"{f}:5:"}},
      {"duplicate key", study("[params]\nn_side = 8\nn_side = 9\n"), "{f}", {"{f}:6:"}},
      {"missing value", study("[params]\nn_side =\n"), "{f}", {"{f}:5:"}},
      // unknown names, with suggestions
      {"unknown table",
       study("[sweeps]\nn_side = [8]\n"),
       "{f}",
       {"{f}:4", "did you mean 'sweep'"}},
      {"unknown study key",
       study("descripton = \"x\"\n"),
       "{f}",
       {"{f}:4", "did you mean 'description'"}},
      {"unknown parameter",
       study("[params]\nkernal = \"cubic_spline\"\n"),
       "{f}",
       {"{f}:5", "did you mean 'kernel'"}},
      {"unknown swept parameter",
       study("[sweep]\nn_sdie = [8, 9]\n"),
       "{f}",
       {"{f}:5", "did you mean 'n_side'"}},
      {"unknown case",
       "[study]\nname = \"bad\"\ncase = \"patch_tset\"\n",
       "{f}",
       {"{f}:3", "did you mean 'patch_test'"}},
      {"unknown scheme",
       "[study]\nname = \"bad\"\ncase = \"lid_driven_cavity\"\nscheme = \"ipsh\"\n",
       "{f}",
       {"{f}:4", "ipsh", "isph"}},
      {"scheme for a case without schemes",
       study("scheme = \"isph\"\n"),
       "{f}",
       {"{f}:4", "scheme"}},
      {"unknown tier key",
       study("[tiers.quick]\nsweeps = { n_side = [8] }\n"),
       "{f}",
       {"{f}:5", "sweeps"}},
      {"exclude names an unknown parameter",
       study("exclude = [ { n_sdie = 8 } ]\n"),
       "{f}",
       {"{f}:4", "n_sdie"}},
      // wrong types
      {"string for an integer",
       study("[params]\nn_side = \"20\"\n"),
       "{f}",
       {"{f}:5", "n_side", "expected an integer"}},
      {"real for an integer",
       study("[sweep]\nn_side = [8, 1.5]\n"),
       "{f}",
       {"{f}:5", "n_side[1]", "expected an integer"}},
      {"bool for an integer", study("[params]\nn_side = true\n"), "{f}", {"{f}:5", "n_side"}},
      {"number for a string", study("[params]\nvisc = 3\n"), "{f}", {"{f}:5", "visc"}},
      {"choice not allowed",
       study("[params]\nlattice = \"hexagonal\"\n"),
       "{f}",
       {"{f}:5", "lattice", "uniform"}},
      {"name is not a string",
       "[study]\nname = 3\ncase = \"patch_test\"\n",
       "{f}",
       {"{f}:2", "name"}},
      // out of range (patch_test has no dx or dt: its resolution is n_side and h_over_dx)
      {"zero resolution", study("[params]\nn_side = 0\n"), "{f}", {"{f}:5", "n_side"}},
      {"negative resolution", study("[sweep]\nn_side = [8, -5]\n"), "{f}", {"{f}:5", "n_side"}},
      {"zero smoothing length", study("[params]\nh_over_dx = 0\n"), "{f}", {"{f}:5", "h_over_dx"}},
      {"negative smoothing length",
       study("[params]\nh_over_dx = -1.2\n"),
       "{f}",
       {"{f}:5", "h_over_dx"}},
      {"zero time step",
       "[study]\nname = \"bad\"\ncase = \"checkpoint_demo\"\n[params]\ndt = 0\n",
       "{f}",
       {"{f}:5", "dt"}},
      {"negative time step",
       "[study]\nname = \"bad\"\ncase = \"checkpoint_demo\"\n[sweep]\ndt = [0.1, -0.1]\n",
       "{f}",
       {"{f}:5", "dt"}},
      // sweep structure
      {"empty sweep axis", study("[sweep]\nn_side = []\n"), "{f}", {"{f}:5", "n_side", "empty"}},
      {"scalar sweep axis", study("[sweep]\nn_side = 8\n"), "{f}", {"{f}:5", "n_side"}},
      {"zip lengths differ",
       study("[[zip]]\nn_side = [8, 9]\nh_over_dx = [1.2]\n"),
       "{f}",
       {"{f}:", "n_side", "h_over_dx"}},
      {"fixed and swept",
       study("[params]\nn_side = 8\n[sweep]\nn_side = [8, 9]\n"),
       "{f}",
       {"{f}:7", "line 5", "n_side"}},
      {"bad derived expression",
       study("[derived]\nh_over_dx = \"1.2 * \"\n"),
       "{f}",
       {"{f}:5", "h_over_dx"}},
      {"derived cycle",
       study("[derived]\nh_over_dx = \"disorder\"\ndisorder = \"h_over_dx\"\n"),
       "{f}",
       {"{f}:", "circular"}},
      {"missing case", "[study]\nname = \"bad\"\n", "{f}", {"{f}", "case"}},
      {"bad study name",
       "[study]\nname = \"a b\"\ncase = \"patch_test\"\n",
       "{f}",
       {"{f}:2", "name"}},
      // command lines
      {"no such study file", "", "nothere.toml", {"nothere.toml"}},
      {"unknown tier", "", "good.toml --tier quik", {"quik"}},
      {"negative job count", "", "good.toml --jobs -1", {"--jobs"}, 105},
      {"non-numeric timeout", "", "good.toml --timeout soon", {"--timeout"}, 105},
      {"unknown option with suggestion", "", "good.toml --retry-faild", {"--retry-faild"}, 109},
      {"unwritable database path",
       "",
       "good.toml --db afile/results.sqlite",
       {"afile", "cannot create directory"},
       1},
      {"database with a newer schema",
       "",
       "good.toml --db other/newer.sqlite",
       {"other/newer.sqlite", "schema version 99", "newer"},
       1},
      {"corrupted database file",
       "",
       "good.toml --db other/corrupt.sqlite",
       {"other/corrupt.sqlite", "not a database"},
       1},
      {"database with an overwritten page",
       "",
       "good.toml --db other/damaged.sqlite",
       {"other/damaged.sqlite", "is damaged", "nothing was written", ".recover"},
       1},
      {"truncated database",
       "",
       "good.toml --db other/truncated.sqlite",
       {"other/truncated.sqlite", "is damaged", "malformed"},
       1},
      {"database path is a directory",
       "",
       "good.toml --db other",
       {"'other' is a directory", "other/results.sqlite"},
       1},
      {"someone else's database",
       "",
       "good.toml --db other/foreign.sqlite",
       {"other/foreign.sqlite", "not a runner database"},
       1},
      {"status of a corrupted database",
       "",
       "status --db other/corrupt.sqlite",
       {"other/corrupt.sqlite", "not a database"},
       1},
      {"status of an unknown study", "", "status goood", {"goood", "did you mean 'good'"}, 1},
      {"table of an unknown metric",
       "",
       "table good --rows n_side --cols visc --value er",
       {"'er'", "did you mean 'err'"},
       1},
      {"table with a malformed filter",
       "",
       "table good --rows n_side --cols visc --value err --where lattice",
       {"--where 'lattice'", "KEY=VALUE"},
       1},
      {"table filter on an unknown parameter",
       "",
       "table good --rows n_side --cols visc --value err --where latice=uniform",
       {"latice", "did you mean 'lattice'"},
       1},
      {"table with an unknown format",
       "",
       "table good --rows n_side --cols visc --value err --format xlsx",
       {"--format", "markdown"},
       1},
      {"query with an SQL error", "", "query \"SELEC 1\"", {"SQL error", "SELEC"}, 1},
      {"export in an unknown format", "", "export good --format xml", {"--format"}, 1},
  };
  ASSERT_GE(cases.size(), 30u);
  int n = 0;
  for (const auto& c : cases) {
    SCOPED_TRACE(c.what);
    std::string file = "bad" + std::to_string(n++) + ".toml";
    if (!c.study.empty())
      write_text(dir / file, c.study);
    auto replace = [&](std::string s) {
      for (auto p = s.find("{f}"); p != std::string::npos; p = s.find("{f}"))
        s.replace(p, 3, file);
      return s;
    };
    auto r = run_runner(dir, replace(c.args));
    EXPECT_EQ(r.code, c.code) << r.out;
    for (const auto& e : c.expect)
      EXPECT_CONTAINS(r.out, replace(e));
    EXPECT_EQ(r.out.find("Segmentation"), std::string::npos);
    EXPECT_TRUE(snapshot() == before) << "the database changed";
  }
  EXPECT_TRUE(read_file(dir / "other" / "newer.sqlite") == newer_before);
  EXPECT_TRUE(read_file(dir / "other" / "corrupt.sqlite") == corrupt_before);
  EXPECT_TRUE(read_file(dir / "other" / "foreign.sqlite") == foreign_before);
  EXPECT_TRUE(read_file(dir / "other" / "damaged.sqlite") == damaged_before);
  EXPECT_TRUE(read_file(dir / "other" / "truncated.sqlite") == truncated_before);
  EXPECT_FALSE(fs::exists(dir / "other" / "damaged.sqlite-wal"));
  EXPECT_EQ(sql_int(db, "SELECT count(*) FROM jobs WHERE state='done'"), 2);
  std::cout << "[ bad input ] " << cases.size() << " malformed studies and command lines\n";
}
