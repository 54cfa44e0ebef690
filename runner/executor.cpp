// The local executor: a main thread that owns the database connection (claims, finishes,
// heartbeats) and a pool of worker threads that each supervise one job process at a time.
#include "executor.hpp"

#include "cost.hpp"
#include "diagnostics.hpp"
#include "expand.hpp"
#include "job_file.hpp"
#include "overrides.hpp"
#include "params.hpp"
#include "process.hpp"
#include "progress.hpp"
#include "provenance.hpp"
#include "slurm.hpp"
#include "store.hpp"

#include <atomic>
#include <cerrno>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <deque>
#include <fcntl.h>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sys/file.h>
#include <thread>
#include <unistd.h>

namespace sph::runner {

namespace fs = std::filesystem;

namespace {

std::atomic<int> g_stop{0};
std::atomic<int> g_signal{0};

extern "C" void on_stop_signal(int sig) {
  g_signal.store(sig);
  g_stop.fetch_add(1);
}

// Installs SIGINT/SIGTERM/SIGHUP/SIGPIPE handlers for the lifetime of a run.
class SignalGuard {
public:
  SignalGuard() {
    g_stop = 0;
    g_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    for (std::size_t i = 0; i < n; ++i)
      sigaction(signals[i], &sa, &old_[i]);
  }
  ~SignalGuard() {
    for (std::size_t i = 0; i < n; ++i)
      sigaction(signals[i], &old_[i], nullptr);
  }

private:
  // SIGHUP: the terminal closed; SIGPIPE: stdout is a pipe whose reader went away (`| head`).
  static constexpr int signals[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};
  static constexpr std::size_t n = sizeof signals / sizeof *signals;
  struct sigaction old_[n] = {};
};

struct Task {
  std::string label, running_label; // label_of and running_label of its job
  std::int64_t job_id = 0;
  int attempt = 0;
  fs::path spec, result, log, progress, output_dir;
  int lock_fd = -1; // flock on <output_dir>/.attempt.lock while the attempt runs
  JobRecord record; // params.json of the job's folder
  fs::path alias;   // by-params/ link to the folder (alias_of)
  std::chrono::steady_clock::time_point started;
  std::optional<double> predicted_s; // the cost model's wall seconds (ETA)
  // The first simulated-time fraction the attempt reported (> 0 when it resumed from a
  // checkpoint): the ETA counts the progress made since then.
  std::optional<double> first_fraction;
};

// Rewrites params.json at the end of an attempt; a failure to write it is a warning (the
// database holds the same facts), not a reason to lose the result.
void finish_record(Task& t, const std::string& state, double finished_at, std::ostream& err) {
  t.record.state = state;
  t.record.finished_at = finished_at;
  try {
    write_job_record(t.output_dir, t.record);
  } catch (const std::exception& e) {
    err << "warning: " << e.what() << "\n";
  }
}

const char* const folder_lock_name = ".attempt.lock";

// Takes an exclusive lock on the job's output folder for its attempt (held by the runner while
// the job process runs; released by the kernel if the runner dies). false when another attempt
// holds it; *holder then says which pid wrote it.
bool take_folder_lock(Task& t, std::string* holder) {
  const fs::path p = t.output_dir / folder_lock_name;
  int fd = ::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0)
    throw std::runtime_error("cannot create " + p.string() + ": " + std::strerror(errno));
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    char buf[64] = {};
    ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
    std::string who = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
    while (!who.empty() && std::isspace(static_cast<unsigned char>(who.back())))
      who.pop_back();
    if (holder)
      *holder = who.empty() ? "" : " (" + who + ")";
    ::close(fd);
    return false;
  }
  std::string me = "runner " + host_name() + ":" + std::to_string(getpid()) + ", attempt " +
                   std::to_string(t.attempt) + "\n";
  if (::ftruncate(fd, 0) == 0 && ::pwrite(fd, me.data(), me.size(), 0) < 0) {
    // the holder's name is informative only
  }
  t.lock_fd = fd;
  return true;
}

// Removes the lock file while still holding the lock (so an empty folder can be removed).
void unlink_folder_lock(const Task& t) {
  if (t.lock_fd >= 0)
    ::unlink((t.output_dir / folder_lock_name).c_str());
}

void release_folder_lock(Task& t) {
  if (t.lock_fd >= 0)
    ::close(t.lock_fd);
  t.lock_fd = -1;
}

// The owner of a job on this host is alive: its pid runs and that process started before it
// claimed the job (claimed_at), so it is not an unrelated process that reused the pid of a dead
// runner. (The name of the program is no test: a runner started from a copy of the binary under
// another name, or from a rebuilt one, owns its jobs as well.) Where /proc gives no start time,
// the process having the same name as this one decides.
bool owner_alive(int pid, double claimed_at) {
  if (!pid_alive(pid))
    return false;
  if (const auto start = process_start_time(pid))
    return *start <= claimed_at + 2.0; // /proc's boot time has whole seconds
  auto comm = [](const std::string& p) {
    std::ifstream in("/proc/" + p + "/comm");
    std::string s;
    std::getline(in, s);
    return s;
  };
  std::string theirs = comm(std::to_string(pid)), ours = comm("self");
  return theirs.empty() || ours.empty() || theirs == ours;
}

struct Outcome {
  Task task;
  ChildOutcome child;
};

// Work queue to the workers and result queue back to the main thread.
class Channel {
public:
  void push_task(Task t) {
    {
      std::lock_guard lk(m_);
      tasks_.push_back(std::move(t));
    }
    task_cv_.notify_one();
  }
  std::optional<Task> pop_task() {
    std::unique_lock lk(m_);
    task_cv_.wait(lk, [&] { return closed_ || !tasks_.empty(); });
    if (tasks_.empty())
      return std::nullopt;
    Task t = std::move(tasks_.front());
    tasks_.pop_front();
    return t;
  }
  void close() {
    {
      std::lock_guard lk(m_);
      closed_ = true;
    }
    task_cv_.notify_all();
  }
  void push_outcome(Outcome o) {
    {
      std::lock_guard lk(m_);
      outcomes_.push_back(std::move(o));
    }
    outcome_cv_.notify_one();
  }
  std::vector<Outcome> wait_outcomes(std::chrono::milliseconds timeout) {
    std::unique_lock lk(m_);
    outcome_cv_.wait_for(lk, timeout, [&] { return !outcomes_.empty(); });
    std::vector<Outcome> v(std::make_move_iterator(outcomes_.begin()),
                           std::make_move_iterator(outcomes_.end()));
    outcomes_.clear();
    return v;
  }

private:
  std::mutex m_;
  std::condition_variable task_cv_, outcome_cv_;
  std::deque<Task> tasks_;
  std::deque<Outcome> outcomes_;
  bool closed_ = false;
};

// The job's values of the varying parameters, "name=value" joined by sep.
std::string varying_values(const JobSpec& job, const std::vector<std::string>& varying,
                           const char* sep) {
  std::string s;
  for (const auto& name : varying)
    if (auto it = job.params.find(name); it != job.params.end())
      s += (s.empty() ? "" : sep) + name + "=" + format_value_plain(it->second);
  return s;
}

// A finished job's line: its key prefix and varying parameters.
std::string label_of(const JobSpec& job, const std::vector<std::string>& varying) {
  const std::string v = varying_values(job, varying, " ");
  return job.key.substr(0, 12) + (v.empty() ? "" : " " + v);
}

// A running job on the progress line: its varying parameters (the key prefix when none vary).
std::string running_label(const JobSpec& job, const std::vector<std::string>& varying) {
  const std::string v = varying_values(job, varying, " ");
  return v.empty() ? job.key.substr(0, 8) : v;
}

// The readable alias of a job's folder: <study folder>/by-params/<varying params>_<key prefix>,
// a relative symlink to ../<key> ("dx=0.01,visc=visc03_3fa81c2e"; the key prefix keeps jobs of
// different tiers with the same varying values apart).
fs::path alias_of(const fs::path& output_dir, const JobSpec& job,
                  const std::vector<std::string>& varying) {
  std::string s = varying_values(job, varying, ",");
  for (char& c : s)
    if (c == '/' || c == ' ')
      c = '_';
  return output_dir.parent_path() / "by-params" /
         ((s.empty() ? "" : s + "_") + job.key.substr(0, 8));
}

// Creates the alias (if missing); a failure is a warning, the job runs.
void make_alias(const fs::path& alias, const fs::path& output_dir, std::ostream& err) {
  std::error_code ec;
  if (fs::is_symlink(alias, ec))
    return;
  fs::create_directories(alias.parent_path(), ec);
  fs::create_directory_symlink(fs::path("..") / output_dir.filename(), alias, ec);
  if (ec)
    err << "warning: cannot create the folder alias " << alias.string() << ": " << ec.message()
        << "\n";
}

std::string short_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

// Removes scratch directories of runners on this host that are no longer alive.
void clean_dead_scratch(const fs::path& base, const std::string& host) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(base, ec)) {
    std::string n = e.path().filename().string();
    auto dash = n.rfind('-');
    if (dash == std::string::npos || n.substr(0, dash) != host)
      continue;
    int pid = std::atoi(n.c_str() + dash + 1);
    if (pid > 0 && pid != getpid() && !pid_alive(pid))
      fs::remove_all(e.path(), ec);
  }
}

std::optional<double> read_progress(const fs::path& p) {
  std::ifstream in(p);
  double x;
  if (in >> x && std::isfinite(x))
    return x;
  return std::nullopt;
}

bool is_empty_dir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec) && fs::is_empty(p, ec);
}

} // namespace

Finish outcome_to_finish(const ChildOutcome& c, const fs::path& result_file, const fs::path& log,
                         std::optional<double> timeout_s) {
  Finish f;
  f.finished_at = unix_now();
  if (c.pid > 0) {
    f.wall_s = c.wall_s;
    f.cpu_s = c.cpu_s;
    f.peak_rss_kb = c.peak_rss_kb;
    f.child_pid = c.pid;
    if (c.exited)
      f.exit_code = c.exit_code;
    else if (c.term_signal)
      f.signal = c.term_signal;
  }
  std::string tail = file_tail(log, 4000);
  auto with_tail = [&](std::string s) {
    if (!tail.empty())
      s += "\n--- job output (tail) ---\n" + tail;
    return s;
  };
  std::optional<JobFileResult> r;
  std::string bad_result;
  try {
    r = read_result_file(result_file);
  } catch (const std::exception& e) {
    bad_result = e.what();
  }
  if (r && (r->status == "done" || r->status == "diverged")) {
    f.metrics = r->metrics;
    f.message = r->message;
    f.state = r->status == "done" ? JobState::done : JobState::diverged;
    if (f.state == JobState::done)
      for (const auto& [name, value] : f.metrics)
        if (!std::isfinite(value)) {
          f.state = JobState::diverged;
          f.message = "metric '" + name + "' is " + (std::isnan(value) ? "NaN" : "infinite") +
                      (f.message.empty() ? "" : "; " + f.message);
          break;
        }
    return f;
  }
  if (c.timed_out) {
    f.state = JobState::timeout;
    f.failure_class = "timeout";
    f.error_text = with_tail("exceeded the wall-clock limit of " +
                             short_number(timeout_s.value_or(0)) + " s (--timeout)");
  } else if (r && r->status == "failed") {
    f.state = JobState::failed;
    f.failure_class = "exception";
    f.message = r->message;
    f.error_text = with_tail("exception: " + r->message);
  } else if (r) { // cancelled without being asked
    f.state = JobState::failed;
    f.failure_class = "exception";
    f.message = r->message;
    f.error_text = with_tail("the case returned Cancelled without a cancellation request");
  } else if (!c.spawn_error.empty()) {
    f.state = JobState::failed;
    f.failure_class = "spawn";
    f.error_text = c.spawn_error;
  } else if (!c.exited) {
    f.state = JobState::failed;
    f.failure_class = "signal";
    f.error_text = with_tail("job process killed by " + signal_description(c.term_signal));
  } else {
    f.state = JobState::failed;
    f.failure_class = "exit";
    f.error_text = with_tail(
        "job process exited with code " + std::to_string(c.exit_code) +
        (bad_result.empty() ? " without writing a result" : "; unreadable result: " + bad_result));
  }
  return f;
}

Selection select_jobs(const Study& study_file, const RunOptions& opts) {
  std::vector<Assignment> sets;
  std::set<std::string> set_names;
  for (const auto& kv : opts.set) {
    sets.push_back(parse_assignment(study_file.specs, kv, "--set"));
    if (!set_names.insert(sets.back().name).second)
      throw StudyError({{"command line", 0, 0,
                         "--set " + kv + ": '" + sets.back().name +
                             "' is given twice; give each parameter one value"}});
  }
  Selection sel{study_file, opts.tier, opts.max_jobs, {}, {}};
  for (const auto& kv : opts.where)
    sel.where.push_back(parse_assignment(study_file.specs, kv, "--where"));
  apply_overrides(sel.study, sets);
  sel.label = opts.tier.empty() ? std::string(full_tier) : opts.tier;
  if (!sets.empty())
    sel.label += "+" + overrides_label(sets);
  return sel;
}

Survey survey(const Selection& sel, const std::function<void(const JobSpec&)>& on_selected) {
  Survey s;
  JobStream jobs = sel.jobs();
  JobSpec job;
  while (jobs.next(job)) {
    if (s.selected.empty())
      s.first = job.params;
    const bool yes = matches_where(job.params, sel.where);
    s.selected.push_back(yes);
    if (yes) {
      ++s.n_selected;
      if (on_selected)
        on_selected(job);
    }
  }
  s.summary = jobs.summary();
  s.summary.tier = sel.label;
  if (s.n_selected == 0 && !sel.where.empty())
    fail_where(sel.jobs(), sel.where, sel.label);
  return s;
}

SweepStart start_sweep(Store& store, const Study& study, const Selection& sel,
                       const SweepStartOptions& o, std::ostream& out) {
  SweepStart r;
  r.recovered = store.reset_stale(host_name(), static_cast<int>(getpid()), unix_now(),
                                  o.stale_after_s, owner_alive);
  r.integrity = r.recovered.empty() ? "ok" : store.quick_check();
  if (store.count_in_state(JobState::submitted) > 0)
    r.ingested = ingest_slurm(store, out);
  JobStream jobs = sel.jobs();
  r.sync = store.register_expansion(study, sel.label, jobs, o.retry_failed, o.max_attempts,
                                    o.rerun_stale, solver_fingerprint(study.case_name));
  for (const auto& row : r.sync.jobs)
    if (row.state == JobState::pending)
      r.todo.push_back(&row);
  return r;
}

int run_study(const Study& study, const RunOptions& opts, std::ostream& out, std::ostream& err) {
  const Selection sel = select_jobs(study, opts);
  std::string where_text;
  for (const auto& w : opts.where)
    where_text += " --where " + w;
  const std::string& tier = sel.label;
  const std::string title = study.name + (tier == full_tier ? "" : " [" + tier + "]");

  // The cost of what this run would run (new and pending jobs; failed ones with --retry-failed),
  // calibrated from the database's finished jobs: printed, and above an hour of wall time on this
  // machine the run needs --yes. In a real run a database the estimate cannot read is left to the
  // writer's checks below (its messages), the estimate then goes without calibration.
  // One pass over the jobs (which also validates them all, before anything is written) looks up
  // their states in batches and adds those to run to the estimate.
  std::optional<Store> ro;
  CostSamples samples;
  auto unreadable = [&] {
    if (opts.dry_run)
      throw;
    ro.reset();
    samples.clear();
  };
  {
    std::error_code ec;
    if (fs::exists(opts.db_path, ec)) {
      try {
        ro.emplace(Store::open_read(opts.db_path));
        std::vector<std::string> schemes = study.info->schemes;
        if (schemes.empty())
          schemes.emplace_back();
        samples = ro->cost_samples(schemes);
      } catch (const std::exception&) {
        unreadable();
      }
    }
  }
  CostTally tally(samples);
  std::size_t n_to_run = 0;
  std::vector<std::optional<JobState>> listed; // --dry-run: each selected job's state
  auto settle = [&](const JobSpec& j, std::optional<JobState> st) {
    const bool failing =
        st == JobState::failed || st == JobState::diverged || st == JobState::timeout;
    if (!st || st == JobState::pending || (failing && opts.retry_failed)) {
      tally.add(j);
      ++n_to_run;
    }
    if (opts.dry_run)
      listed.push_back(st);
  };
  std::vector<JobSpec> batch;
  auto settle_batch = [&] {
    std::vector<std::string> keys;
    for (const auto& j : batch)
      keys.push_back(j.key);
    std::map<std::string, JobState> states;
    try {
      if (ro)
        states = ro->states_of(keys);
    } catch (const std::exception&) {
      unreadable();
    }
    for (const auto& j : batch) {
      auto it = states.find(j.key);
      settle(j, it == states.end() ? std::nullopt : std::optional<JobState>(it->second));
    }
    batch.clear();
  };
  const Survey sv = survey(sel, [&](const JobSpec& j) {
    if (!ro)
      return settle(j, std::nullopt);
    batch.push_back(j);
    if (batch.size() >= 4096)
      settle_batch();
  });
  settle_batch();
  ro.reset(); // the reader is done
  const ExpansionSummary& ex = sv.summary;
  const bool filtered = sv.n_selected != ex.size;
  const StudyEstimate cost = tally.result();
  const std::size_t est_workers =
      std::min<std::size_t>(opts.jobs > 0 ? static_cast<std::size_t>(opts.jobs)
                                          : std::max(1u, std::thread::hardware_concurrency()),
                            std::max<std::size_t>(n_to_run, 1));
  auto print_estimate = [&] {
    if (n_to_run == 0)
      return;
    if (cost.estimated == 0) {
      out << "estimate: unknown for the " << n_to_run << " job(s) to run\n";
      for (const auto& b : cost.basis)
        out << "  " << b << "\n";
      return;
    }
    out << "estimate: " << format_cost(cost.cpu_s) << " for " << cost.estimated << " of the "
        << n_to_run << " job(s) to run, about " << format_cost(cost.wall_s(est_workers), "wall")
        << " on this machine with " << est_workers << " at once";
    if (cost.unknown)
      out << " (" << cost.unknown << " job(s) without an estimate)";
    out << "\n";
    for (const auto& b : cost.basis)
      out << "  " << b << "\n";
  };

  if (opts.dry_run) {
    out << title << ": " << ex.size << " jobs (" << ex.combinations << " combinations, "
        << ex.excluded << " excluded, " << ex.duplicates << " duplicates collapsed)\n";
    if (filtered)
      out << sv.n_selected << " of them match" << where_text << " (listed below)\n";
    if (ex.size) {
      std::string fixed;
      for (const auto& [k, v] : sv.first)
        if (std::find(ex.varying.begin(), ex.varying.end(), k) == ex.varying.end())
          fixed += " " + k + "=" + format_value_plain(v);
      out << "fixed:" << fixed << "\n";
    }
    // A second pass lists the selected jobs.
    std::string lines;
    JobStream jobs = sel.jobs();
    JobSpec j;
    for (std::size_t ordinal = 0, k = 0; jobs.next(j); ++ordinal) {
      if (!sv.selected[ordinal])
        continue;
      const auto& st = listed[k++];
      char buf[16];
      std::snprintf(buf, sizeof buf, "%-8s", st ? to_string(*st) : "new");
      lines += buf;
      lines += ' ';
      lines += label_of(j, ex.varying);
      lines += '\n';
      if (lines.size() > (1u << 16)) {
        out << lines;
        lines.clear();
      }
    }
    out << lines;
    print_estimate();
    return 0;
  }
  if (cost.wall_s(est_workers) > 3600 && !opts.yes) {
    print_estimate();
    throw StudyError(
        {{study.file, 0, 0,
          "this run is estimated at " + format_cost(cost.wall_s(est_workers), "wall") + " (" +
              format_cost(cost.cpu_s) + ") on this machine, more than an hour: nothing was run. " +
              (study.file.empty()
                   ? std::string("Run it with --yes")
                   : "Run it with --yes, or a shorter tier (--tier " +
                         (study.tier_names().empty() ? std::string("NAME")
                                                     : study.tier_names().front()) +
                         "), or on a cluster (runner submit " + study.file + " --slurm)")}});
  }
  print_estimate();

  // SIGINT, SIGTERM, SIGHUP (closed terminal) and SIGPIPE (`runner ... | head`) stop the run
  // cleanly from here on: no new claims, running jobs stopped and put back to pending.
  SignalGuard guard;
  const std::string host = host_name();
  const int pid = static_cast<int>(getpid());
  const std::string fingerprint = solver_fingerprint(study.case_name);
  Store store = Store::open_write(opts.db_path, opts.allow_network_fs);
  const std::string db_name = opts.db_path.string();
  // Any SQLite error from here on names the database (disk full, I/O error, locked too long).
  auto db_error = [&](const std::exception& e) {
    return std::runtime_error("database '" + db_name + "': " + e.what());
  };
  SweepStart front;
  try {
    front = start_sweep(
        store, study, sel,
        {opts.retry_failed, opts.max_attempts, opts.rerun_stale, opts.stale_after_s}, out);
    store.checkpoint_wal(false);
  } catch (const SqliteError& e) {
    throw db_error(e);
  }
  const auto& stale = front.recovered;
  if (!stale.empty()) {
    out << "recovered " << stale.size() << " job(s) left running by a dead runner:";
    for (std::size_t i = 0; i < stale.size() && i < 5; ++i)
      out << "\n  " << stale[i].key.substr(0, 12) << " " << stale[i].reason;
    out << "\n";
    if (front.integrity != "ok")
      err << "warning: database integrity check after an unclean shutdown: " << front.integrity
          << "\n";
  }
  if (const auto& ing = front.ingested; ing && (ing->ingested || ing->lost || ing->waiting))
    out << "Slurm: ingested " << ing->ingested << " finished job(s), " << ing->lost
        << " lost (pending again), " << ing->waiting << " still submitted\n";
  const SyncReport& sync = front.sync;
  std::vector<const JobRow*> todo;
  for (const JobRow* row : front.todo)
    if (sv.selected[row->ordinal])
      todo.push_back(row);
  const std::size_t stale_requeued = sync.stale_requeued, stale_kept = sync.stale_kept;

  std::map<JobState, std::size_t> counts;
  for (const auto& row : sync.jobs)
    ++counts[row.state];
  auto count = [&](JobState s) { return counts.count(s) ? counts[s] : std::size_t(0); };
  std::size_t failing =
      count(JobState::failed) + count(JobState::timeout) + count(JobState::diverged);
  out << title << ": " << ex.size << " jobs: " << count(JobState::done) << " done already, ";
  if (failing && !opts.retry_failed)
    out << failing << " failed/diverged/timed out (not retried; use --retry-failed), ";
  if (count(JobState::running))
    out << count(JobState::running) << " running elsewhere, ";
  out << todo.size() << " to run";
  if (sync.inserted)
    out << " (" << sync.inserted << " new)";
  if (filtered)
    out << "; only the " << sv.n_selected << " job(s) matching" << where_text
        << " run, the others stay as they are";
  out << "\n";
  if (stale_kept)
    out << "note: " << stale_kept << " finished job(s) are stale: made by other solver code "
        << "(fingerprint differs from this build's " << fingerprint
        << "); kept as they are, --rerun-stale recomputes them\n";
  if (stale_requeued)
    out << "recomputing " << stale_requeued << " stale job(s) (--rerun-stale)\n";
  if (sync.requeued)
    out << "retrying " << sync.requeued << " failed job(s)\n";
  if (sync.exhausted)
    out << sync.exhausted << " failed job(s) reached --max-attempts " << opts.max_attempts
        << " and stay failed\n";
  if (sync.removed)
    out << "note: " << sync.removed << " job(s) of an earlier version of this study are no "
        << "longer in it (their results stay in the database)\n";
  if (sync.definition_changed && !sync.study_is_new)
    out << "note: the study file changed since the last run\n";

  std::size_t n_workers = opts.jobs > 0 ? static_cast<std::size_t>(opts.jobs)
                                        : std::max(1u, std::thread::hardware_concurrency());
  n_workers = std::min(n_workers, std::max<std::size_t>(todo.size(), 1));

  const fs::path db_dir =
      opts.db_path.parent_path().empty() ? fs::path(".") : opts.db_path.parent_path();
  const fs::path scratch_base = db_dir / ".runner";
  const fs::path scratch = scratch_base / (host + "-" + std::to_string(pid));
  std::size_t ran = 0, interrupted = 0, lost = 0, busy = 0;
  std::vector<std::string> failures;
  auto t_start = std::chrono::steady_clock::now();

  if (!todo.empty() && g_stop.load() == 0) {
    clean_dead_scratch(scratch_base, host);
    fs::create_directories(scratch);
    Channel ch;
    std::vector<std::thread> workers;
    std::map<std::int64_t, Task> running;
    // Stops the pool whatever happens below (an SQLite error, a full disk): the workers' job
    // processes are stopped, the threads joined, and the running jobs given back when the
    // database still takes a write (otherwise the next run recovers them: their owner is gone).
    auto stop_pool = [&](const std::string& reason) {
      g_stop.fetch_add(1);
      ch.close();
      for (auto& w : workers)
        if (w.joinable())
          w.join();
      for (Outcome& o : ch.wait_outcomes(std::chrono::milliseconds(0))) {
        try {
          store.release(o.task.job_id, o.task.attempt, host, pid, reason, unix_now());
        } catch (const std::exception&) {
        }
        running.erase(o.task.job_id);
      }
      for (auto& [id, t] : running) {
        try {
          store.release(id, t.attempt, host, pid, reason, unix_now());
        } catch (const std::exception&) {
        }
      }
      for (auto& [id, t] : running)
        release_folder_lock(t);
      running.clear();
      std::error_code ec;
      fs::remove_all(scratch, ec);
      fs::remove(scratch_base, ec);
    };
    for (std::size_t w = 0; w < n_workers; ++w)
      workers.emplace_back([&] {
        while (auto t = ch.pop_task()) {
          ChildRequest req;
          req.exe = opts.self_exe;
          req.args = {"job",
                      "--spec",
                      t->spec.string(),
                      "--out",
                      t->result.string(),
                      "--die-with-parent",
                      "--parent-pid",
                      std::to_string(::getpid())};
          req.env = job_environment(opts.threads_per_job);
          req.log_path = t->log;
          ChildOutcome c = run_child(req, opts.timeout_s, g_stop, opts.kill_grace_s);
          ch.push_outcome({std::move(*t), std::move(c)});
        }
      });

    bool live = opts.live_progress.value_or(isatty(STDOUT_FILENO) != 0);
    Progress progress(out, live, todo.size(), n_workers);
    progress.set_width(terminal_columns());
    progress.set_log_every_s(opts.log_every_s);
    try {
      // Mean wall time of this study's earlier finished attempts: the ETA before a job finishes.
      // Without any, the cost model's mean estimate per job (CPU time over the job's threads).
      if (auto prior = store.mean_wall_s(sync.study_id, tier))
        progress.set_prior_job_s(*prior);
      const double per_thread = 1.0 / std::max(opts.threads_per_job, 1);
      progress.set_plan(cost.cpu_s * per_thread, cost.estimated);
      AttemptStart start{host,          pid, opts.threads_per_job, code_version(),
                         compiler_id(), 0,   fingerprint,          std::nullopt};
      std::size_t next = 0;
      JobCursor cursor(sel.jobs()); // the to-do list is in expansion order
      auto last_heartbeat = std::chrono::steady_clock::now();
      auto last_checkpoint = last_heartbeat;
      store.wal_files_changed(); // notes the -wal and -shm files it uses (checked at heartbeats)

      for (;;) {
        while (g_stop.load() == 0 && running.size() < n_workers && next < todo.size()) {
          const JobRow& row = *todo[next++];
          const JobSpec& job = cursor.at(row.ordinal);
          start.started_at = unix_now();
          start.predicted_cpu_s = estimate_job(job, samples);
          auto attempt = store.claim(row.id, start);
          std::optional<double> predicted;
          if (start.predicted_cpu_s)
            predicted = *start.predicted_cpu_s * per_thread;
          progress.job_started(predicted);
          if (!attempt)
            continue; // another runner took it
          Task t;
          t.started = std::chrono::steady_clock::now();
          t.predicted_s = predicted;
          t.label = label_of(job, ex.varying);
          t.running_label = running_label(job, ex.varying);
          t.job_id = row.id;
          t.attempt = *attempt;
          std::string stem = job.key + "." + std::to_string(*attempt);
          t.spec = scratch / (stem + ".spec.json");
          t.result = scratch / (stem + ".result.json");
          t.log = scratch / (stem + ".log");
          t.progress = scratch / (stem + ".progress");
          t.output_dir = db_dir / study.name / job.key;
          JobFileSpec spec{job.key,
                           job.case_name,
                           job.scheme,
                           job.params,
                           opts.threads_per_job,
                           *attempt,
                           t.output_dir.string(),
                           t.progress.string(),
                           opts.checkpoint_every_steps,
                           opts.checkpoint_every_s};
          std::string holder;
          try {
            fs::create_directories(t.output_dir);
            t.alias = alias_of(t.output_dir, job, ex.varying);
            make_alias(t.alias, t.output_dir, err);
            if (!take_folder_lock(t, &holder)) {
              // Another attempt (a runner that was stopped, or on another host sharing this
              // folder) still works in the job's folder: never two attempts in one folder.
              store.release(row.id, *attempt, host, pid,
                            "interrupted: the job's output folder " + t.output_dir.string() +
                                " is in use by another attempt" + holder,
                            unix_now());
              ++busy;
              err << "warning: job " << job.key.substr(0, 12) << ": its output folder is in use "
                  << "by another attempt" << holder << "; left pending\n";
              continue;
            }
            t.record = {job.key,      study.name,      tier,     job.case_name, job.scheme,
                        job.params,   job.params_json, *attempt, host,          start.started_at,
                        std::nullopt, "running"};
            write_file_atomic(t.spec, spec_to_json(spec));
          } catch (const SqliteError&) {
            release_folder_lock(t);
            throw;
          } catch (const std::exception& e) {
            release_folder_lock(t);
            Finish f;
            f.state = JobState::failed;
            f.failure_class = "spawn";
            f.finished_at = unix_now();
            f.error_text = std::string("cannot prepare the job: ") + e.what();
            store.finish(row.id, *attempt, host, pid, f);
            progress.finished("failed", t.label, f.error_text);
            failures.push_back(t.label + ": " + f.error_text);
            continue;
          }
          running.emplace(row.id, t);
          ch.push_task(std::move(t));
        }
        progress.set_running(running.size());
        if (running.empty() && (next >= todo.size() || g_stop.load() > 0))
          break;

        for (Outcome& o : ch.wait_outcomes(std::chrono::milliseconds(100))) {
          const std::string& label = o.task.label;
          std::error_code ec;
          bool cancelled_result = false;
          if (g_stop.load() > 0 && o.child.stopped) {
            try {
              auto r = read_result_file(o.task.result);
              cancelled_result = !r || r->status == "cancelled" || r->status == "failed";
            } catch (...) {
              cancelled_result = true;
            }
          }
          if (cancelled_result) {
            if (!is_empty_dir(o.task.output_dir)) // e.g. the checkpoint it resumes from
              finish_record(o.task, "interrupted", unix_now(), err);
            store.release(o.task.job_id, o.task.attempt, host, pid,
                          "interrupted: the runner received " + signal_description(g_signal.load()),
                          unix_now());
            ++interrupted;
          } else {
            std::string first_metric;
            Finish f = outcome_to_finish(o.child, o.task.result, o.task.log, opts.timeout_s);
            if (!f.metrics.empty())
              first_metric = f.metrics.front().first + "=" + short_number(f.metrics.front().second);
            unlink_folder_lock(o.task);
            if (!holds_result(f.state) || opts.keep_logs) {
              // Keep the full output of a failed attempt (of every one with --keep-logs) next
              // to its outputs.
              fs::path kept =
                  o.task.output_dir / ("attempt-" + std::to_string(o.task.attempt) + ".log");
              fs::rename(o.task.log, kept, ec);
              if (!ec && !holds_result(f.state))
                f.error_text += "\n(full output: " + kept.string() + ")";
            }
            // A folder with something in it (outputs, a checkpoint, a log) describes itself in
            // params.json and is recorded; an empty one is removed (patch_test writes nothing).
            if (!is_empty_dir(o.task.output_dir)) {
              finish_record(o.task, to_string(f.state), f.finished_at, err);
              f.output_dir = o.task.output_dir.string();
            } else {
              fs::remove(o.task.output_dir, ec);
              fs::remove(o.task.alias, ec);
            }
            if (!store.finish(o.task.job_id, o.task.attempt, host, pid, f)) {
              ++lost;
              err << "warning: job " << o.task.record.key.substr(0, 12)
                  << " was taken over by another runner; its result was discarded\n";
            }
            ++ran;
            std::string detail = short_number(o.child.wall_s) + " s";
            if (!first_metric.empty())
              detail += "  " + first_metric;
            if (f.state == JobState::diverged && !f.message.empty())
              detail += "  " + f.message;
            if (!holds_result(f.state)) {
              std::string first_line = f.error_text.substr(0, f.error_text.find('\n'));
              detail += "  " + first_line;
              failures.push_back(label + ": " + first_line);
            }
            progress.finished(to_string(f.state), label, detail, o.child.wall_s,
                              o.task.predicted_s);
          }
          release_folder_lock(o.task);
          running.erase(o.task.job_id);
          fs::remove(o.task.spec, ec);
          fs::remove(o.task.result, ec);
          fs::remove(o.task.log, ec);
          fs::remove(o.task.progress, ec);
        }
        progress.set_running(running.size());
        {
          // Each running job's simulated-time fraction, as its worker last wrote it (<= 1/s).
          std::vector<ProgressJob> fr;
          const auto now = std::chrono::steady_clock::now();
          for (auto& [id, t] : running) {
            const std::optional<double> f = read_progress(t.progress);
            if (f && !t.first_fraction)
              t.first_fraction = *f;
            fr.push_back({t.running_label, f.value_or(0.0),
                          std::chrono::duration<double>(now - t.started).count(), t.predicted_s,
                          t.first_fraction.value_or(0.0)});
          }
          progress.set_running_jobs(std::move(fr));
        }
        progress.tick();

        auto now = std::chrono::steady_clock::now();
        if (std::chrono::duration<double>(now - last_heartbeat).count() >= opts.heartbeat_s) {
          last_heartbeat = now;
          std::vector<std::pair<std::int64_t, std::optional<double>>> hb;
          for (const auto& [id, t] : running)
            hb.emplace_back(id, read_progress(t.progress));
          // Its -wal or -shm file removed under it, this runner would record results no other
          // runner sees (and they would run the jobs again): stop before writing more.
          if (std::string changed = store.wal_files_changed(); !changed.empty())
            throw std::runtime_error(
                changed + " while this runner used it: what it recorded since the last "
                          "checkpoint of the -wal file is not in the database file. Stop every "
                          "runner on this database, check it (runner query \"PRAGMA "
                          "integrity_check\"), then run again");
          store.heartbeat(hb, host, pid, unix_now());
        }
        if (std::chrono::duration<double>(now - last_checkpoint).count() >= 30) {
          last_checkpoint = now;
          store.checkpoint_wal(false); // keeps the -wal file small during a long sweep
        }
      }
    } catch (const std::exception& e) {
      progress.close();
      const bool sqlite = dynamic_cast<const SqliteError*>(&e) != nullptr;
      const std::size_t n_running = running.size();
      stop_pool(std::string("interrupted: the runner stopped on an error: ") + e.what());
      std::string what = sqlite ? "database '" + db_name + "': " + e.what() : e.what();
      throw std::runtime_error(
          what + "; the sweep stopped" +
          (n_running ? " (" + std::to_string(n_running) +
                           " running job(s) stopped: put back to pending, or recovered by the "
                           "next run)"
                     : std::string()) +
          "; every result recorded before is kept" +
          (sqlite && (dynamic_cast<const SqliteError&>(e).code() & 0xff) == SQLITE_FULL
               ? "; free space on the disk that holds '" + db_name + "' and run again"
               : std::string()));
    }
    ch.close();
    for (auto& w : workers)
      w.join();
    progress.close();
    std::error_code ec;
    fs::remove_all(scratch, ec);
    fs::remove(scratch_base, ec);        // only when empty (other runners may be using it)
    fs::remove(db_dir / study.name, ec); // only when no job kept outputs or logs
  }

  // Summary from the store: the state of every job of the study (tier).
  std::map<JobState, std::size_t> final_counts;
  try {
    final_counts = store.state_counts(sync.study_id, tier);
    store.checkpoint_wal(true);
  } catch (const SqliteError& e) {
    throw db_error(e);
  }
  double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  out << title << ": " << ex.size << " jobs:";
  bool first = true;
  for (JobState s : {JobState::done, JobState::diverged, JobState::failed, JobState::timeout,
                     JobState::running, JobState::pending})
    if (final_counts.count(s)) {
      out << (first ? " " : ", ") << final_counts[s] << " " << s;
      first = false;
    }
  if (ran)
    out << " (ran " << ran << " in " << format_duration(elapsed) << ")";
  out << "\n";
  for (std::size_t i = 0; i < failures.size() && i < 10; ++i)
    out << "  failed: " << failures[i] << "\n";
  if (failures.size() > 10)
    out << "  ... " << failures.size() - 10 << " more (runner status " << study.name << ")\n";
  if (interrupted || g_stop.load() > 0) {
    int sig = g_signal.load();
    out << "interrupted by " << signal_description(sig) << ": " << interrupted
        << " running job(s) put back to pending; run again to resume\n";
    return 128 + (sig ? sig : SIGINT);
  }
  if (lost || busy)
    return 1;
  // An attempt of this run that failed fails the run, also when its job keeps an earlier result.
  bool any_failed = final_counts.count(JobState::failed) || final_counts.count(JobState::timeout) ||
                    !failures.empty();
  return any_failed ? 1 : 0;
}

} // namespace sph::runner
