// Progress of a sweep. On a terminal: one live line (done/total, running, failed, diverged,
// elapsed, ETA, and each running job's simulated-time fraction), redrawn in place, with failures
// every finished job's line printed above it. Otherwise (a pipe, a log file, a batch job): one
// plain line per finished job, and a plain progress line every `log_every_s` seconds while jobs
// run, so a long job in a log is never silent.
//
// ETA, the work left divided by the workers (never less than the longest running job's rest):
// - a running job at simulated-time fraction f after e seconds has e (1 - f) / (f - f0) left (its
//   own rate since it started at f0: 0, or the fraction of the checkpoint it resumed from; once
//   f - f0 >= 2 %); before that, its cost-model estimate less e (scaled by 1 - f0);
// - a job not started, its cost-model estimate (cost.hpp);
// each estimate scaled by the ratio of measured to estimated time of the jobs finished in this run.
// A job without an estimate counts as the mean wall time of the jobs finished in this run (before
// the first one, of the study's earlier attempts in the database).
#pragma once

#include <chrono>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace sph::runner {

// A running job as the progress line sees it.
struct ProgressJob {
  std::string label;                 // short label (varying parameters)
  double fraction = 0;               // simulated-time fraction 0..1
  double elapsed_s = 0;              // wall seconds since it started
  std::optional<double> predicted_s; // the cost model's wall seconds for it
  double start_fraction = 0;         // fraction at the attempt's start (a resumed checkpoint)
};

class Progress {
public:
  Progress(std::ostream& out, bool live, std::size_t total, std::size_t workers = 1);
  // One job finished after wall_s seconds. `label` identifies it (key prefix and varying params),
  // `detail` is the timing and first metric or the error.
  // predicted_s: the cost model's wall seconds for it.
  void finished(const std::string& state, const std::string& label, const std::string& detail,
                std::optional<double> wall_s = std::nullopt,
                std::optional<double> predicted_s = std::nullopt);
  void set_running(std::size_t n);
  // Mean wall time of earlier attempts of this study's jobs (from the database), used for the ETA
  // until a job of this run finishes.
  void set_prior_job_s(std::optional<double> s) { prior_job_s_ = s; }
  // The running jobs.
  void set_running_jobs(std::vector<ProgressJob> r) { running_jobs_ = std::move(r); }
  // The cost model's wall seconds (one worker) of the jobs not started, and how many jobs that
  // covers (the others have no estimate); job_started takes a job out of it.
  void set_plan(double predicted_s, std::size_t n_predicted) {
    plan_s_ = predicted_s, plan_n_ = n_predicted;
  }
  void job_started(std::optional<double> predicted_s);
  // Live: redraws the line (at most 5 times a second). Plain: prints a progress line every
  // log_every_s seconds while jobs run.
  void tick();
  // Clears the live line before the summary.
  void close();
  // Terminal width used to cut the live line (it must not wrap, or \r cannot redraw it).
  void set_width(std::size_t columns) { width_ = columns; }
  void set_log_every_s(double s) { log_every_s_ = s; }

  std::size_t done() const { return done_; }
  // "1:02:03", or "?" when no job time is known yet.
  std::string eta() const;
  // The progress text without control characters (the live line's content).
  std::string line() const;

private:
  std::ostream& out_;
  bool live_;
  std::size_t total_, workers_;
  std::size_t done_ = 0, failed_ = 0, diverged_ = 0, running_ = 0;
  double job_s_sum_ = 0;
  std::size_t job_s_n_ = 0;
  std::optional<double> prior_job_s_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
  std::size_t width_ = 0; // 0: do not cut
  double log_every_s_ = 60;
  std::vector<ProgressJob> running_jobs_;
  double plan_s_ = 0;
  std::size_t plan_n_ = 0;
  double measured_s_ = 0, predicted_s_ = 0; // finished jobs with an estimate: both sums
  void draw();
  std::string counter() const;
};

// "1:02:03" or "4:05"
std::string format_duration(double seconds);

// Columns of the terminal on stdout (0 when not a terminal or unknown).
std::size_t terminal_columns();

} // namespace sph::runner
