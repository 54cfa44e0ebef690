// Helpers shared by the runner tests: temporary directories, study parsing from text, substring
// assertions.
#pragma once

#include "diagnostics.hpp"
#include "study.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace sph::runner::test {

// A fresh directory under the system temp dir, removed at the end of the test.
class TempDir {
public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("sph_runner_test_" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& s) const { return path_ / s; }

private:
  std::filesystem::path path_;
};

inline void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

// The diagnostics text of a study that must fail to parse ("" if it parses).
inline std::string study_error(const std::string& toml) {
  try {
    parse_study(toml, "test.toml");
  } catch (const StudyError& e) {
    return e.what();
  }
  return "";
}

// The [sweep] of a patch_test study of 20,000 jobs (4 x 10 x 2 x 25 x 10).
inline const char* const sweep_20000_jobs = R"(
[sweep]
visc = ["visc01", "visc02", "visc03", "visc04"]
n_side = [8, 9, 10, 11, 12, 13, 14, 15, 16, 17]
lattice = ["uniform", "disordered"]
seed = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25]
disorder = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]
)";

#define EXPECT_CONTAINS(haystack, needle)                                                          \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos)                                 \
      << "expected to find: " << (needle) << "\nin: " << (haystack)

} // namespace sph::runner::test
