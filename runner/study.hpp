// A study file (TOML) parsed and validated against the case registry: the study's name and case,
// fixed parameters, sweep axes, zip groups, explicit cases, derived parameters, exclusions and
// tiers. Every item keeps the line it came from, so later errors (in expansion) can name it.
// See docs/runner.md for the file format.
#pragma once

#include "cases/case.hpp"
#include "expr.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sph::runner {

struct Assignment {
  std::string name;
  ParamValue value;
  int line = 0;
};

struct Axis {
  std::string name;
  std::vector<ParamValue> values;
  int line = 0;
};

// Lists of equal length that vary together.
struct ZipGroup {
  std::vector<Axis> axes;
  int line = 0;
  std::size_t length() const { return axes.empty() ? 0 : axes.front().values.size(); }
};

// One explicit extra job: overrides on top of [params].
struct ExplicitCase {
  std::vector<Assignment> overrides;
  int line = 0;
};

struct Derived {
  std::string name;
  Expr expr;
  int line = 0;
};

// Drops the jobs of the product whose values match every entry.
struct Exclude {
  std::vector<Assignment> match;
  int line = 0;
};

// Overrides for a shorter (or longer) run of the same study.
struct Tier {
  std::string name;
  std::string description;
  int line = 0;
  std::vector<Assignment> params; // merged over [params]; pins a parameter swept in the base
  std::vector<Axis> sweep;        // replaces axes of the same name, adds the others
  std::optional<std::vector<ZipGroup>> zip;       // replaces all [[zip]] groups
  std::optional<std::vector<ExplicitCase>> cases; // replaces all [[cases]]
  std::optional<std::vector<Exclude>> exclude;    // replaces [study] exclude
};

// [search]: the stability edge of one numeric parameter, by bisection between a value taken as
// stable (lo) and one taken as unstable (hi), for every job of the expansion (a group); each probe
// is an ordinary job. A probe is unstable when it diverges or a metric passes its bound.
struct Search {
  std::string param;
  double lo = 0, hi = 0;
  double until = 0.05; // stop when |b - a| <= until |a| for the bracket [a, b]
  bool log = false;    // bisect in log(value): geometric midpoints
  std::vector<std::pair<std::string, double>> unstable_above, unstable_below; // metric bounds
  int line = 0;
};

struct Study {
  std::string file; // as given (used in messages)
  std::string name;
  std::string case_name;
  std::string description;
  const CaseInfo* info = nullptr;
  std::vector<ParamSpec> specs; // the case's params (+ "scheme" when the case has schemes)
  int case_line = 0;

  std::vector<Assignment> params; // [params] and [study] scheme
  std::vector<Axis> sweep;        // in file order: the first axis varies slowest
  std::vector<ZipGroup> zip;
  std::vector<ExplicitCase> cases;
  std::vector<Derived> derived;
  std::vector<Exclude> exclude;
  std::vector<Tier> tiers;
  std::optional<Search> search;

  std::string definition_sha256; // of the file's bytes
  // Registering the study adds its jobs without retiring the others (`runner one`'s "adhoc").
  bool accumulate = false;

  const Tier* find_tier(const std::string& name) const;
  std::vector<std::string> tier_names() const;
};

// Limits on hostile or mistaken input: a study file's size, a study name's length (it names a
// directory: results/<name>/<64-character key>/...).
inline constexpr std::size_t max_study_file_bytes = 4u << 20;
inline constexpr std::size_t max_study_name = 200;

// The tier name under which a study's untiered expansion is recorded.
inline constexpr const char* full_tier = "full";

// Reads and validates a study file. Throws StudyError (with file:line diagnostics).
Study load_study(const std::filesystem::path& path);
// Same, from text; `file` labels the diagnostics.
Study parse_study(const std::string& text, const std::string& file);

} // namespace sph::runner
