// The job store: one SQLite database (WAL) holding studies, jobs, attempts and metrics.
// All writes go through short BEGIN IMMEDIATE transactions; a job is `done` only together with its
// metrics, in one transaction. The schema is versioned by PRAGMA user_version (docs/runner.md).
#pragma once

#include "expand.hpp"
#include "sqlite.hpp"

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sph::runner {

// Seconds since the Unix epoch (the store's time unit).
double unix_now();

struct StudyRecord {
  std::string name;
  std::string case_name;
  std::string description;
  std::string file;
  std::string definition_sha256;
};

struct JobRow {
  std::int64_t id = 0;
  std::size_t ordinal = 0; // index in the expansion
  std::string state;
  int attempts = 0;
};

struct SyncReport {
  std::int64_t study_id = 0;
  bool study_is_new = false;
  bool definition_changed = false;
  std::size_t inserted = 0;  // jobs new to the database
  std::size_t removed = 0;   // were in this study and tier, no longer in its expansion
  std::size_t requeued = 0;  // failed/diverged/timeout jobs put back to pending (--retry-failed)
  std::size_t exhausted = 0; // failed jobs left alone because they reached max_attempts
  std::size_t stale_requeued = 0; // done/diverged jobs of other solver code put back to pending
  std::size_t stale_kept = 0;     // ... kept as they are (without rerun_stale)
  std::vector<JobRow> jobs;       // in expansion order
};

struct AttemptStart {
  std::string host;
  int pid = 0; // the runner's pid (owner of the job)
  int threads = 1;
  std::string code_version;
  std::string compiler;
  double started_at = 0;
  std::string solver_fingerprint; // provenance.hpp
};

struct Finish {
  std::string state; // done, failed, diverged or timeout
  double finished_at = 0;
  std::optional<double> wall_s, cpu_s;
  std::optional<std::int64_t> peak_rss_kb, child_pid, exit_code, signal;
  std::string message;    // from the case
  std::string error_text; // why it failed (with the job's stderr tail)
  // Why the attempt did not finish: exit (non-zero exit or no result), signal, timeout,
  // exception (run() threw), spawn (could not start); "" for done and diverged.
  std::string failure_class;
  std::vector<std::pair<std::string, double>> metrics;
  std::optional<std::string> output_dir;
};

struct StaleJob {
  std::string key;
  std::string reason;
};

class Store {
public:
  static constexpr int schema_version = 4;
  // PRAGMA application_id of a runner database: 'SPHR'.
  static constexpr std::int64_t application_id = 0x53504852;

  // Creates the file (and its directory) if needed, migrates the schema, sets WAL.
  // Refuses a database on a network file system unless allow_network_fs (then no WAL).
  static Store open_write(const std::filesystem::path& path, bool allow_network_fs = false);
  // Read-only connection to an existing database.
  static Store open_read(const std::filesystem::path& path);

  Db& db() { return db_; }
  const std::filesystem::path& path() const { return path_; }

  // Registers the study and its jobs for `tier` (one transaction): inserts new jobs as pending,
  // records membership and order, drops membership of jobs no longer in the expansion, and with
  // retry_failed puts failed/diverged/timeout jobs with fewer than max_attempts failing attempts
  // back to pending.
  // With rerun_stale_of (this build's solver fingerprint), done and diverged jobs whose result
  // was made by other solver code go back to pending too.
  SyncReport sync_study(const StudyRecord& study, const std::string& tier,
                        const std::vector<JobSpec>& jobs, bool retry_failed, int max_attempts,
                        double now, const std::optional<std::string>& rerun_stale_of = {});

  // The front half shared by `run` and `submit`: registers an expanded study (sync_study with the
  // study's record) and counts the stale jobs it keeps; fingerprint is this build's solver
  // fingerprint, rerun_stale puts the stale ones back to pending instead.
  SyncReport register_expansion(const Study& study, const Expansion& ex, bool retry_failed,
                                int max_attempts, bool rerun_stale, const std::string& fingerprint);

  // Done and diverged jobs of a study's tier (current expansion) whose result was made by solver
  // code other than `fingerprint` (or before fingerprints were recorded).
  std::size_t stale_count(std::int64_t study_id, const std::string& tier,
                          const std::string& fingerprint);

  // PRAGMA wal_checkpoint: PASSIVE (never waits) or, with truncate, TRUNCATE (the -wal file
  // back to zero bytes when no reader is using it). Errors are ignored: a checkpoint is tidying.
  void checkpoint_wal(bool truncate);

  // Puts `running` jobs whose owner is gone back to pending (same host: the owner pid is dead;
  // another host: a heartbeat older than stale_after_s); their attempt rows become `abandoned`.
  std::vector<StaleJob> reset_stale(const std::string& host, int self_pid, double now,
                                    double stale_after_s,
                                    const std::function<bool(int)>& pid_alive);

  // Atomically takes a pending job: returns the attempt number, or nullopt when the job is no
  // longer pending (another runner took it).
  std::optional<int> claim(std::int64_t job_id, const AttemptStart& a);

  // Records a finished attempt: attempt row, metrics and job state in one transaction.
  // false when the job is no longer ours (reset as stale by another runner): nothing written.
  bool finish(std::int64_t job_id, int attempt, const std::string& host, int pid, const Finish& f);

  // Records the outcome of a job handed to Slurm (state `submitted`, attempt `attempt`); the
  // attempt row gets the host that ran it and its Slurm job id. false when the job is no longer
  // submitted under that attempt (already ingested, or reset): nothing written.
  bool finish_submitted(std::int64_t job_id, int attempt, const std::string& host,
                        const std::string& slurm_job_id, const Finish& f);

  // Gives a job back (runner interrupted): state pending, attempt row `interrupted`.
  void release(std::int64_t job_id, int attempt, const std::string& host, int pid,
               const std::string& reason, double now);

  // Refreshes heartbeat_at (and progress when known) of jobs this runner owns.
  void heartbeat(const std::vector<std::pair<std::int64_t, std::optional<double>>>& jobs,
                 const std::string& host, int pid, double now);

  // Counts by state of a study's jobs in a tier.
  std::map<std::string, std::size_t> state_counts(std::int64_t study_id, const std::string& tier);

  // State of each key (absent keys are not in the map); for --dry-run.
  std::map<std::string, std::string> states_of(const std::vector<std::string>& keys);

private:
  Store(Db db, std::filesystem::path path) : db_(std::move(db)), path_(std::move(path)) {}
  void migrate();
  void record_attempt(std::int64_t job_id, int attempt, const Finish& f); // inside a transaction
  Db db_;
  std::filesystem::path path_;
};

// The error text for a database file SQLite reports as corrupt (what: SQLite's words).
// at_open: found before anything was written; otherwise in the middle of a command.
std::string damaged_message(const std::filesystem::path& path, const std::string& what,
                            bool at_open = true);

// SQL: 1 when job `job` (an SQL expression for jobs.id, e.g. "j.id") with state `state` (e.g.
// "j.state") holds a result (done or diverged) made by solver code other than the bound
// parameter `fp` (e.g. "?3"); 0 otherwise. For databases before schema version 4 (no
// fingerprints) every result is stale.
std::string stale_sql(Db& db, const std::string& job, const std::string& state,
                      const std::string& fp);

// True when `dir` is on NFS, SMB/CIFS, Lustre, GPFS, BeeGFS, Ceph or FUSE (sshfs...).
bool is_network_filesystem(const std::filesystem::path& dir, std::string* fs_name = nullptr);

} // namespace sph::runner
