// Job-spec and result files: round trips, non-finite metrics, atomic writes.
#include "helpers.hpp"
#include "job_file.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sph::runner;
using namespace sph::runner::test;

TEST(JobFile, SpecRoundTripTypesParamsByTheCase) {
  JobFileSpec s;
  s.key = "abc";
  s.case_name = "patch_test";
  s.params = {
      {"n_side", std::int64_t{12}}, {"disorder", 1.0}, {"kernel", std::string("wendland_c2")}};
  s.threads = 2;
  s.attempt = 3;
  s.output_dir = "/tmp/x";
  JobFileSpec back = spec_from_json(spec_to_json(s));
  EXPECT_EQ(back.key, "abc");
  EXPECT_EQ(back.threads, 2);
  EXPECT_EQ(back.attempt, 3);
  EXPECT_EQ(std::get<std::int64_t>(back.params.at("n_side")), 12);
  EXPECT_EQ(std::get<double>(back.params.at("disorder")), 1.0);
  EXPECT_EQ(std::get<std::string>(back.params.at("kernel")), "wendland_c2");
  EXPECT_TRUE(back.params.count("h_over_dx")); // defaults filled in
  s.params["bogus"] = 1.0;
  EXPECT_THROW(spec_from_json(spec_to_json(s)), std::invalid_argument);
}

TEST(JobFile, ResultRoundTripKeepsNonFiniteValues) {
  JobFileResult r{"k", "diverged", {{"a", 1.5}, {"b", std::nan("")}, {"c", -HUGE_VAL}}, "blew up"};
  JobFileResult back = result_from_json(result_to_json(r));
  EXPECT_EQ(back.status, "diverged");
  ASSERT_EQ(back.metrics.size(), 3u);
  EXPECT_EQ(back.metrics[0].second, 1.5);
  EXPECT_TRUE(std::isnan(back.metrics[1].second));
  EXPECT_TRUE(std::isinf(back.metrics[2].second));
  EXPECT_EQ(back.message, "blew up");
  EXPECT_THROW(result_from_json("{\"format\":\"other\"}"), std::invalid_argument);
}

TEST(JobFile, AtomicWriteLeavesNoTemporary) {
  TempDir dir;
  write_result_file(dir / "r.json", {"k", "done", {{"err", 0.1}}, ""});
  EXPECT_TRUE(std::filesystem::exists(dir / "r.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "r.json.tmp"));
  auto r = read_result_file(dir / "r.json");
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->metrics.at(0).first, "err");
  EXPECT_FALSE(read_result_file(dir / "none.json").has_value());
}
