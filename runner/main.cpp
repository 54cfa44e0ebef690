// The `runner` command line (CLI11): run a study (the default when the first argument is not a
// subcommand), query, status, cases, table, export, and the hidden `job` worker subcommand.
#include "commands.hpp"
#include "diagnostics.hpp"
#include "executor.hpp"
#include "job_worker.hpp"
#include "overrides.hpp"
#include "provenance.hpp"
#include "report.hpp"
#include "search.hpp"
#include "slurm.hpp"
#include "store.hpp"
#include "study.hpp"

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <set>
#include <string>
#include <vector>

using namespace sph::runner;

namespace {

// A real option value: a finite number >= lo (> lo when exclusive), or a message saying what is
// allowed. CLI11's number checks let "nan" through (every comparison with NaN is false).
CLI::Validator finite_number(double lo, bool exclusive, const std::string& also = "") {
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%g", lo);
        const std::string allowed = std::string("a finite number ") + (exclusive ? "> " : ">= ") +
                                    buf + " (seconds)" + also;
        char* end = nullptr;
        double x = std::strtod(s.c_str(), &end);
        if (s.empty() || !end || *end != 0)
          return "'" + s + "' is not a number; expected " + allowed;
        if (!std::isfinite(x) || (exclusive ? x <= lo : x < lo))
          return "'" + s + "' is not allowed; expected " + allowed;
        return "";
      },
      "NUMBER");
}

// An integer option value in [lo, hi], or a message saying what is allowed.
CLI::Validator integer_in(long long lo, long long hi) {
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        const std::string allowed =
            "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
        errno = 0;
        char* end = nullptr;
        long long x = std::strtoll(s.c_str(), &end, 10);
        if (s.empty() || !end || *end != 0 || errno == ERANGE)
          return "'" + s + "' is not an integer; expected " + allowed;
        if (x < lo || x > hi)
          return "'" + s + "' is out of range; expected " + allowed;
        return "";
      },
      "INT");
}

// An option value that goes into a line of the Slurm script: one line, no control characters
// (a line break would start a line of shell in job.sbatch).
CLI::Validator one_script_line() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        for (unsigned char c : s)
          if (c < 0x20 || c == 0x7f)
            return "the value contains a line break or another control character; each value "
                   "is one #SBATCH line (e.g. --account=X): repeat the option for more";
        return "";
      },
      "TEXT");
}

// A --tier value: a tier's name (an empty one would silently mean the whole study).
CLI::Validator tier_name() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        return s.empty() ? "an empty tier name; omit --tier for the whole study" : "";
      },
      "NAME");
}

} // namespace

int main(int argc, char** argv) {
  // A positional study file and subcommands clash in CLI11: treat `runner STUDY.toml ...` as
  // `runner run STUDY.toml ...`.
  static const std::set<std::string> subcommands = {
      "report",     "run", "job",    "query",     "status",  "cases",
      "table",      "one", "export", "publish",   "submit",  "ingest",
      "slurm-task", "-h",  "--help", "--version", "converge"};
  std::vector<std::string> args(argv, argv + argc);
  if (args.size() > 1 && !subcommands.count(args[1]))
    args.insert(args.begin() + 1, "run");

  CLI::App app{"SPH study runner: runs parameter studies of SPH cases and records every result "
               "in SQLite"};
  app.require_subcommand(1);
  app.set_version_flag("--version", code_version());
  const std::string default_db = "results/results.sqlite";
  // More OpenMP threads than this in one job is a typo (each job crashed at 100,000).
  const long long max_threads_per_job = 1024;

  RunOptions ro;
  std::string study_file, db_run = default_db;
  double timeout = 0;
  auto* run = app.add_subcommand("run", "Run a study (default: `runner STUDY.toml`)");
  run->add_option("study", study_file, "Study file (TOML)")->required();
  run->add_option("--db", db_run, "Database file")->capture_default_str();
  run->add_option("-j,--jobs", ro.jobs, "Jobs run in parallel (default: number of cores)")
      ->check(integer_in(0, 4096));
  run->add_option("--tier", ro.tier, "Run a tier of the study ([tiers.NAME])")->check(tier_name());
  run->add_option("--threads-per-job", ro.threads_per_job, "OpenMP threads of each job")
      ->capture_default_str()
      ->check(integer_in(1, max_threads_per_job));
  run->add_option("--timeout", timeout, "Wall-clock limit per job in seconds (omit: none)")
      ->check(finite_number(0, true, "; omit --timeout for no limit"));
  run->add_flag("--retry-failed", ro.retry_failed, "Re-run failed, diverged and timed-out jobs");
  run->add_option("--max-attempts", ro.max_attempts,
                  "With --retry-failed, leave jobs that failed this many times")
      ->capture_default_str()
      ->check(integer_in(1, 1000000));
  run->add_flag("--rerun-stale", ro.rerun_stale,
                "Recompute finished jobs made by other solver code (stale; see runner status)");
  run->add_option("--max-jobs", ro.max_jobs,
                  "Refuse a study that expands to more jobs than this (counted before expanding)")
      ->capture_default_str()
      ->check(integer_in(1, 1000000000000LL));
  run->add_option("--checkpoint-every-steps", ro.checkpoint_every_steps,
                  "Jobs that support checkpoints save one every N steps (0: off)")
      ->check(integer_in(0, 1000000000000000LL));
  run->add_option("--checkpoint-every-s", ro.checkpoint_every_s,
                  "... and every S seconds of wall clock (0: off)")
      ->capture_default_str()
      ->check(finite_number(0, false, "; 0: off"));
  run->add_option("--heartbeat-s", ro.heartbeat_s, "Heartbeat/progress interval (tests)")
      ->group("")
      ->check(finite_number(0, true));
  run->add_option("--stale-after-s", ro.stale_after_s,
                  "Heartbeat age after which a job of another host is abandoned (tests)")
      ->group("")
      ->check(finite_number(0, true));
  std::string progress_mode = "auto";
  run->add_option("--progress", progress_mode,
                  "live: one line redrawn in place; plain: log lines; auto: live on a terminal")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "live", "plain"}));
  run->add_option("--log-every-s", ro.log_every_s,
                  "Plain progress: a progress line this often while jobs run")
      ->capture_default_str()
      ->check(finite_number(0, true));
  run->add_flag("-n,--dry-run", ro.dry_run, "List the jobs and their state; run and write nothing");
  run->add_flag("--allow-network-fs", ro.allow_network_fs,
                "Accept a database on a network file system (rollback journal, one runner only)");
  run->add_flag("-y,--yes", ro.yes,
                "Run even when the cost estimate exceeds an hour of wall time on this machine");
  run->add_flag("--keep-logs", ro.keep_logs,
                "Keep every attempt's output as <job folder>/attempt-N.log (default: failed only)");
  run->add_option("--set", ro.set,
                  "Override a parameter for every job, KEY=VALUE (repeatable; a new job where the "
                  "value differs), e.g. --set n_side=40");
  run->add_option("--where", ro.where,
                  "Run only the study's jobs with this value, KEY=VALUE (repeatable), e.g. "
                  "--where visc=visc03");

  RunOptions one_opt;
  std::string one_case, one_scheme, db_one = default_db;
  std::vector<std::string> one_params;
  double one_timeout = 0;
  auto* one = app.add_subcommand(
      "one", "Run one job of a case in the foreground, without a study file (study 'adhoc')");
  one->add_option("case", one_case, "Case (runner cases lists them)")->required();
  one->add_option("params", one_params, "Parameters, KEY=VALUE ... (e.g. visc=visc03 n_side=40)");
  one->add_option("--scheme", one_scheme, "Scheme (cases with schemes; default: the case's first)");
  one->add_option("--db", db_one, "Database file")->capture_default_str();
  one->add_option("--threads-per-job", one_opt.threads_per_job, "OpenMP threads of the job")
      ->capture_default_str()
      ->check(integer_in(1, max_threads_per_job));
  one->add_option("--timeout", one_timeout, "Wall-clock limit in seconds (omit: none)")
      ->check(finite_number(0, true, "; omit --timeout for no limit"));
  one->add_flag("-n,--dry-run", one_opt.dry_run, "Show the job and its state; run nothing");
  one->add_flag("-y,--yes", one_opt.yes, "Run even when the estimate exceeds an hour");
  one->add_flag("--retry-failed", one_opt.retry_failed,
                "Run the job again if it failed, diverged or timed out");
  one->add_flag("--rerun-stale", one_opt.rerun_stale,
                "Recompute the job if its result was made by other solver code (stale)");

  std::string spec_file, out_file;
  bool die_with_parent = false;
  int parent_pid = 0;
  auto* job = app.add_subcommand("job", "Run one job from a job-spec file (internal)");
  job->group(""); // hidden
  job->add_option("--spec", spec_file)->required();
  job->add_option("--out", out_file)->required();
  job->add_flag("--die-with-parent", die_with_parent);
  job->add_option("--parent-pid", parent_pid); // the process that started it (--die-with-parent)

  std::string db_query = default_db, sql;
  auto* query = app.add_subcommand("query", "Run one SQL statement (read-only), print CSV");
  query->add_option("sql", sql, "SQL, e.g. \"SELECT * FROM job_metrics\"")->required();
  query->add_option("--db", db_query, "Database file")->capture_default_str();
  double query_timeout = 600;
  query
      ->add_option("--timeout", query_timeout,
                   "Stop the query with an error after this many seconds (0: no limit)")
      ->capture_default_str()
      ->check(finite_number(0, false, "; 0: no limit"));

  std::string db_status = default_db, status_study;
  auto* status = app.add_subcommand("status", "Job counts by state, running jobs, last errors");
  status->add_option("study", status_study, "Only this study");
  status->add_option("--db", db_status, "Database file")->capture_default_str();

  auto* cases = app.add_subcommand("cases", "List the cases and their parameters; one case with "
                                            "its metrics and outputs");
  std::string cases_name;
  cases->add_option("case", cases_name, "Only this case, with its metrics and HDF5 datasets");

  TableOptions topt;
  std::string db_table = default_db;
  auto* table = app.add_subcommand("table", "Pivot a metric by two parameters");
  table->add_option("study", topt.study)->required();
  table->add_option("--rows", topt.rows, "Parameter for the rows")->required();
  table->add_option("--cols", topt.cols, "Parameter for the columns")->required();
  table->add_option("--value", topt.metric, "Metric")->required();
  table->add_option("--agg", topt.agg, "mean, median, min, max or count")->capture_default_str();
  table->add_option("--format", topt.format, "text, csv or markdown")->capture_default_str();
  table->add_option("--where", topt.where,
                    "Only jobs with this parameter value, KEY=VALUE (repeatable), e.g. "
                    "--where lattice=uniform");
  table->add_option("--db", db_table, "Database file")->capture_default_str();

  ConvergeOptions copt;
  std::string db_converge = default_db;
  double formal_order = 0;
  auto* converge = app.add_subcommand(
      "converge", "Observed order, Richardson-extrapolated value and grid-convergence index of a "
                  "metric over a resolution parameter, per group of the other parameters");
  converge->add_option("study", copt.study)->required();
  converge
      ->add_option("--param", copt.param,
                   "The resolution parameter: a spacing (dx) or a count (n_side, D_over_dx)")
      ->required();
  converge->add_option("--value", copt.metric, "Metric")->required();
  converge
      ->add_option("--kind", copt.kind,
                   "self: the metric converges to an unknown value (order from three "
                   "resolutions); error: the metric is an error against a reference (tends to 0)")
      ->capture_default_str();
  converge
      ->add_option("--resolution", copt.resolution,
                   "auto, spacing or count (count: spacing = 1/value; auto: count when every "
                   "value is a whole number >= 2)")
      ->capture_default_str();
  auto* formal = converge->add_option(
      "--formal-order", formal_order,
      "The order assumed where a group has only two resolutions (its GCI then uses Fs = 3)");
  converge->add_option("--format", copt.format, "text, csv or markdown")->capture_default_str();
  converge->add_option("--where", copt.where,
                       "Only jobs with this parameter value, KEY=VALUE (repeatable)");
  converge->add_option("--db", db_converge, "Database file")->capture_default_str();
  converge->add_option("--ignore", copt.ignore,
                       "A parameter whose values do not split the groups (repeatable), e.g. "
                       "--ignore t_end to put runs of different lengths in one sequence");
  converge->add_option("--published", copt.published,
                       "Read a published record (docs/results/STUDY.csv, written by `runner "
                       "publish`) instead of the database");

  std::string db_export = default_db, export_study, export_format = "csv";
  auto* exp = app.add_subcommand("export", "Export a study's jobs, parameters and metrics");
  exp->add_option("study", export_study)->required();
  exp->add_option("--format", export_format, "csv or json")->capture_default_str();
  exp->add_option("--db", db_export, "Database file")->capture_default_str();

  std::string db_publish = default_db, publish_study, publish_out;
  auto* publish = app.add_subcommand(
      "publish", "Write the committed record of a study's runs: docs/results/STUDY.csv, one row "
                 "per job and metric (rows of jobs not in this database are kept)");
  publish->add_option("study", publish_study)->required();
  publish->add_option("--out", publish_out, "CSV file (default: docs/results/STUDY.csv)");
  publish->add_option("--db", db_publish, "Database file")->capture_default_str();

  ReportOptions report_opt;
  report_opt.db = default_db;
  std::string report_db = default_db;
  auto* report = app.add_subcommand("report", "Write a study's figures and tables as an HTML page");
  report
      ->add_option("study", report_opt.study, "Study file, or the name of a study in the database")
      ->required();
  report->add_option("--db", report_db, "Database file")->capture_default_str();
  report->add_option("--out", report_opt.out_dir,
                     "Output directory (default: <db dir>/report/<study>)");
  report->add_option("--tier", report_opt.tier, "Only the jobs of this tier")->check(tier_name());
  report->add_option("--image-format", report_opt.image_format, "svg or png")
      ->capture_default_str();

  SubmitOptions so;
  std::string submit_file, db_submit = default_db;
  double submit_timeout = 0;
  bool use_slurm = false;
  auto* submit = app.add_subcommand("submit", "Run a study's pending jobs as a Slurm job array");
  submit->add_option("study", submit_file, "Study file (TOML)")->required();
  submit->add_flag("--slurm", use_slurm, "Submit to Slurm (the only back end)")->required();
  submit->add_option("--db", db_submit, "Database file (on the head node's local disk)")
      ->capture_default_str();
  submit->add_option("--tier", so.tier, "Submit a tier of the study")->check(tier_name());
  submit
      ->add_option("--array-limit", so.array_limit,
                   "Array tasks running at once (%K of --array; 0: no limit)")
      ->check(integer_in(0, 1000000));
  submit->add_option("--jobs-per-task", so.jobs_per_task, "Jobs run by each array task")
      ->capture_default_str()
      ->check(integer_in(1, 1000000));
  submit->add_option("--threads-per-job", so.threads_per_job, "OpenMP threads of each job")
      ->capture_default_str()
      ->check(integer_in(1, max_threads_per_job));
  submit->add_option("--timeout", submit_timeout, "Wall-clock limit per job in seconds")
      ->check(finite_number(0, true, "; omit --timeout for no limit"));
  submit->add_flag("--retry-failed", so.retry_failed, "Resubmit failed/diverged/timed-out jobs");
  submit->add_flag("--rerun-stale", so.rerun_stale,
                   "Resubmit finished jobs made by other solver code (stale)");
  submit
      ->add_option("--max-jobs", so.max_jobs,
                   "Refuse a study that expands to more jobs than this (counted before expanding)")
      ->capture_default_str()
      ->check(integer_in(1, 1000000000000LL));
  submit->add_option("--max-attempts", so.max_attempts, "With --retry-failed")
      ->capture_default_str()
      ->check(integer_in(1, 1000000));
  submit->add_option("--partition", so.partition, "Slurm partition")->check(one_script_line());
  submit->add_option("--sbatch-arg", so.sbatch_args, "Extra #SBATCH line (repeatable)")
      ->check(one_script_line());
  submit->add_option("--slurm-dir", so.slurm_dir,
                     "Directory for manifests, specs, results (shared with the nodes; default: "
                     "<db dir>/slurm)");
  submit
      ->add_option("--checkpoint-every-steps", so.checkpoint_every_steps,
                   "Jobs that support checkpoints save one every N steps (0: off)")
      ->check(integer_in(0, 1000000000000000LL));
  submit
      ->add_option("--checkpoint-every-s", so.checkpoint_every_s,
                   "... and every S seconds of wall clock (0: off)")
      ->capture_default_str()
      ->check(finite_number(0, false, "; 0: off"));
  submit->add_option("--set", so.set, "Override a parameter for every job, KEY=VALUE (repeatable)");
  submit->add_option("--where", so.where,
                     "Submit only the study's jobs with this value, KEY=VALUE (repeatable)");
  submit->add_flag("--wait", so.wait, "Wait for the array, ingesting results as they arrive");
  submit->add_flag("-n,--dry-run", so.dry_run, "Write the manifest and script, do not sbatch");

  std::string db_ingest = default_db;
  auto* ingest =
      app.add_subcommand("ingest", "Record finished Slurm jobs' results in the database");
  ingest->add_option("--db", db_ingest, "Database file")->capture_default_str();

  std::string manifest_file;
  int task_index = -1;
  auto* slurm_task = app.add_subcommand("slurm-task", "Run one Slurm array task (internal)");
  slurm_task->group(""); // hidden
  slurm_task->add_option("--manifest", manifest_file)->required();
  slurm_task->add_option("--task", task_index)->required();

  std::vector<const char*> cargs;
  for (const auto& a : args)
    cargs.push_back(a.c_str());
  try {
    app.parse(static_cast<int>(cargs.size()), cargs.data());
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  const int rc = [&]() -> int {
    try {
      if (*job)
        return run_job_files(spec_file, out_file, die_with_parent, parent_pid);
      if (*slurm_task)
        return run_slurm_task(manifest_file, task_index);
      if (*run) {
        ro.db_path = db_run;
        if (progress_mode != "auto")
          ro.live_progress = progress_mode == "live";
        if (timeout > 0)
          ro.timeout_s = timeout;
        Study study = load_study(study_file);
        if (study.search)
          return run_search(study, ro, std::cout, std::cerr);
        return run_study(study, ro, std::cout, std::cerr);
      }
      if (*one) {
        one_opt.db_path = db_one;
        one_opt.jobs = 1;
        one_opt.live_progress = false;
        if (one_timeout > 0)
          one_opt.timeout_s = one_timeout;
        Study adhoc = adhoc_study(one_case, one_scheme, one_params);
        return cmd_one(adhoc, one_opt, std::cout, std::cerr);
      }
      if (*submit) {
        so.db_path = db_submit;
        if (submit_timeout > 0)
          so.timeout_s = submit_timeout;
        Study study = load_study(submit_file);
        if (study.search)
          throw std::runtime_error(submit_file +
                                   ": a study with [search] runs its probes one round at a time "
                                   "and cannot be submitted as one array; run it with `runner "
                                   "run` (inside a Slurm allocation if need be)");
        return cmd_submit(study, so, std::cout, std::cerr);
      }
      if (*ingest)
        return cmd_ingest(db_ingest, std::cout);
      if (*query)
        return cmd_query(db_query, sql, std::cout, query_timeout);
      if (*status)
        return cmd_status(db_status, status_study, std::cout);
      if (*cases)
        return cmd_cases(std::cout, cases_name);
      if (*table)
        return cmd_table(db_table, topt, std::cout);
      if (*converge) {
        if (formal->count())
          copt.formal_order = formal_order;
        return cmd_converge(db_converge, copt, std::cout);
      }
      if (*report) {
        report_opt.db = report_db;
        return cmd_report(report_opt, std::cout);
      }
      if (*exp)
        return cmd_export(db_export, export_study, export_format, std::cout);
      if (*publish)
        return cmd_publish(db_publish, publish_study,
                           publish_out.empty() ? "docs/results/" + publish_study + ".csv"
                                               : publish_out,
                           std::cout);
    } catch (const StudyError& e) {
      std::cerr << e.what() << "\n";
      return 2;
    } catch (const SqliteError& e) {
      // A page found damaged in the middle of a command: name the file and what to do.
      int primary = e.code() & 0xff;
      std::string db = *run        ? db_run
                       : *one      ? db_one
                       : *submit   ? db_submit
                       : *ingest   ? db_ingest
                       : *query    ? db_query
                       : *status   ? db_status
                       : *table    ? db_table
                       : *converge ? db_converge
                       : *report   ? report_db
                       : *exp      ? db_export
                                   : std::string();
      if ((primary == SQLITE_CORRUPT || primary == SQLITE_NOTADB) && !db.empty())
        std::cerr << "runner: error: " << damaged_message(db, e.what(), false) << "\n";
      else if (!db.empty())
        std::cerr << "runner: error: database '" << db << "': " << e.what()
                  << (primary == SQLITE_FULL ? " (free space on its disk and run again)" : "")
                  << "\n";
      else
        std::cerr << "runner: error: " << e.what() << "\n";
      return 1;
    } catch (const std::exception& e) {
      std::cerr << "runner: error: " << e.what() << "\n";
      return 1;
    }
    return 0;
  }();
  if (*job || *slurm_task) // workers: their exit code says what became of the job
    return rc;
  // Every other command's output must reach its destination: when it cannot be written (a full
  // disk, /dev/full, a closed pipe) the output is incomplete and the command fails.
  std::cout.flush();
  errno = 0;
  const bool unwritten = !std::cout.good() || std::fflush(stdout) != 0 || std::ferror(stdout);
  if (!unwritten)
    return rc;
  const int err = errno;
  std::cerr << "runner: error: cannot write the output"
            << (err ? std::string(": ") + std::strerror(err) : std::string())
            << "; what was written is incomplete\n";
  return rc ? rc : 1;
}
