// The job store: one SQLite database (WAL) holding studies, jobs, attempts and metrics.
// All writes go through short BEGIN IMMEDIATE transactions; a job is `done` only together with its
// metrics, in one transaction. The schema is versioned by PRAGMA user_version (docs/runner.md).
#pragma once

#include "cost.hpp"
#include "expand.hpp"
#include "sqlite.hpp"

#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace sph::runner {

// Seconds since the Unix epoch (the store's time unit).
double unix_now();

// The state of a job (the `jobs.state` column). Every transition is a Store method:
//   pending -> running (claim) -> done | failed | diverged | timeout (finish) or pending (release,
//   reset_stale); pending -> submitted (mark_submitted) -> done | ... (finish_submitted) or
//   pending (give back, lost, orphaned); failed | diverged | timeout -> pending (--retry-failed);
//   done | diverged -> pending (--rerun-stale). The way back to pending is one function
//   (Store::to_pending). The column keeps these lower-case words, so existing databases and
//   users' SQL (`WHERE status='done'` on job_metrics) keep working.
enum class JobState { pending, submitted, running, done, failed, diverged, timeout };

// The database word of a state ("pending", ...).
const char* to_string(JobState s);
// The state of a database word; nullopt for anything else.
std::optional<JobState> parse_job_state(std::string_view s);
// As parse_job_state, but an unknown word throws (a database written by something else).
JobState job_state_from(std::string_view s);
// Every state, in the order `runner status` shows them.
const std::vector<JobState>& all_job_states();
// A result is recorded: done or diverged.
inline bool holds_result(JobState s) {
  return s == JobState::done || s == JobState::diverged;
}
inline bool operator==(JobState a, std::string_view b) {
  return b == to_string(a);
}
inline bool operator!=(JobState a, std::string_view b) {
  return !(a == b);
}
inline std::ostream& operator<<(std::ostream& o, JobState s) {
  return o << to_string(s);
}

// A JobState field that also takes its database word (f.state = "done"; an unknown word throws).
class JobStateField {
public:
  JobStateField(JobState s = JobState::failed) : s_(s) {}
  JobStateField(const char* s) : s_(job_state_from(s)) {}
  JobStateField(const std::string& s) : s_(job_state_from(s)) {}
  operator JobState() const { return s_; }
  JobState get() const { return s_; }

private:
  JobState s_;
};
inline std::ostream& operator<<(std::ostream& o, JobStateField s) {
  return o << s.get();
}

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
  JobState state = JobState::pending;
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
  std::string solver_fingerprint;        // provenance.hpp
  std::optional<double> predicted_cpu_s; // the cost model's estimate (cost.hpp), if any
};

struct Finish {
  JobStateField state; // done, failed, diverged or timeout
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

// Rows the read commands (status, table, export, report) and Slurm ingestion get from the store.
struct StudyInfo {
  std::int64_t id = 0;
  std::string file, definition_sha256, description, case_name;
};

struct StateCount { // runner status: one (study, tier, state) group
  std::string study, tier;
  JobState state = JobState::pending;
  std::int64_t count = 0, stale = 0;
};

struct RunningJob {
  std::string key, host, params_json;
  std::int64_t pid = 0;
  std::optional<double> heartbeat_at, progress;
};

struct SubmittedArray {
  std::string array_id; // "" when not yet known
  std::int64_t jobs = 0;
  double since = 0;
};

struct AttemptError {
  std::string key, attempt_state, failure_class, error_text;
  std::int64_t attempt = 0;
  double finished_at = 0;
  JobState job_state = JobState::pending;
};

struct StudyJob { // a job of a study, in expansion order
  std::int64_t id = 0;
  std::string key, scheme, params_json, output_dir;
  JobState state = JobState::pending;
  bool stale = false;             // made by other solver code than the fingerprint asked about
  std::vector<std::string> tiers; // the study's tiers (current expansion) the job belongs to
};

struct MetricValue {
  std::int64_t job_id = 0;
  std::string name;
  std::optional<double> value; // NaN is stored as NULL
};

// A value of an SQL result column, for the pivot of `runner table`.
struct SqlCell {
  int type = SQLITE_NULL; // SQLITE_INTEGER, SQLITE_FLOAT, SQLITE_TEXT, SQLITE_NULL
  std::int64_t integer = 0;
  double real = 0;
  std::string text;
};

// --where filters: jobs whose parameter `name` has this value (all must hold) and one of the
// schemes.
using WhereValue = std::variant<double, std::string, std::int64_t>;
struct JobFilter {
  std::vector<std::pair<std::string, WhereValue>> params;
  std::vector<std::string> schemes;
};

struct PivotCell {
  SqlCell row, col;
  std::optional<double> value;
};

// One job of a pivot cell: its row and column values, the metric and its identity parameters
// (jobs.params_json).
struct PivotMember {
  SqlCell row, col;
  double value = 0.0;
  std::string params;
  std::int64_t ordinal = 0; // the job's place in the study's expansion (the order of its values)
};

struct SubmittedJob {
  std::int64_t id = 0;
  std::string key, slurm_job_id;
  int attempt = 0;
  std::string params_json;
};

struct Submission {
  std::int64_t id = 0;
  std::string array_id;
  std::filesystem::path dir;
};

class Store {
public:
  static constexpr int schema_version = 6;
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
  // was made by other solver code go back to pending too. With accumulate, jobs registered
  // earlier stay current members (nothing is "no longer in the study"), and r.jobs lists only
  // the given jobs.
  SyncReport sync_study(const StudyRecord& study, const std::string& tier,
                        const std::vector<JobSpec>& jobs, bool retry_failed, int max_attempts,
                        double now, const std::optional<std::string>& rerun_stale_of = {},
                        bool accumulate = false);
  // The same with the jobs one at a time, in expansion order: jobs() gives the next one, nullptr
  // after the last (a JobStream: none is held).
  using JobSource = std::function<const JobSpec*()>;
  SyncReport sync_study(const StudyRecord& study, const std::string& tier, const JobSource& jobs,
                        bool retry_failed, int max_attempts, double now,
                        const std::optional<std::string>& rerun_stale_of, bool accumulate);

  // The front half shared by `run` and `submit`: registers a study's jobs for a tier as the
  // stream gives them (sync_study with the study's record) and counts the stale jobs it keeps;
  // fingerprint is this build's solver fingerprint, rerun_stale puts the stale ones back to
  // pending instead.
  SyncReport register_expansion(const Study& study, const std::string& tier, JobStream& jobs,
                                bool retry_failed, int max_attempts, bool rerun_stale,
                                const std::string& fingerprint);

  // Done and diverged jobs of a study's tier (current expansion) whose result was made by solver
  // code other than `fingerprint` (or before fingerprints were recorded).
  std::size_t stale_count(std::int64_t study_id, const std::string& tier,
                          const std::string& fingerprint);

  // The database's -wal and -shm files, as this connection has them open: "" while they are the
  // files it opened (each one noted the first time it is seen), else which one was deleted or
  // replaced. A connection whose -wal or -shm file was removed under it writes where no other
  // connection reads: its transactions are lost to them, and jobs may run twice.
  std::string wal_files_changed();

  // PRAGMA wal_checkpoint: PASSIVE (never waits) or, with truncate, TRUNCATE (the -wal file
  // back to zero bytes when no reader is using it). Errors are ignored: a checkpoint is tidying.
  void checkpoint_wal(bool truncate);

  // Puts `running` jobs whose owner is gone back to pending (same host: owner_alive(pid,
  // claimed_at) says no, claimed_at the start of the running attempt; another host: a heartbeat
  // older than stale_after_s); their attempt rows become `abandoned`.
  std::vector<StaleJob> reset_stale(const std::string& host, int self_pid, double now,
                                    double stale_after_s,
                                    const std::function<bool(int, double)>& owner_alive);

  // Atomically takes a pending job: returns the attempt number, or nullopt when the job is no
  // longer pending (another runner took it).
  std::optional<int> claim(std::int64_t job_id, const AttemptStart& a);

  // Records a finished attempt: attempt row, metrics and job state in one transaction.
  // false when the job is no longer ours (reset as stale by another runner): nothing written.
  // The attempt's metrics always go to attempt_metrics. They become the job's result (metrics,
  // state) when it is done, or diverged while the job holds no done result; otherwise the job
  // keeps the result it holds and its state (a recomputation that fails or diverges never takes
  // a result away; the attempt row says what happened).
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
  std::map<JobState, std::size_t> state_counts(std::int64_t study_id, const std::string& tier);

  // State of each key (absent keys are not in the map); for --dry-run.
  std::map<std::string, JobState> states_of(const std::vector<std::string>& keys);

  // One job by key: state, attempts, output folder and metrics (in recording order).
  struct JobSummary {
    std::int64_t id = 0;
    JobState state = JobState::pending;
    int attempts = 0;
    std::string output_dir;
    std::vector<std::pair<std::string, std::optional<double>>> metrics;
  };
  std::optional<JobSummary> job_summary(const std::string& key);

  // Done jobs' last attempts (a diverged job stopped early: not a rate) with their CPU time and
  // size metrics (n_particles, steps, work_steps or acoustic_steps, dimension,
  // predicted_work), of every case
  // with one of these schemes ("" for none), by "case/scheme"; at most `limit` per scheme.
  std::map<std::string, std::vector<CostSample>>
  cost_samples(const std::vector<std::string>& schemes, std::size_t limit = 2000);

  // Jobs in a state, all studies.
  std::size_t count_in_state(JobState s);
  // PRAGMA quick_check: "ok" or SQLite's first complaint.
  std::string quick_check();
  // Mean wall time of the finished (done, diverged) attempts of a study's tier; the ETA before
  // the first job of a run finishes.
  std::optional<double> mean_wall_s(std::int64_t study_id, const std::string& tier);

  // --- Reading (status, table, export, report) ---------------------------------------------
  std::optional<StudyInfo> find_study(const std::string& name);
  std::vector<std::string> study_names();
  // Counts per (study, tier, state) of the current expansions (one study, or all), with how many
  // are stale against `fingerprint_of_case` of their study's case.
  std::vector<StateCount>
  state_table(std::optional<std::int64_t> study_id,
              const std::function<std::string(const std::string&)>& fingerprint_of_case);
  std::vector<RunningJob> running_jobs(std::optional<std::int64_t> study_id);
  std::vector<SubmittedArray> submitted_arrays(std::optional<std::int64_t> study_id);
  // The last `limit` failed, timed-out, abandoned or interrupted attempts with an error text.
  std::vector<AttemptError> last_errors(std::optional<std::int64_t> study_id, int limit);
  // The jobs of a study in expansion order: of one tier, or all; only the current expansion, or
  // every job ever registered with it. Their output_dir as job_folder() gives it.
  std::vector<StudyJob> study_jobs(std::int64_t study_id, const std::optional<std::string>& tier,
                                   bool current_only, const std::string& fingerprint);
  // A job's folder as recorded (jobs.output_dir), as a path that works from here: a folder is
  // <database dir>/<study>/<key>, recorded relative to the directory the runner ran in when its
  // --db was relative, so a relative one is taken from this database's own directory.
  std::string job_folder(const std::string& recorded) const;
  // The metrics of every job ever registered with a study, by job and then recording order.
  std::vector<MetricValue> study_metrics(std::int64_t study_id);
  // The code version of the attempt that recorded each job's metrics (job id -> version).
  std::map<std::int64_t, std::string> metric_code_versions(std::int64_t study_id);
  // Distinct metric names of a study's jobs.
  std::vector<std::string> metric_names(std::int64_t study_id);
  // Parameter names of a study's jobs; has_param: one of them.
  std::vector<std::string> param_names(std::int64_t study_id);
  bool has_param(std::int64_t study_id, const std::string& name);
  // Jobs of a study that are stale against `fingerprint`: current ones, or (report) any of a tier.
  std::size_t stale_in_study(std::int64_t study_id, const std::string& fingerprint,
                             const std::optional<std::string>& tier, bool current_only);
  // `runner table`: agg(metric) ("avg", "min", "max", "count") grouped by two parameters (or
  // "scheme") over the study's current jobs that pass the filter.
  // The jobs behind pivot(): every selected job that has the metric, with its parameters (for a
  // median, the count per cell and the parameters that vary inside a cell).
  std::vector<PivotMember> pivot_members(std::int64_t study_id, const std::string& rows,
                                         const std::string& cols, const std::string& metric,
                                         const JobFilter& filter);
  std::vector<PivotCell> pivot(std::int64_t study_id, const std::string& rows,
                               const std::string& cols, const std::string& metric,
                               const std::string& agg, const JobFilter& filter);
  // `runner query`: prepares the user's statement after checking it reads only (authorizer and
  // sqlite3_stmt_readonly) and is one statement; throws with the reason otherwise.
  Stmt prepare_read_query(const std::string& sql);
  // Interrupts this connection's statements once `seconds` have passed from now (SQLite's
  // progress handler; their step() throws SQLITE_INTERRUPT); 0: no limit. deadline_passed():
  // whether that happened.
  void set_deadline(double seconds);
  bool deadline_passed() const;

  // --- Slurm -------------------------------------------------------------------------------
  // Records a submission of n_jobs in n_tasks; dir_of(id) names its directory (manifest in it).
  std::int64_t create_submission(std::int64_t study_id, const std::string& tier, std::size_t n_jobs,
                                 std::size_t n_tasks, double now,
                                 const std::function<std::filesystem::path(std::int64_t)>& dir_of);
  // One transaction: pending -> submitted (attempt + 1, attempt row `running` on host "slurm")
  // for each job still pending; on_marked(index in ids, attempt) for each (writes its spec);
  // then before_commit() (writes the manifest) returns the task count recorded with the number
  // of marked jobs in the submission. An exception rolls everything back. Returns (id, attempt).
  std::vector<std::pair<std::int64_t, int>>
  mark_submitted(const std::vector<std::int64_t>& ids, const AttemptStart& a,
                 std::int64_t submission, const std::function<void(std::size_t, int)>& on_marked,
                 const std::function<std::size_t()>& before_commit);
  // sbatch failed (or --dry-run): submitted -> pending, attempt rows `interrupted` [submit].
  void give_back_submitted(const std::vector<std::pair<std::int64_t, int>>& jobs,
                           const std::string& reason, double now);
  // The array id of a submission and each job's "<array>_<task>" id (jobs[k] in task tasks[k]).
  void record_array(std::int64_t submission, const std::string& array_id,
                    const std::vector<std::pair<std::int64_t, int>>& jobs,
                    const std::vector<std::size_t>& tasks);
  // Jobs still submitted in an array.
  std::size_t count_submitted_in_array(const std::string& array_id);
  // Submitted jobs whose submitter died before sbatch returned (no array id): pending again.
  std::size_t requeue_orphan_submissions(const std::string& host, int self_pid, double now,
                                         const std::function<bool(int)>& pid_alive);
  // Submissions with jobs still submitted, and those jobs.
  std::vector<Submission> open_submissions();
  std::vector<SubmittedJob> submitted_jobs_of_array(const std::string& array_id);
  // A study the job belongs to (its first), for jobs whose manifest does not say.
  std::optional<std::string> a_study_of_job(std::int64_t job_id);
  // Submitted jobs whose array left the queue without an outcome: pending again.
  void requeue_lost(const std::vector<std::pair<std::int64_t, int>>& jobs,
                    const std::string& reason, double now);

private:
  Stmt prepare_pivot(std::int64_t study_id, const std::string& columns, const std::string& metric,
                     const JobFilter& filter, const std::string& tail);
  Store(Db db, std::filesystem::path path) : db_(std::move(db)), path_(std::move(path)) {}
  void migrate();
  void record_attempt(std::int64_t job_id, int attempt, const Finish& f); // inside a transaction
  // The one way back to `pending`: prepares "UPDATE jobs SET state='pending' (no owner, no
  // heartbeat), updated_at=?1 WHERE <cond>"; cond's own parameters start at ?2. Every reset
  // (stale owner, release, --retry-failed, --rerun-stale, Slurm give-back, lost and orphaned
  // submissions) runs through it, inside the caller's transaction.
  Stmt to_pending(const std::string& cond);
  // Closes the attempt rows of jobs sent back to pending: state (interrupted or abandoned),
  // failure_class, finished_at, error_text = ?1..?4; cond's parameters start at ?5.
  Stmt end_attempt(const std::string& cond);
  Db db_;
  std::filesystem::path path_;
  // set_deadline(): the time and whether it passed (on the heap: the handler keeps its address
  // when the Store moves).
  struct Deadline {
    std::chrono::steady_clock::time_point at;
    bool passed = false;
  };
  std::unique_ptr<Deadline> deadline_;
  std::map<std::string, std::pair<std::uint64_t, std::uint64_t>> wal_files_; // (dev, inode)
};

// The error text for a database file SQLite reports as corrupt (what: SQLite's words).
// at_open: found before anything was written; otherwise in the middle of a command.
std::string damaged_message(const std::filesystem::path& path, const std::string& what,
                            bool at_open = true);

// True when `dir` is on NFS, SMB/CIFS, Lustre, GPFS, BeeGFS, Ceph or FUSE (sshfs...).
bool is_network_filesystem(const std::filesystem::path& dir, std::string* fs_name = nullptr);

} // namespace sph::runner
