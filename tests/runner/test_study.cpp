// Study validation: every class of error is reported with file:line and what was expected.
#include "expand.hpp"
#include "helpers.hpp"

#include <gtest/gtest.h>

using namespace sph::runner;
using namespace sph::runner::test;

namespace {
// Lines 1-2 are empty; [study] is on line 3, name on 4, case on 5: a table appended starts on 6.
const std::string head = R"(

[study]
name = "t"
case = "patch_test"
)";
} // namespace

TEST(StudyParse, ValidStudyKeepsFileOrderOfAxes) {
  Study s = parse_study(head + R"(
[params]
kernel = "cubic_spline"
[sweep]
visc = ["visc01", "visc02"]
n_side = [8, 12]
lattice = ["uniform", "disordered"]
)",
                        "ok.toml");
  ASSERT_EQ(s.sweep.size(), 3u);
  EXPECT_EQ(s.sweep[0].name, "visc");
  EXPECT_EQ(s.sweep[1].name, "n_side");
  EXPECT_EQ(s.sweep[2].name, "lattice");
  EXPECT_EQ(s.sweep[1].line, 11);
  EXPECT_EQ(s.definition_sha256.size(), 64u);
}

TEST(StudyErrors, TomlSyntaxErrorHasLineAndColumn) {
  auto e = study_error(head + "[params]\nn_side = = 3\n");
  EXPECT_CONTAINS(e, "test.toml:7:");
  EXPECT_CONTAINS(e, "TOML syntax error");
}

TEST(StudyErrors, UnknownTopLevelTableAndKey) {
  auto e = study_error(head + "[sweeps]\nn_side = [8]\n");
  EXPECT_CONTAINS(e, "test.toml:6");
  EXPECT_CONTAINS(e, "[sweeps]");
  EXPECT_CONTAINS(e, "did you mean 'sweep'");
  e = study_error(head + "descripton = \"x\"\n");
  EXPECT_CONTAINS(e, "test.toml:6");
  EXPECT_CONTAINS(e, "[study] unknown key 'descripton'");
  EXPECT_CONTAINS(e, "did you mean 'description'");
}

TEST(StudyErrors, MissingStudyTableAndKeys) {
  EXPECT_CONTAINS(study_error("[params]\nn_side = 8\n"), "missing [study]");
  EXPECT_CONTAINS(study_error("[study]\nname = \"x\"\n"), "missing key 'case'");
}

TEST(StudyErrors, UnknownCaseListsKnownOnes) {
  auto e = study_error("[study]\nname = \"t\"\ncase = \"patch_tset\"\n");
  EXPECT_CONTAINS(e, "test.toml:3");
  EXPECT_CONTAINS(e, "unknown case \"patch_tset\"");
  EXPECT_CONTAINS(e, "did you mean 'patch_test'");
  EXPECT_CONTAINS(e, "known cases: 'cantilever', 'cavity_cylinder', "); // listed by name
  EXPECT_CONTAINS(e, "'patch_test'");
}

TEST(StudyErrors, SchemeForACaseWithoutSchemes) {
  auto e = study_error("[study]\nname = \"t\"\ncase = \"patch_test\"\nscheme = \"isph\"\n");
  EXPECT_CONTAINS(e, "test.toml:4");
  EXPECT_CONTAINS(e, "takes no scheme");
}

TEST(StudyErrors, UnknownParameterWithSuggestion) {
  auto e = study_error(head + "[params]\nkernal = \"cubic_spline\"\n");
  EXPECT_CONTAINS(e, "test.toml:7");
  EXPECT_CONTAINS(e, "[params] kernal: unknown parameter");
  EXPECT_CONTAINS(e, "did you mean 'kernel'");
  e = study_error(head + "[sweep]\nnside = [8, 12]\n");
  EXPECT_CONTAINS(e, "test.toml:7");
  EXPECT_CONTAINS(e, "did you mean 'n_side'");
}

TEST(StudyErrors, WrongTypes) {
  // An Int rejects 1.5; a Real accepts an integer; Bool and String are strict.
  auto e = study_error(head + "[sweep]\nn_side = [8,\n  1.5]\n");
  EXPECT_CONTAINS(e, "test.toml:8");
  EXPECT_CONTAINS(e, "n_side[1]: expected an integer, got 1.5");
  EXPECT_EQ(study_error(head + "[params]\nh_over_dx = 2\n"), "");
  e = study_error(head + "[params]\nkernel = 3\n");
  EXPECT_CONTAINS(e, "test.toml:7");
  EXPECT_CONTAINS(e, "expected a string, got 3");
  e = study_error(head + "[params]\nn_side = \"12\"\n");
  EXPECT_CONTAINS(e, "expected an integer, got \"12\"");
  e = study_error(head + "[params]\nn_side = [8, 12]\n");
  EXPECT_CONTAINS(e, "put lists under [sweep]");
}

TEST(StudyErrors, OutOfRangeAndChoices) {
  auto e = study_error(head + "[params]\nn_side = 2\n");
  EXPECT_CONTAINS(e, "test.toml:7");
  EXPECT_CONTAINS(e, "2 is out of range: expected [4,");
  e = study_error(head + "[sweep]\ndisorder = [0.5, 1.5]\n");
  EXPECT_CONTAINS(e, "disorder[1]: 1.5 is out of range");
  e = study_error(head + "[params]\nvisc = \"visc05\"\n");
  EXPECT_CONTAINS(e, "test.toml:7");
  EXPECT_CONTAINS(e, "\"visc05\" is not one of 'visc01', 'visc02', 'visc03', 'visc04'");
}

TEST(StudyErrors, EmptyAxisAndScalarAxis) {
  auto e = study_error(head + "[sweep]\nn_side = []\n");
  EXPECT_CONTAINS(e, "test.toml:7");
  EXPECT_CONTAINS(e, "empty list");
  e = study_error(head + "[sweep]\nn_side = 8\n");
  EXPECT_CONTAINS(e, "expected a list of values");
}

TEST(StudyErrors, ZipLengthMismatchNamesLines) {
  auto e = study_error(head + "[[zip]]\nn_side = [8, 12, 16]\nh_over_dx = [1.2, 1.5]\n");
  EXPECT_CONTAINS(e, "test.toml:6");
  EXPECT_CONTAINS(e, "same length");
  EXPECT_CONTAINS(e, "n_side has 3 (line 7)");
  EXPECT_CONTAINS(e, "h_over_dx has 2 (line 8)");
}

TEST(StudyErrors, ParameterBothFixedAndSwept) {
  auto e = study_error(head + "[params]\nn_side = 8\n[sweep]\nn_side = [8, 12]\n");
  EXPECT_CONTAINS(e, "test.toml:9");
  EXPECT_CONTAINS(e, "'n_side' is set in [sweep] and also in [params] (line 7)");
}

TEST(StudyErrors, DerivedExpressionErrors) {
  auto e = study_error(head + "[derived]\nh_over_dx = \"1.2 * n_sid\"\n");
  EXPECT_CONTAINS(e, "test.toml:7");
  EXPECT_CONTAINS(e, "unknown name 'n_sid'");
  EXPECT_CONTAINS(e, "did you mean 'n_side'");
  e = study_error(head + "[derived]\nh_over_dx = \"1.2 *\"\n");
  EXPECT_CONTAINS(e, "test.toml:7");
  EXPECT_CONTAINS(e, "unexpected end of expression");
  e = study_error(head + "[derived]\nkernel = \"1\"\n");
  EXPECT_CONTAINS(e, "only numeric parameters can be derived");
  e = study_error(head + "[derived]\nh_over_dx = \"kernel * 2\"\n");
  EXPECT_CONTAINS(e, "'kernel' is a string");
}

TEST(StudyErrors, UnknownTierKeyAndReservedName) {
  auto e = study_error(head + "[tiers.quick]\nsweeps = { n_side = [8] }\n");
  EXPECT_CONTAINS(e, "test.toml:7");
  EXPECT_CONTAINS(e, "[tiers.quick]: unknown key 'sweeps'");
  e = study_error(head + "[tiers.full]\nsweep = { n_side = [8] }\n");
  EXPECT_CONTAINS(e, "reserved");
}

TEST(StudyErrors, BadStudyName) {
  auto e = study_error("[study]\nname = \"../x\"\ncase = \"patch_test\"\n");
  EXPECT_CONTAINS(e, "test.toml:2");
  EXPECT_CONTAINS(e, "results directory");
}

TEST(StudyErrors, SeveralErrorsAreReportedTogether) {
  auto e = study_error(head + "[params]\nkernal = \"x\"\nn_side = 1.5\n");
  EXPECT_CONTAINS(e, "test.toml:7");
  EXPECT_CONTAINS(e, "test.toml:8");
}

TEST(StudyErrors, UnreadableFile) {
  TempDir dir;
  try {
    load_study(dir / "missing.toml");
    FAIL();
  } catch (const StudyError& e) {
    EXPECT_CONTAINS(e.what(), "missing.toml: error: cannot read study file");
  }
  try {
    load_study(dir.path());
    FAIL();
  } catch (const StudyError& e) {
    EXPECT_CONTAINS(e.what(), "directory");
  }
}

TEST(StudyErrors, UnknownTierAtExpansion) {
  Study s = parse_study(head + "[tiers.quick]\nsweep = { n_side = [8] }\n", "t.toml");
  try {
    expand(s, "quik");
    FAIL();
  } catch (const StudyError& e) {
    EXPECT_CONTAINS(e.what(), "no tier named 'quik'");
    EXPECT_CONTAINS(e.what(), "did you mean 'quick'");
  }
}

TEST(StudyErrors, RealStudiesOfTheRepositoryParse) {
  const char* src = std::getenv("SPH_SOURCE_DIR");
  if (!src)
    GTEST_SKIP() << "SPH_SOURCE_DIR not set";
  for (const auto& e :
       std::filesystem::directory_iterator(std::filesystem::path(src) / "studies")) {
    if (e.path().extension() != ".toml")
      continue;
    SCOPED_TRACE(e.path().string());
    std::ifstream in(e.path());
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.find("\"patch_test\"") == std::string::npos)
      continue; // other cases may be in flux
    Study s;
    ASSERT_NO_THROW(s = load_study(e.path()));
    EXPECT_NO_THROW(expand(s));
    for (const auto& t : s.tiers)
      EXPECT_NO_THROW(expand(s, t.name));
  }
}
