// Streamed expansion (issue 17 item 4): the jobs of a study one at a time give exactly the keys,
// in exactly the order, that the vector expansion gave before it streamed (the digests below were
// computed by the code before the change, at 8e015d1), with the same counts of combinations,
// exclusions and duplicates: a study registered by an earlier runner is recognised job for job.
#include "expand.hpp"
#include "helpers.hpp"
#include "job_key.hpp"

#include <gtest/gtest.h>

#include <map>

using namespace sph::runner;
using namespace sph::runner::test;

namespace {

// Studies with a zip group, exclusions, explicit cases, duplicates (a repeated value, 1 and 1.0,
// a case equal to a product job), derived values, tiers and schemes.
const std::map<std::string, std::string> inline_studies = {
    {"zip_exclude_cases", R"([study]
name = "a"
case = "patch_test"
exclude = [ { lattice = "uniform", seed = 2 } ]
[params]
kernel = "wendland_c2"
[sweep]
lattice = ["uniform", "disordered"]
seed = [1, 2, 3, 1]
[[zip]]
n_side = [8, 12, 16]
h_over_dx = [1.2, 1.3, 1.5]
[[cases]]
n_side = 30
[[cases]]
lattice = "disordered"
seed = 3
n_side = 12
h_over_dx = 1.3
[tiers.quick]
sweep = { seed = [7] }
cases = [ { n_side = 9 }, { n_side = 9 } ]
)"},
    {"reals_and_derived", R"([study]
name = "b"
case = "patch_test"
[sweep]
disorder = [1, 1.0, 0.5, 0.25]
n_side = [10, 20, 40]
[derived]
h_over_dx = "1 + n_side / 40"
eta_over_h = "h_over_dx / 100"
)"},
    {"twenty_thousand",
     std::string("[study]\nname = \"d\"\ncase = \"patch_test\"\n") + sweep_20000_jobs},
    // studies/tvf_tgv.toml as of 8e015d1 (without its figures): a scheme, cases, a tier.
    {"tvf_tgv", R"toml([study]
name = "tvf_tgv"
case = "taylor_green"
scheme = "wcsph_tvf"
description = "Taylor-Green Re = 100: TVF none/original/smoothing_length/limited x n_side (seed 002, section 4.1)"

[params]
Re = 100
t_end = 5.0
riemann_dissipation = "none"
kernel = "wendland_c2"
h_over_dx = 1.3
perturb = 0.3
seed = 1

[sweep]
tvf = ["none", "original", "smoothing_length", "limited"]
n_side = [50, 100, 200]

[[cases]]
n_side = 100
perturb = 0.0
tvf = "none"

[[cases]]
n_side = 100
perturb = 0.0
tvf = "original"

[[cases]]
n_side = 100
perturb = 0.0
tvf = "smoothing_length"

[[cases]]
n_side = 100
perturb = 0.0
tvf = "limited"

[[cases]]
n_side = 100
tvf = "original"
pb_factor = 0.25

[[cases]]
n_side = 100
kernel_correction = true
tvf = "none"

[[cases]]
n_side = 100
kernel_correction = true
tvf = "original"

[[cases]]
n_side = 100
kernel_correction = true
tvf = "smoothing_length"

[[cases]]
n_side = 100
kernel_correction = true
tvf = "limited"

[tiers.quick]
params = { t_end = 1.0 }
sweep = { n_side = [20] }
cases = []
)toml"},
    {"schemes", R"([study]
name = "c"
case = "cavity_cylinder"
[params]
t_end = 0.5
[sweep]
scheme = ["isph", "wcsph_tvf"]
dx = [0.05, 0.025]
[[cases]]
scheme = "wcsph_tvf"
dx = 0.05
[[cases]]
scheme = "isph"
dx = 0.02
)"},
};

// What identifies an expansion: its keys in order and its counts.
std::string digest(const std::vector<std::string>& keys, std::size_t combinations,
                   std::size_t excluded, std::size_t duplicates) {
  std::string text;
  for (const auto& k : keys)
    text += k + "\n";
  text += std::to_string(combinations) + "/" + std::to_string(excluded) + "/" +
          std::to_string(duplicates);
  return std::to_string(keys.size()) + " " + sha256_hex(text).substr(0, 16);
}

// Every study to check, by "name[tier]".
std::map<std::string, std::pair<Study, std::string>> studies_to_check() {
  std::map<std::string, std::pair<Study, std::string>> out;
  for (const auto& [name, text] : inline_studies) {
    Study s = parse_study(text, name + ".toml");
    out.emplace(name, std::pair{s, std::string()});
    for (const auto& t : s.tier_names())
      out.emplace(name + "[" + t + "]", std::pair{s, t});
  }
  return out;
}

} // namespace

TEST(ExpandStream, KeysAndOrderAreThoseOfTheVectorExpansionBeforeStreaming) {
  // Digests of the expansion computed by the code before streaming (8e015d1): count, then the
  // SHA-256 of the keys in order and of the counts of combinations, exclusions, duplicates.
  const std::map<std::string, std::string> before = {
      {"reals_and_derived", "9 3aca843266164134"},
      {"schemes", "5 aa6f1eb7861a7c52"},
      {"tvf_tgv", "21 c9bee36621cd7de8"},
      {"tvf_tgv[quick]", "4 d27a9dd321415c00"},
      {"twenty_thousand", "20000 01a02b183be0e6ad"},
      {"zip_exclude_cases", "16 f4184c2968dc8048"},
      {"zip_exclude_cases[quick]", "7 cd6a4149a8651e75"},
  };
  const auto studies = studies_to_check();
  ASSERT_EQ(studies.size(), before.size());
  for (const auto& [name, st] : studies) {
    const auto& [study, tier] = st;
    auto it = before.find(name);
    ASSERT_TRUE(it != before.end()) << name;
    // The stream, job by job.
    std::vector<std::string> keys;
    JobStream jobs(study, tier);
    JobSpec job;
    while (jobs.next(job))
      keys.push_back(job.key);
    const ExpansionSummary& sum = jobs.summary();
    EXPECT_EQ(sum.size, keys.size()) << name;
    EXPECT_EQ(digest(keys, sum.combinations, sum.excluded, sum.duplicates), it->second) << name;
    // The vector expand() collects: the same jobs, counts and varying parameters.
    Expansion ex = expand(study, tier);
    ASSERT_EQ(ex.jobs.size(), keys.size()) << name;
    for (std::size_t i = 0; i < keys.size(); ++i)
      ASSERT_EQ(ex.jobs[i].key, keys[i]) << name << " job " << i;
    EXPECT_EQ(ex.varying, sum.varying) << name;
  }
}

TEST(ExpandStream, DuplicatesAndExclusionsAreCountedAsBefore) {
  // zip_exclude_cases: 2 lattices x 4 seeds (seed 1 twice) x 3 zip points = 24 combinations, 3
  // excluded (uniform, seed 2), 6 duplicates (seed 1 again) and a case equal to a product job.
  const Study study = parse_study(inline_studies.at("zip_exclude_cases"), "z.toml");
  JobStream jobs(study);
  JobSpec job;
  std::size_t n = 0;
  while (jobs.next(job))
    ++n;
  EXPECT_EQ(n, 16u);
  EXPECT_EQ(jobs.summary().combinations, 24u);
  EXPECT_EQ(jobs.summary().excluded, 3u);
  EXPECT_EQ(jobs.summary().duplicates, 7u);
  EXPECT_EQ(jobs.summary().varying,
            (std::vector<std::string>{"n_side", "lattice", "seed", "h_over_dx"})); // spec order
}
