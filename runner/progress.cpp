// Live progress line or plain log lines for a running sweep.
#include "progress.hpp"

#include <cstdio>

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

Progress::Progress(std::ostream& out, bool live, std::size_t total)
    : out_(out), live_(live), total_(total), start_(std::chrono::steady_clock::now()) {}

std::string Progress::counter() const {
  char buf[64];
  int width = static_cast<int>(std::to_string(total_).size());
  std::snprintf(buf, sizeof buf, "[%*zu/%zu]", width, done_, total_);
  return buf;
}

void Progress::finished(const std::string& state, const std::string& label,
                        const std::string& detail) {
  ++done_;
  if (state == "failed" || state == "timeout")
    ++failed_;
  if (state == "diverged")
    ++diverged_;
  bool notable = state != "done";
  if (live_ && !notable) {
    tick();
    return;
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

void Progress::tick() {
  if (!live_)
    return;
  auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(200))
    return;
  draw();
}

void Progress::draw() {
  auto now = std::chrono::steady_clock::now();
  last_draw_ = now;
  double elapsed = std::chrono::duration<double>(now - start_).count();
  std::string eta = "?";
  if (done_ > 0)
    eta =
        format_duration(elapsed / static_cast<double>(done_) * static_cast<double>(total_ - done_));
  out_ << "\r\033[K" << counter() << " running " << running_ << ", failed " << failed_
       << ", diverged " << diverged_ << ", elapsed " << format_duration(elapsed) << ", ETA " << eta;
  std::size_t shown = 0;
  for (const auto& [label, f] : fractions_) {
    if (shown++ == 4) {
      out_ << " ...";
      break;
    }
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s %.0f%%", label.c_str(), 100 * f);
    out_ << (shown == 1 ? " | " : ", ") << buf;
  }
  out_ << std::flush;
  drawn_ = true;
}

void Progress::close() {
  if (live_ && drawn_)
    out_ << "\r\033[K" << std::flush;
  drawn_ = false;
}

} // namespace sph::runner
