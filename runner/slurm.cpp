// Slurm job arrays: submit (manifest + one sbatch), the array task body, and ingestion of the
// tasks' outcome files into the store on the head node.
#include "slurm.hpp"

#include "executor.hpp"
#include "expand.hpp"
#include "job_file.hpp"
#include "process.hpp"
#include "provenance.hpp"
#include "store.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace sph::runner {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

inline constexpr const char* manifest_format = "sph-slurm-manifest/1";
inline constexpr const char* outcome_format = "sph-task-outcome/1";

std::atomic<int> g_task_stop{0};
extern "C" void on_task_term(int) {
  g_task_stop.store(1);
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s)
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

struct Cmd {
  int code = -1;
  std::string out;
};

// Runs a shell command, capturing stdout and stderr.
Cmd shell(const std::string& cmd) {
  Cmd r;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p)
    return r;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0)
    r.out.append(buf, n);
  int st = pclose(p);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

std::string trim(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())))
    s.pop_back();
  return s;
}

// Moves the contents of directory src into dest (created), replacing entries of the same name,
// then removes src. Renames where possible; copies across file systems.
void move_outputs(const fs::path& src, const fs::path& dest) {
  std::error_code ec;
  if (src.empty() || !fs::is_directory(src, ec) || fs::equivalent(src, dest, ec))
    return;
  fs::create_directories(dest, ec);
  for (const auto& e : fs::directory_iterator(src, ec)) {
    fs::path to = dest / e.path().filename();
    std::error_code rc;
    fs::remove_all(to, rc);
    fs::rename(e.path(), to, rc);
    if (rc) { // another file system: copy, then remove the source
      fs::copy(e.path(), to, fs::copy_options::recursive | fs::copy_options::overwrite_existing,
               rc);
      if (!rc)
        fs::remove_all(e.path(), rc);
    }
  }
  fs::remove(src, ec); // only when empty
}

// Slurm's time limit in minutes for a task of n jobs: each job's limit plus a margin.
int time_limit_minutes(std::optional<double> timeout_s, int n) {
  if (!timeout_s)
    return 0;
  double s = (*timeout_s + 10) * n + 60;
  return static_cast<int>(s / 60) + 1;
}

} // namespace

int cmd_submit(const Study& study, const SubmitOptions& opts, std::ostream& out,
               std::ostream& err) {
  if (opts.jobs_per_task < 1)
    throw std::runtime_error("--jobs-per-task must be at least 1");
  RunOptions ro; // --set and --where as for a local run
  ro.tier = opts.tier;
  ro.max_jobs = opts.max_jobs;
  ro.set = opts.set;
  ro.where = opts.where;
  const Selection sel = select_jobs(study, ro);
  const Survey sv = survey(sel); // every job valid, before anything is written
  const std::string tier = sel.label;
  Store store = Store::open_write(opts.db_path);
  const std::string host = host_name();
  const int pid = static_cast<int>(getpid());
  const std::string fingerprint = solver_fingerprint(study.case_name);
  SweepStart front = start_sweep(store, study, sel,
                                 {opts.retry_failed, opts.max_attempts, opts.rerun_stale, 30}, out);
  if (const auto& ing = front.ingested; ing && (ing->ingested || ing->lost))
    out << "ingested " << ing->ingested << " finished Slurm job(s)"
        << (ing->lost ? ", " + std::to_string(ing->lost) + " lost (pending again)" : "") << "\n";
  const SyncReport& sync = front.sync;
  if (sync.stale_requeued)
    out << "resubmitting " << sync.stale_requeued << " stale job(s) (--rerun-stale)\n";
  else if (auto n = sync.stale_kept)
    out << "note: " << n << " finished job(s) are stale: made by other solver code (fingerprint "
        << "differs from this build's " << fingerprint
        << "); kept as they are, --rerun-stale resubmits them\n";
  std::vector<const JobRow*> todo; // the pending jobs --where selects
  for (const JobRow* row : front.todo)
    if (sv.selected[row->ordinal])
      todo.push_back(row);
  std::size_t submitted_already = 0, done = 0;
  for (const auto& row : sync.jobs) {
    if (row.state == JobState::submitted)
      ++submitted_already;
    else if (row.state == JobState::done)
      ++done;
  }
  const std::string title = study.name + (tier == full_tier ? "" : " [" + tier + "]");
  out << title << ": " << sv.summary.size << " jobs: " << done << " done, " << submitted_already
      << " already submitted, " << todo.size() << " to submit\n";
  if (todo.empty())
    return 0;

  const fs::path db_dir =
      fs::absolute(opts.db_path.parent_path().empty() ? fs::path(".") : opts.db_path.parent_path());
  fs::path base = opts.slurm_dir.empty() ? db_dir / "slurm" : fs::absolute(opts.slurm_dir);
  fs::path exe = fs::canonical(opts.self_exe);

  // Record the submission first: its id names the directory.
  const std::size_t n_tasks = (todo.size() + static_cast<std::size_t>(opts.jobs_per_task) - 1) /
                              static_cast<std::size_t>(opts.jobs_per_task);
  fs::path dir;
  const std::int64_t sub_id = store.create_submission(
      sync.study_id, tier, todo.size(), n_tasks, unix_now(),
      [&](std::int64_t id) { return dir = base / (study.name + "-" + std::to_string(id)); });
  fs::create_directories(dir / "specs");
  fs::create_directories(dir / "results");
  fs::create_directories(dir / "logs");

  // Mark the jobs submitted (attempt +1, attempt row `running` on host "slurm") and write specs,
  // then the manifest, in the store's transaction.
  json tasks = json::array();
  json task = json::array();
  std::vector<std::int64_t> ids;
  for (const JobRow* row : todo)
    ids.push_back(row->id);
  AttemptStart start{host,          pid,        opts.threads_per_job, code_version(),
                     compiler_id(), unix_now(), fingerprint,          std::nullopt};
  JobCursor cursor(sel.jobs()); // the to-do list is in expansion order
  auto on_marked = [&](std::size_t k, int attempt) {
    const JobSpec& job = cursor.at(todo[k]->ordinal);
    std::string stem = job.key + "." + std::to_string(attempt);
    // Outputs (HDF5 series, checkpoints) go to the shared directory the nodes see; ingestion
    // moves a finished job's outputs to <db dir>/<study>/<key>, as a local run leaves them.
    // Keyed by job, not by submission: a resubmitted job resumes from its checkpoint there.
    fs::path output_dir = base / "outputs" / study.name / job.key;
    fs::create_directories(output_dir);
    JobFileSpec spec{job.key,
                     job.case_name,
                     job.scheme,
                     job.params,
                     opts.threads_per_job,
                     attempt,
                     output_dir.string(),
                     "",
                     opts.checkpoint_every_steps,
                     opts.checkpoint_every_s};
    write_file_atomic(dir / "specs" / (stem + ".spec.json"), spec_to_json(spec));
    task.push_back({{"key", job.key}, {"attempt", attempt}, {"stem", stem}});
    if (task.size() == static_cast<std::size_t>(opts.jobs_per_task)) {
      tasks.push_back(task);
      task = json::array();
    }
  };
  auto write_manifest = [&]() -> std::size_t {
    if (!task.empty())
      tasks.push_back(task);
    json manifest = {{"format", manifest_format},
                     {"study", study.name},
                     {"tier", tier},
                     {"submission", sub_id},
                     {"dir", dir.string()},
                     {"runner", exe.string()},
                     {"threads", opts.threads_per_job},
                     {"timeout_s", opts.timeout_s ? json(*opts.timeout_s) : json()},
                     {"tasks", tasks}};
    write_file_atomic(dir / "manifest.json", manifest.dump(1) + "\n");
    return tasks.size();
  };
  const std::vector<std::pair<std::int64_t, int>> marked =
      store.mark_submitted(ids, start, sub_id, on_marked, write_manifest);
  if (marked.empty()) {
    out << "nothing to submit (another runner took the jobs)\n";
    return 0;
  }

  // The batch script: one array task per group of jobs.
  std::ostringstream script;
  script << "#!/bin/sh\n"
         << "#SBATCH --job-name=sph-" << study.name << "\n"
         << "#SBATCH --array=0-" << tasks.size() - 1;
  if (opts.array_limit > 0)
    script << "%" << opts.array_limit;
  script << "\n#SBATCH --output=" << (dir / "logs" / "task-%A_%a.out").string() << "\n"
         << "#SBATCH --cpus-per-task=" << opts.threads_per_job << "\n";
  if (int minutes = time_limit_minutes(opts.timeout_s, opts.jobs_per_task))
    script << "#SBATCH --time=" << minutes << "\n";
  if (!opts.partition.empty())
    script << "#SBATCH --partition=" << opts.partition << "\n";
  for (const auto& a : opts.sbatch_args)
    script << "#SBATCH " << a << "\n";
  script << "exec " << shell_quote(exe.string()) << " slurm-task --manifest "
         << shell_quote((dir / "manifest.json").string()) << " --task \"$SLURM_ARRAY_TASK_ID\"\n";
  write_file_atomic(dir / "job.sbatch", script.str());

  auto give_back = [&](const std::string& reason) {
    store.give_back_submitted(marked, reason, unix_now());
  };

  if (opts.dry_run) {
    give_back("dry run: not submitted");
    out << "wrote " << (dir / "job.sbatch").string() << " (" << marked.size() << " jobs in "
        << tasks.size() << " array tasks); not submitted (--dry-run)\n";
    return 0;
  }
  // sbatch, retried a few times: controllers under load answer with transient errors.
  Cmd sb;
  for (int i = 0; i < 4; ++i) {
    sb = shell("sbatch --parsable " + shell_quote((dir / "job.sbatch").string()));
    if (sb.code == 0)
      break;
    std::this_thread::sleep_for(std::chrono::seconds(1 << i));
  }
  std::string array_id = trim(sb.out);
  if (auto semi = array_id.find(';'); semi != std::string::npos)
    array_id = array_id.substr(0, semi);
  if (sb.code != 0 || array_id.empty() ||
      array_id.find_first_not_of("0123456789") != std::string::npos) {
    give_back("sbatch failed: " + trim(sb.out));
    err << "runner submit: sbatch failed (exit " << sb.code << "): " << trim(sb.out) << "\n";
    return 1;
  }
  {
    std::vector<std::size_t> task_of;
    for (std::size_t t = 0; t < tasks.size(); ++t)
      task_of.insert(task_of.end(), tasks[t].size(), t);
    store.record_array(sub_id, array_id, marked, task_of);
  }
  out << "submitted " << marked.size() << " jobs as Slurm array " << array_id << " ("
      << tasks.size() << " tasks"
      << (opts.array_limit > 0 ? ", at most " + std::to_string(opts.array_limit) + " at once" : "")
      << "); files in " << dir.string() << "\n";
  if (!opts.wait)
    return 0;
  for (;;) {
    std::this_thread::sleep_for(std::chrono::duration<double>(opts.poll_s));
    IngestReport r = ingest_slurm(store, out);
    const std::size_t left = store.count_submitted_in_array(array_id);
    if (r.ingested || r.lost)
      out << "ingested " << r.ingested << (r.lost ? ", lost " + std::to_string(r.lost) : "") << "; "
          << left << " still submitted\n"
          << std::flush;
    if (left == 0)
      break;
  }
  auto counts = store.state_counts(sync.study_id, tier);
  out << title << ":";
  for (const auto& [s, c] : counts)
    out << " " << c << " " << s;
  out << "\n";
  return counts.count(JobState::failed) || counts.count(JobState::timeout) ? 1 : 0;
}

int run_slurm_task(const fs::path& manifest_path, int task) {
  json m = json::parse(read_file(manifest_path));
  if (m.value("format", "") != manifest_format)
    throw std::runtime_error("'" + manifest_path.string() + "' is not a runner manifest");
  const auto& tasks = m.at("tasks");
  if (task < 0 || static_cast<std::size_t>(task) >= tasks.size())
    throw std::runtime_error("task " + std::to_string(task) + " out of range (manifest has " +
                             std::to_string(tasks.size()) + " tasks)");
  fs::path dir = m.at("dir").get<std::string>();
  std::optional<double> timeout;
  if (!m.at("timeout_s").is_null())
    timeout = m.at("timeout_s").get<double>();
  struct sigaction sa {};
  sa.sa_handler = on_task_term;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);
  std::string slurm_id;
  if (const char* a = std::getenv("SLURM_ARRAY_JOB_ID"))
    slurm_id = std::string(a) + "_" + std::to_string(task);
  else if (const char* j = std::getenv("SLURM_JOB_ID"))
    slurm_id = j;
  const std::string host = host_name();
  int rc = 0;
  for (const auto& job : tasks[static_cast<std::size_t>(task)]) {
    if (g_task_stop.load())
      return 128 + SIGTERM; // the remaining jobs stay submitted; ingest finds them lost
    std::string stem = job.at("stem").get<std::string>();
    fs::path spec = dir / "specs" / (stem + ".spec.json");
    fs::path result = dir / "results" / (stem + ".result.json");
    fs::path outcome = dir / "results" / (stem + ".outcome.json");
    fs::path log = dir / "logs" / (stem + ".log");
    if (fs::exists(outcome))
      continue; // done by an earlier run of this task (requeue)
    ChildRequest req;
    req.exe = m.at("runner").get<std::string>();
    req.args = {"job",           "--spec",
                spec.string(),   "--out",
                result.string(), "--die-with-parent",
                "--parent-pid",  std::to_string(::getpid())};
    req.env = job_environment(m.value("threads", 1));
    req.log_path = log;
    ChildOutcome c = run_child(req, timeout, g_task_stop, 5);
    // scancel signals every process of the task, the job too: a job stopped that way is not an
    // outcome (it stays submitted, and ingestion puts it back to pending once the array is gone).
    bool cancelled = false;
    try {
      auto r = read_result_file(result);
      cancelled = r && r->status == "cancelled" && !c.timed_out;
    } catch (...) {
    }
    if (c.stopped || g_task_stop.load() || cancelled)
      return 128 + SIGTERM;
    json o = {{"format", outcome_format},
              {"key", job.at("key")},
              {"attempt", job.at("attempt")},
              {"host", host},
              {"slurm_job_id", slurm_id},
              {"spawn_error", c.spawn_error},
              {"pid", c.pid},
              {"exited", c.exited},
              {"exit_code", c.exit_code},
              {"term_signal", c.term_signal},
              {"timed_out", c.timed_out},
              {"wall_s", c.wall_s},
              {"cpu_s", c.cpu_s},
              {"peak_rss_kb", c.peak_rss_kb}};
    try {
      write_file_atomic(outcome, o.dump(1) + "\n");
    } catch (const std::exception& e) {
      std::fprintf(stderr, "runner slurm-task: %s\n", e.what());
      rc = 1;
    }
  }
  return rc;
}

IngestReport ingest_slurm(Store& store, std::ostream& out) {
  IngestReport rep;
  // Jobs marked submitted by a `runner submit` that died before sbatch returned (or before it
  // recorded the array id): no array will report them, so they go back to pending.
  rep.lost += store.requeue_orphan_submissions(host_name(), static_cast<int>(getpid()), unix_now(),
                                               pid_alive);
  struct Sub {
    std::int64_t id;
    std::string array_id;
    fs::path dir;
    std::optional<double> timeout;
    std::string study, tier;
  };
  std::vector<Sub> subs;
  for (const Submission& s : store.open_submissions())
    subs.push_back({s.id, s.array_id, s.dir, std::nullopt, "", ""});
  for (auto& sub : subs) {
    try {
      json m = json::parse(read_file(sub.dir / "manifest.json"));
      if (!m.at("timeout_s").is_null())
        sub.timeout = m.at("timeout_s").get<double>();
      sub.study = m.value("study", "");
      sub.tier = m.value("tier", "");
    } catch (...) {
    }
    // Is the array still queued or running? Asked before reading outcomes, so that a job whose
    // outcome appears in between is not taken for lost.
    bool array_gone = false;
    if (!sub.array_id.empty()) {
      Cmd q = shell("squeue -h -r -j " + sub.array_id + " -o %i");
      if (q.code == 0 && trim(q.out).empty())
        array_gone = true;
      else if (q.out.find("Invalid job id") != std::string::npos)
        array_gone = true;
    }
    const std::vector<SubmittedJob> js = store.submitted_jobs_of_array(sub.array_id);
    const fs::path db_dir =
        store.path().parent_path().empty() ? fs::path(".") : store.path().parent_path();
    std::vector<std::pair<std::int64_t, int>> lost;
    for (const auto& j : js) {
      std::string stem = j.key + "." + std::to_string(j.attempt);
      fs::path outcome = sub.dir / "results" / (stem + ".outcome.json");
      fs::path result = sub.dir / "results" / (stem + ".result.json");
      fs::path log = sub.dir / "logs" / (stem + ".log");
      std::error_code ec;
      if (!fs::exists(outcome, ec)) {
        if (array_gone)
          lost.emplace_back(j.id, j.attempt);
        else
          ++rep.waiting;
        continue;
      }
      ChildOutcome c;
      std::string host = "?", slurm_id = j.slurm_job_id;
      try {
        json o = json::parse(read_file(outcome));
        c.spawn_error = o.value("spawn_error", "");
        c.pid = o.value("pid", 0);
        c.exited = o.value("exited", false);
        c.exit_code = o.value("exit_code", 0);
        c.term_signal = o.value("term_signal", 0);
        c.timed_out = o.value("timed_out", false);
        c.wall_s = o.value("wall_s", 0.0);
        c.cpu_s = o.value("cpu_s", 0.0);
        c.peak_rss_kb = o.value("peak_rss_kb", 0L);
        host = o.value("host", "?");
        if (auto s = o.value("slurm_job_id", std::string()); !s.empty())
          slurm_id = s;
      } catch (const std::exception& e) {
        c.spawn_error = "unreadable outcome file '" + outcome.string() + "': " + e.what();
      }
      Finish f = outcome_to_finish(c, result, log, sub.timeout);
      if (f.state != JobState::done && f.state != JobState::diverged)
        f.error_text += "\n(full output: " + log.string() + ")";
      {
        std::string study_name = sub.study;
        if (study_name.empty())
          study_name = store.a_study_of_job(j.id).value_or("");
        fs::path src;
        try {
          src = json::parse(read_file(sub.dir / "specs" / (stem + ".spec.json")))
                    .value("output_dir", std::string());
        } catch (...) {
        }
        if (!study_name.empty()) {
          fs::path d = fs::absolute(db_dir) / study_name / j.key;
          // A finished job's outputs join the database's side; a failed one's stay in the
          // shared directory, where its checkpoint awaits the resubmission.
          if (holds_result(f.state) && !src.empty())
            move_outputs(src, d);
          // params.json, as a local run writes it (the start time from the job's wall time),
          // in a folder that holds outputs.
          try {
            if (!fs::is_directory(d, ec) || fs::is_empty(d, ec))
              throw std::runtime_error("no outputs");
            JobFileSpec spec = read_spec_file(sub.dir / "specs" / (stem + ".spec.json"));
            JobRecord rec{j.key,         study_name,
                          sub.tier,      spec.case_name,
                          spec.scheme,   spec.params,
                          j.params_json, j.attempt,
                          host,          f.finished_at - f.wall_s.value_or(0),
                          f.finished_at, to_string(f.state)};
            write_job_record(d, rec);
          } catch (const std::exception&) {
            // no outputs, or the spec is gone: the database describes the job
          }
          if (fs::is_directory(d, ec) && !fs::is_empty(d, ec))
            f.output_dir = d.string();
          else
            fs::remove(d, ec);
        }
      }
      if (store.finish_submitted(j.id, j.attempt, host, slurm_id, f))
        ++rep.ingested;
      // Ingested (or stale): the files have done their job.
      fs::remove(outcome, ec);
      fs::remove(result, ec);
      fs::remove(sub.dir / "specs" / (stem + ".spec.json"), ec);
      if (f.state == JobState::done || f.state == JobState::diverged)
        fs::remove(log, ec);
    }
    if (!lost.empty()) {
      store.requeue_lost(lost,
                         "abandoned: Slurm array " + sub.array_id +
                             " left the queue without an outcome for this job (cancelled, time "
                             "limit, node failure)",
                         unix_now());
      rep.lost += lost.size();
    }
  }
  (void)out;
  return rep;
}

int cmd_ingest(const fs::path& db, std::ostream& out) {
  Store store = Store::open_write(db);
  IngestReport r = ingest_slurm(store, out);
  out << "ingested " << r.ingested << " job(s), " << r.lost << " lost (pending again), "
      << r.waiting << " still submitted\n";
  return 0;
}

} // namespace sph::runner
