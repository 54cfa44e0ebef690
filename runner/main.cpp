// The `runner` command line (CLI11): run a study (the default when the first argument is not a
// subcommand), query, status, cases, table, export, and the hidden `job` worker subcommand.
#include "commands.hpp"
#include "diagnostics.hpp"
#include "executor.hpp"
#include "job_worker.hpp"
#include "provenance.hpp"
#include "study.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <set>
#include <string>
#include <vector>

using namespace sph::runner;

int main(int argc, char** argv) {
  // A positional study file and subcommands clash in CLI11: treat `runner STUDY.toml ...` as
  // `runner run STUDY.toml ...`.
  static const std::set<std::string> subcommands = {
      "run", "job", "query", "status", "cases", "table", "export", "-h", "--help", "--version"};
  std::vector<std::string> args(argv, argv + argc);
  if (args.size() > 1 && !subcommands.count(args[1]))
    args.insert(args.begin() + 1, "run");

  CLI::App app{"SPH study runner: runs parameter studies of SPH cases and records every result "
               "in SQLite"};
  app.require_subcommand(1);
  app.set_version_flag("--version", code_version());
  const std::string default_db = "results/results.sqlite";

  RunOptions ro;
  std::string study_file, db_run = default_db;
  double timeout = 0;
  auto* run = app.add_subcommand("run", "Run a study (default: `runner STUDY.toml`)");
  run->add_option("study", study_file, "Study file (TOML)")->required();
  run->add_option("--db", db_run, "Database file")->capture_default_str();
  run->add_option("-j,--jobs", ro.jobs, "Jobs run in parallel (default: number of cores)")
      ->check(CLI::NonNegativeNumber);
  run->add_option("--tier", ro.tier, "Run a tier of the study ([tiers.NAME])");
  run->add_option("--threads-per-job", ro.threads_per_job, "OpenMP threads of each job")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  run->add_option("--timeout", timeout, "Wall-clock limit per job in seconds (0: none)")
      ->check(CLI::NonNegativeNumber);
  run->add_flag("--retry-failed", ro.retry_failed, "Re-run failed, diverged and timed-out jobs");
  run->add_option("--max-attempts", ro.max_attempts,
                  "With --retry-failed, leave jobs that failed this many times")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  run->add_flag("-n,--dry-run", ro.dry_run, "List the jobs and their state; run and write nothing");
  run->add_flag("--allow-network-fs", ro.allow_network_fs,
                "Accept a database on a network file system (rollback journal, one runner only)");

  std::string spec_file, out_file;
  bool die_with_parent = false;
  auto* job = app.add_subcommand("job", "Run one job from a job-spec file (internal)");
  job->group(""); // hidden
  job->add_option("--spec", spec_file)->required();
  job->add_option("--out", out_file)->required();
  job->add_flag("--die-with-parent", die_with_parent);

  std::string db_query = default_db, sql;
  auto* query = app.add_subcommand("query", "Run one SQL statement (read-only), print CSV");
  query->add_option("sql", sql, "SQL, e.g. \"SELECT * FROM job_metrics\"")->required();
  query->add_option("--db", db_query, "Database file")->capture_default_str();

  std::string db_status = default_db, status_study;
  auto* status = app.add_subcommand("status", "Job counts by state, running jobs, last errors");
  status->add_option("study", status_study, "Only this study");
  status->add_option("--db", db_status, "Database file")->capture_default_str();

  auto* cases = app.add_subcommand("cases", "List the cases and their parameters");

  TableOptions topt;
  std::string db_table = default_db;
  auto* table = app.add_subcommand("table", "Pivot a metric by two parameters");
  table->add_option("study", topt.study)->required();
  table->add_option("--rows", topt.rows, "Parameter for the rows")->required();
  table->add_option("--cols", topt.cols, "Parameter for the columns")->required();
  table->add_option("--value", topt.metric, "Metric")->required();
  table->add_option("--agg", topt.agg, "mean, min, max or count")->capture_default_str();
  table->add_option("--format", topt.format, "text or csv")->capture_default_str();
  table->add_option("--db", db_table, "Database file")->capture_default_str();

  std::string db_export = default_db, export_study, export_format = "csv";
  auto* exp = app.add_subcommand("export", "Export a study's jobs, parameters and metrics");
  exp->add_option("study", export_study)->required();
  exp->add_option("--format", export_format, "csv or json")->capture_default_str();
  exp->add_option("--db", db_export, "Database file")->capture_default_str();

  std::vector<const char*> cargs;
  for (const auto& a : args)
    cargs.push_back(a.c_str());
  try {
    app.parse(static_cast<int>(cargs.size()), cargs.data());
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    if (*job)
      return run_job_files(spec_file, out_file, die_with_parent);
    if (*run) {
      ro.db_path = db_run;
      if (timeout > 0)
        ro.timeout_s = timeout;
      Study study = load_study(study_file);
      return run_study(study, ro, std::cout, std::cerr);
    }
    if (*query)
      return cmd_query(db_query, sql, std::cout);
    if (*status)
      return cmd_status(db_status, status_study, std::cout);
    if (*cases)
      return cmd_cases(std::cout);
    if (*table)
      return cmd_table(db_table, topt, std::cout);
    if (*exp)
      return cmd_export(db_export, export_study, export_format, std::cout);
  } catch (const StudyError& e) {
    std::cerr << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "runner: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
