// The contract between the solver and whoever runs it (the runner, a test, a user's program).
//
// A case declares its parameters (name, type, default, range or choices, documentation) and a run
// function: resolved parameters in, metrics out. The solver knows nothing of TOML or SQLite: the
// runner validates a study against these specs, fills defaults, computes the job key from the
// resolved set, and records what run() returns.
//
// Adding a case: one file in solver/cases/ named like its registry key, defining
// `CaseInfo make_<key>_case()`, and one line in cases/registry.cpp.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace sph {

// A parameter value. Int and Real are distinct: a Real parameter given as 1 is stored as 1.0.
using ParamValue = std::variant<bool, std::int64_t, double, std::string>;
using Params = std::map<std::string, ParamValue>;

enum class ParamType { Bool, Int, Real, String };

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::Real;
  ParamValue default_value = 0.0;   // every parameter has a default
  std::string doc;                  // one line, with units
  std::optional<double> min;        // Int/Real: inclusive lower bound
  std::optional<double> max;        // Int/Real: inclusive upper bound
  bool min_exclusive = false;       // min is exclusive (e.g. dx > 0)
  std::vector<std::string> choices; // String: allowed values (empty: any)
  // false: does not enter the job's identity (threads, output options).
  bool identity = true;
  // true: at its default value the parameter does not enter the job key either, so a parameter
  // added to a case with a default that reproduces the old behaviour keeps the keys (and the
  // finished results) of the jobs that do not set it. Other values enter the key as usual.
  bool neutral_default = false;
};

// Typed access to resolved parameters (the runner guarantees presence and type).
double get_real(const Params& p, const std::string& key);
std::int64_t get_int(const Params& p, const std::string& key);
bool get_bool(const Params& p, const std::string& key);
const std::string& get_string(const Params& p, const std::string& key);

// What a run may use of its environment.
struct RunContext {
  int threads = 1;                           // OpenMP threads for this job
  std::filesystem::path output_dir;          // where the job may write HDF5 outputs; empty: none
  std::function<void(double)> progress;      // fraction of simulated time done, 0..1 (may be empty)
  const std::atomic<bool>* cancel = nullptr; // set when the job must stop (timeout, shutdown)
  // Checkpoints (io/checkpoint.hpp) of a long job: the directory where it saves and finds its
  // checkpoint (kept by the runner across attempts of the same job; empty: none), and how often
  // to save (0: never on that criterion). attempt: 1 for the first run, 2... for re-runs.
  std::filesystem::path checkpoint_dir;
  std::int64_t checkpoint_every_steps = 0;
  double checkpoint_every_s = 0;
  int attempt = 1;

  bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
  void report(double fraction) const {
    if (progress)
      progress(fraction);
  }
};

enum class RunStatus { Done, Diverged, Cancelled };

struct RunResult {
  RunStatus status = RunStatus::Done;
  std::vector<std::pair<std::string, double>> metrics; // in the order the case computed them
  std::string message;                                 // why it diverged, or notes

  void add(const std::string& name, double value) { metrics.emplace_back(name, value); }
};

// The answer of a time loop to a request to stop (ctx.cancelled(): timeout, shutdown, scancel):
// save() first (a case that checkpoints saves its state there; a no-op when checkpoints are off),
// then res is marked Cancelled at time t. True when the loop must stop and return res.
template <class Save>
bool stop_if_cancelled(const RunContext& ctx, double t, RunResult& res, Save&& save) {
  if (!ctx.cancelled())
    return false;
  save();
  res.status = RunStatus::Cancelled;
  res.message = "cancelled at t = " + std::to_string(t);
  return true;
}

// A time integrator family (isph, wcsph_tvf, contact, alsph): its own parameters, shared by every
// case it runs. A study names `scheme = "isph"`; the job's parameters are the case's plus the
// scheme's, and Params carries the scheme's name under the key "scheme".
struct SchemeInfo {
  std::string name;
  std::string description; // one line, with the paper
  std::vector<ParamSpec> params;
};

struct CaseInfo {
  std::string name;
  std::string description;          // one line, with the paper and section
  std::vector<std::string> schemes; // schemes this case runs with (empty: none; first = default)
  std::vector<ParamSpec> params;    // the case's own parameters (geometry, physics, diagnostics)
  std::function<RunResult(const Params&, const RunContext&)> run;
  // Optional: the case's own constraints on a resolved parameter set, checked when a study is
  // validated (before anything runs): an error message ("1/dx must be an integer"), or nullopt.
  std::function<std::optional<std::string>(const Params&)> check;
};

// All registered cases, in registration order.
const std::vector<CaseInfo>& case_registry();
// nullptr when no case has that name.
const CaseInfo* find_case(const std::string& name);

// All registered schemes (schemes/registry.cpp), and look-up by name (nullptr if unknown).
const std::vector<SchemeInfo>& scheme_registry();
const SchemeInfo* find_scheme(const std::string& name);

// Version of the numerics; enters every job key. Bump when a change alters results of existing
// parameter sets, so that old and new results never share a key.
inline constexpr int numerics_version = 1;

} // namespace sph
