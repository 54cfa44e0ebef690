// Runs a study: expands it, registers its jobs in the store, recovers jobs abandoned by dead
// runners, then runs the pending ones on a pool of workers, each job in a child process
// (`runner job`), and records every outcome in one transaction per job.
#pragma once

#include "expand.hpp"
#include "slurm.hpp"
#include "store.hpp"
#include "study.hpp"

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace sph::runner {

struct RunOptions {
  std::filesystem::path db_path = "results/results.sqlite";
  std::string tier;        // "" for the whole study
  int jobs = 0;            // parallel jobs; 0: number of cores
  int threads_per_job = 1; // OMP_NUM_THREADS and RunContext::threads of each job
  std::optional<double> timeout_s;
  bool retry_failed = false;
  int max_attempts = 3; // failing attempts after which --retry-failed leaves a job alone
  bool dry_run = false;
  bool allow_network_fs = false;
  std::optional<bool> live_progress; // default: stdout is a terminal
  double log_every_s = 60;           // without the live line: a plain progress line this often
  std::string self_exe = "/proc/self/exe"; // the binary that has the `job` subcommand
  double heartbeat_s = 5;
  double stale_after_s = 30; // a running job whose heartbeat is older is abandoned
  double kill_grace_s = 5;   // SIGTERM -> SIGKILL delay
  // Checkpoint policy of each job (RunContext); 0: off. Cases that support checkpoints save
  // in the job's output directory, which is kept across attempts so a re-run resumes.
  std::int64_t checkpoint_every_steps = 0;
  double checkpoint_every_s = 600;
  // Recompute finished jobs whose solver fingerprint differs from this build's (stale).
  bool rerun_stale = false;
  // Refuse a study (tier) that expands to more jobs than this, before expanding it.
  std::size_t max_jobs = default_max_jobs;
  // --set KEY=VALUE: overrides for every job (registered under the tier "<tier>+KEY=VALUE,...");
  // --where KEY=VALUE: run only the jobs with these values (the whole study is registered).
  std::vector<std::string> set, where;
  // Keep every attempt's job output as <output_dir>/attempt-N.log (`runner one`); otherwise only
  // failed attempts keep theirs.
  bool keep_logs = false;
  // Run even when the estimate exceeds an hour of wall time (otherwise refused, exit 2).
  bool yes = false;
};

struct Finish;
struct ChildOutcome;
class Store;

// The front half `run` and `submit` share: expand -> register -> to-do. Jobs left running by
// dead runners go back to pending, finished Slurm results are ingested (when jobs are submitted),
// the study's expansion is registered (sync_study: new jobs pending, --retry-failed,
// --rerun-stale) and its pending jobs, in expansion order, are the to-do list.
struct SweepStart {
  std::vector<StaleJob> recovered; // running jobs whose owner was gone, now pending
  std::string integrity;           // PRAGMA quick_check after such a recovery ("ok": fine)
  std::optional<IngestReport> ingested;
  SyncReport sync;
  std::vector<const JobRow*> todo; // the pending jobs, pointers into sync.jobs
};
struct SweepStartOptions {
  bool retry_failed = false;
  int max_attempts = 3;
  bool rerun_stale = false;
  double stale_after_s = 30;
};
SweepStart start_sweep(Store& store, const Study& study, const Expansion& ex,
                       const SweepStartOptions& o, std::ostream& out);

// The record of an attempt from how its job process ended, its result file (may be missing) and
// its log (tail kept in the error text). Shared by the local pool and Slurm ingestion.
Finish outcome_to_finish(const ChildOutcome& c, const std::filesystem::path& result_file,
                         const std::filesystem::path& log, std::optional<double> timeout_s);

// Returns the process exit code: 0 when no job of the study (tier) is failed or timed out,
// 1 otherwise, 128+signal when interrupted. Study errors are thrown as StudyError before anything
// is written.
int run_study(const Study& study, const RunOptions& opts, std::ostream& out, std::ostream& err);

// The expansion run_study runs: --set applied, the tier named after the overrides, and the
// indexes of the jobs --where selects (all of them without --where). Bad --set/--where input is a
// StudyError naming the key and what it expects.
struct SelectedExpansion {
  Expansion ex;
  std::vector<std::size_t> selected;
};
SelectedExpansion expand_selected(const Study& study, const RunOptions& opts);

} // namespace sph::runner
