// Stability-edge search ([search] in a study file): for every job of the study's expansion (a
// group: one combination of the other parameters) the runner bisects the searched parameter
// between `lo` (taken as stable) and `hi` (taken as unstable) until the bracket [a, b] (a the
// largest stable value below the smallest unstable one, b) has |b - a| <= until |a|.
//
// Each probe is an ordinary job of the study (its own key; reused, resumable, queryable): stable
// when it ends `done` and passes the metric bounds, unstable when it ends `diverged` or passes a
// bound. Round by round the next probe of every unfinished group is run, so the probes of one group
// run one after another and the groups of a round in parallel. The next probe depends only on the
// recorded ones, so an interrupted search resumes where it stopped.
#pragma once

#include "executor.hpp"
#include "study.hpp"

#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace sph::runner {

class Store;

// One probe's verdict.
enum class Verdict { stable, unstable, failed };

struct Probe {
  double value = 0;
  Verdict verdict = Verdict::failed;
};

// The bracket of one group from its probes.
struct Bracket {
  std::optional<double> a, b; // largest stable below the smallest unstable; smallest unstable
  std::optional<double> next; // the next value to probe (none: finished)
  std::string state;          // "searching", "bracketed", "stable at hi", "unstable at lo", ...
  bool non_monotone = false;  // a stable probe beyond an unstable one
  std::size_t probes = 0;
};

// Pure: the bracket and the next probe from a group's recorded probes.
Bracket bracket_of(const Search& s, const std::vector<Probe>& probes);

// Runs (or resumes) the search of a study with [search]; prints the brackets. Exit code as
// run_study's (1 when a probe failed).
int run_search(const Study& study, const RunOptions& opts, std::ostream& out, std::ostream& err);

// The brackets recorded so far, one per group: its label, probes and bracket (`runner table`,
// --dry-run).
struct GroupBracket {
  std::string label;
  Params params; // the group's parameters (the searched one left out)
  Bracket bracket;
};
std::vector<GroupBracket> search_brackets(const Study& study, const RunOptions& opts, Store* store);

} // namespace sph::runner
