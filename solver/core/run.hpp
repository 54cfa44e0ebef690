// What a job's run may use of its environment (RunContext) and what it returns (RunResult): the
// part of the solver's contract that time loops, cases and schemes share. No TOML, no SQLite.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace sph {

struct RunContext {
  int threads = 1;                           // OpenMP threads for this job
  std::filesystem::path output_dir;          // where the job may write HDF5 outputs; empty: none
  std::function<void(double)> progress;      // fraction of simulated time done, 0..1 (may be empty)
  const std::atomic<bool>* cancel = nullptr; // set when the job must stop (timeout, shutdown)
  // The runner's job key (SHA-256 of the job's identity), for the outputs to name their job
  // (io/job_attributes.hpp); empty outside the runner.
  std::string job_key;
  // Checkpoints (io/checkpoint.hpp) of a long job: the directory where it saves and finds its
  // checkpoint (kept by the runner across attempts of the same job; empty: none), and how often
  // to save (0: never on that criterion). attempt: 1 for the first run, 2... for re-runs.
  std::filesystem::path checkpoint_dir;
  std::int64_t checkpoint_every_steps = 0;
  double checkpoint_every_s = 0;
  int attempt = 1;
  // The solver fingerprint the job's checkpoints carry (core/fingerprint.hpp; the runner gives
  // its case's); empty: solver_fingerprint().
  std::string fingerprint;

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

} // namespace sph
