// Runs a study: expands it (a stream, in passes: the expansion is never held whole), registers its
// jobs in the store, recovers jobs abandoned by dead runners, then runs the pending ones on a pool
// of workers, each job in a child process (`runner job`), and records every outcome in one
// transaction per job.
#pragma once

#include "expand.hpp"
#include "slurm.hpp"
#include "store.hpp"
#include "study.hpp"

#include <filesystem>
#include <functional>
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

// The jobs `run` and `submit` run: the study with --set applied, the tier (registered under
// "<tier>+KEY=VALUE,..." with --set) and the --where filters. Each pass over its jobs is a new
// JobStream; none holds the expansion. Bad --set/--where input is a StudyError naming the key and
// what it expects.
struct Selection {
  Study study; // --set applied
  std::string tier;
  std::size_t max_jobs = default_max_jobs;
  std::vector<Assignment> where;
  std::string label; // the tier's name as registered
  JobStream jobs() const { return JobStream(study, tier, max_jobs); }
};
Selection select_jobs(const Study& study, const RunOptions& opts);

// What a pass over a selection tells before anything is written: the expansion's counts (its tier
// the registered label), which jobs --where selects (by ordinal, the index in the expansion) and
// the first job's parameters. Invalid jobs, then a --where that matches none, are thrown
// (StudyError) at its end; on_selected sees each selected job on the way.
struct Survey {
  ExpansionSummary summary;
  std::vector<bool> selected;
  std::size_t n_selected = 0;
  Params first;
};
Survey survey(const Selection& sel, const std::function<void(const JobSpec&)>& on_selected = {});

// The front half `run` and `submit` share: register -> to-do. Jobs left running by dead runners
// go back to pending, finished Slurm results are ingested (when jobs are submitted), the
// selection's jobs are registered as they are expanded (sync: new jobs pending, --retry-failed,
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
SweepStart start_sweep(Store& store, const Study& study, const Selection& sel,
                       const SweepStartOptions& o, std::ostream& out);

// The record of an attempt from how its job process ended, its result file (may be missing) and
// its log (tail kept in the error text). Shared by the local pool and Slurm ingestion.
Finish outcome_to_finish(const ChildOutcome& c, const std::filesystem::path& result_file,
                         const std::filesystem::path& log, std::optional<double> timeout_s);

// Returns the process exit code: 0 when no job of the study (tier) is failed or timed out,
// 1 otherwise, 128+signal when interrupted. Study errors are thrown as StudyError before anything
// is written.
int run_study(const Study& study, const RunOptions& opts, std::ostream& out, std::ostream& err);

} // namespace sph::runner
