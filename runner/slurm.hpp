// Running a study on a Slurm cluster as one job array (docs/runner.md, section "Slurm").
//
// `runner submit STUDY --slurm` freezes the study's pending jobs into a manifest (job-spec files
// grouped into array tasks), marks them `submitted` and calls `sbatch --array=0-(n-1)%K` once.
// Each array task runs `runner slurm-task`, which runs its jobs one after the other through the
// `runner job` worker and writes, per job, a result file and an outcome file (both written then
// renamed). Workers never open the database: the head ingests outcome files into SQLite
// (`runner ingest`, `runner submit` again, `runner STUDY`, or `submit --wait`). A submitted job
// whose array is no longer in the queue and left no outcome goes back to pending, so a second
// `runner submit` resubmits only the unfinished jobs.
#pragma once

#include "expand.hpp"
#include "study.hpp"

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace sph::runner {

class Store;

struct SubmitOptions {
  std::filesystem::path db_path = "results/results.sqlite";
  std::string tier;
  int array_limit = 0;   // %K: array tasks running at once (0: no limit)
  int jobs_per_task = 1; // jobs run one after the other by each array task
  int threads_per_job = 1;
  std::size_t max_jobs = default_max_jobs; // refuse larger studies before expanding
  std::optional<double> timeout_s;         // per job; the Slurm time limit is derived from it
  bool retry_failed = false;
  bool rerun_stale = false; // resubmit finished jobs made by other solver code
  int max_attempts = 3;
  std::string partition;                // "" : the cluster's default
  std::vector<std::string> sbatch_args; // extra sbatch options, e.g. --account=X
  std::filesystem::path slurm_dir;      // "" : <db dir>/slurm (must be visible on the nodes)
  std::string self_exe = "/proc/self/exe";
  bool wait = false; // poll and ingest until every submitted job is back
  double poll_s = 2;
  bool dry_run = false; // write the manifest and script, do not sbatch
  // Checkpoint policy of each job (0: off), as for a local run; checkpoints live in the job's
  // output directory under slurm_dir, so a resubmitted job resumes where its last task stopped.
  std::int64_t checkpoint_every_steps = 0;
  double checkpoint_every_s = 600;
  std::vector<std::string> set, where; // as for `runner STUDY` (executor.hpp)
};

int cmd_submit(const Study& study, const SubmitOptions& opts, std::ostream& out, std::ostream& err);

// Runs array task `task` of a manifest (the body of `runner slurm-task`).
int run_slurm_task(const std::filesystem::path& manifest, int task);

struct IngestReport {
  std::size_t ingested = 0; // outcomes recorded
  std::size_t lost = 0;     // submitted jobs whose array ended without an outcome: pending again
  std::size_t waiting = 0;  // still submitted
};

// Ingests every finished outcome file of every submission into the store; marks lost jobs.
IngestReport ingest_slurm(Store& store, std::ostream& out);
int cmd_ingest(const std::filesystem::path& db, std::ostream& out);

} // namespace sph::runner
