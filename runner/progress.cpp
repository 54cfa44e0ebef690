// Live progress line or plain log lines for a running sweep (see progress.hpp for the ETA).
#include "progress.hpp"

#include <algorithm>
#include <cstdio>
#include <sys/ioctl.h>
#include <unistd.h>

namespace sph::runner {

std::string format_duration(double s) {
  if (s < 0)
    s = 0;
  long t = static_cast<long>(s + 0.5);
  char buf[32];
  if (t >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld:%02ld", t / 60, t % 60);
  return buf;
}

std::size_t terminal_columns() {
  struct winsize w {};
  if (isatty(STDOUT_FILENO) && ioctl(STDOUT_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col > 0)
    return w.ws_col;
  return 0;
}

Progress::Progress(std::ostream& out, bool live, std::size_t total, std::size_t workers)
    : out_(out), live_(live), total_(total), workers_(std::max<std::size_t>(workers, 1)),
      start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

std::string Progress::counter() const {
  char buf[64];
  int width = static_cast<int>(std::to_string(total_).size());
  std::snprintf(buf, sizeof buf, "[%*zu/%zu]", width, done_, total_);
  return buf;
}

void Progress::finished(const std::string& state, const std::string& label,
                        const std::string& detail, std::optional<double> wall_s,
                        std::optional<double> predicted_s) {
  ++done_;
  if (state == "failed" || state == "timeout")
    ++failed_;
  if (state == "diverged")
    ++diverged_;
  if (wall_s && (state == "done" || state == "diverged")) {
    job_s_sum_ += *wall_s;
    ++job_s_n_;
    if (predicted_s && *predicted_s > 0)
      measured_s_ += *wall_s, predicted_s_ += *predicted_s;
  }
  if (live_ && drawn_)
    out_ << "\r\033[K";
  char st[16];
  std::snprintf(st, sizeof st, "%-8s", state.c_str());
  out_ << counter() << " " << st << " " << label << "  " << detail << "\n";
  if (live_)
    draw();
  else
    out_.flush();
}

void Progress::set_running(std::size_t n) {
  running_ = n;
}

void Progress::job_started(std::optional<double> predicted_s) {
  if (!predicted_s || plan_n_ == 0)
    return;
  plan_s_ = std::max(plan_s_ - *predicted_s, 0.0);
  --plan_n_;
}

std::string Progress::eta() const {
  std::optional<double> per_job; // for jobs without an estimate
  if (job_s_n_ > 0)
    per_job = job_s_sum_ / static_cast<double>(job_s_n_);
  else
    per_job = prior_job_s_;
  const double ratio = predicted_s_ > 0 ? measured_s_ / predicted_s_ : 1.0;
  double work = 0, longest = 0;
  for (const ProgressJob& r : running_jobs_) {
    const double f = std::clamp(r.fraction, 0.0, 1.0);
    const double f0 = std::clamp(r.start_fraction, 0.0, f);
    double rest;
    if (f - f0 >= 0.02 && r.elapsed_s > 0)
      rest = r.elapsed_s * (1.0 - f) / (f - f0);
    else if (r.predicted_s)
      rest = std::max(*r.predicted_s * ratio * (1.0 - f0) - r.elapsed_s, 0.0);
    else if (per_job)
      rest = *per_job * (1.0 - f);
    else
      return "?";
    work += rest;
    longest = std::max(longest, rest);
  }
  const std::size_t left = total_ - std::min(done_, total_);
  const std::size_t pending = left - std::min(running_jobs_.size(), left);
  const std::size_t unknown = pending - std::min(plan_n_, pending);
  if (unknown > 0 && !per_job)
    return "?";
  work += plan_s_ * ratio + static_cast<double>(unknown) * per_job.value_or(0.0);
  const double parallel = static_cast<double>(std::min(workers_, std::max<std::size_t>(left, 1)));
  return format_duration(std::max(work / parallel, longest));
}

std::string Progress::line() const {
  double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string s = counter() + " running " + std::to_string(running_) + ", failed " +
                  std::to_string(failed_) + ", diverged " + std::to_string(diverged_) +
                  ", elapsed " + format_duration(elapsed) + ", ETA " + eta();
  std::size_t shown = 0;
  for (const ProgressJob& r : running_jobs_) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s %.0f%%", r.label.c_str(),
                  100 * std::clamp(r.fraction, 0.0, 1.0));
    s += (shown++ == 0 ? " | " : ", ") + std::string(buf);
  }
  return s;
}

void Progress::tick() {
  auto now = std::chrono::steady_clock::now();
  if (!live_) {
    if (running_ > 0 && std::chrono::duration<double>(now - last_draw_).count() >= log_every_s_) {
      last_draw_ = now;
      out_ << "progress: " << line() << "\n" << std::flush;
    }
    return;
  }
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(200))
    return;
  draw();
}

void Progress::draw() {
  last_draw_ = std::chrono::steady_clock::now();
  std::string s = line();
  if (width_ > 4 && s.size() > width_ - 1)
    s = s.substr(0, width_ - 4) + "...";
  out_ << "\r\033[K" << s << std::flush;
  drawn_ = true;
}

void Progress::close() {
  if (live_ && drawn_)
    out_ << "\r\033[K" << std::flush;
  drawn_ = false;
}

} // namespace sph::runner
