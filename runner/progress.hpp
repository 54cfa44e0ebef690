// Progress of a sweep: on a terminal, one live line (done/total, running, failed, elapsed, ETA
// from the measured throughput) with failures printed above it; otherwise one log line per
// finished job.
#pragma once

#include <chrono>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace sph::runner {

class Progress {
public:
  Progress(std::ostream& out, bool live, std::size_t total);
  // One job finished. `label` identifies it (key prefix and varying params), `detail` is the
  // timing and first metric or the error.
  void finished(const std::string& state, const std::string& label, const std::string& detail);
  void set_running(std::size_t n);
  // Simulated-time fraction (0..1) of each running job, by short label; shown on the live line.
  void set_fractions(std::vector<std::pair<std::string, double>> f) { fractions_ = std::move(f); }
  // Redraws the live line (rate-limited); no-op in log mode.
  void tick();
  // Clears the live line before the summary.
  void close();

  std::size_t done() const { return done_; }

private:
  std::ostream& out_;
  bool live_;
  std::size_t total_;
  std::size_t done_ = 0, failed_ = 0, diverged_ = 0, running_ = 0;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
  std::vector<std::pair<std::string, double>> fractions_;
  void draw();
  std::string counter() const;
};

// "1:02:03" or "4:05"
std::string format_duration(double seconds);

} // namespace sph::runner
