// Child processes for jobs: spawn (posix_spawn, own process group, stdout+stderr to a log file),
// supervise (wall-clock limit, stop requests: SIGTERM to the group, then SIGKILL after a grace
// period) and reap with wait4() for the child's own CPU time and peak RSS.
#pragma once

#include <atomic>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sph::runner {

struct ChildRequest {
  std::string exe;
  std::vector<std::string> args;                        // argv[1..]
  std::vector<std::pair<std::string, std::string>> env; // set or override in the child
  std::filesystem::path log_path;                       // receives stdout and stderr
};

// The environment a job process gets on top of the runner's: OMP_NUM_THREADS = threads, and
// OMP_WAIT_POLICY = passive unless the user set it (threads that wait spin otherwise, and on a
// shared machine spinning threads made a 2-thread job 2-2.6x slower per step than 1 thread).
std::vector<std::pair<std::string, std::string>> job_environment(int threads);

struct ChildOutcome {
  std::string spawn_error; // non-empty: the child never started
  int pid = 0;
  bool exited = false; // normal exit (exit_code valid); otherwise killed by term_signal
  int exit_code = 0;
  int term_signal = 0;
  bool timed_out = false; // killed for exceeding the wall-clock limit
  bool stopped = false;   // killed because the runner was asked to stop
  double wall_s = 0;
  double cpu_s = 0; // user + system of the child (all its threads, reaped descendants)
  long peak_rss_kb = 0;
};

// stop: 0 run on, 1 stop gracefully (SIGTERM, then SIGKILL after kill_grace_s), 2 kill now.
ChildOutcome run_child(const ChildRequest& req, std::optional<double> timeout_s,
                       const std::atomic<int>& stop, double kill_grace_s);

bool pid_alive(int pid);
// When process pid started, in Unix seconds (from /proc: its start in clock ticks after boot and
// the boot time; to about 1 s), or nullopt where /proc does not say.
std::optional<double> process_start_time(int pid);
// Last max_bytes of a file (from a line start when possible); "" when missing.
std::string file_tail(const std::filesystem::path& path, std::size_t max_bytes);
// "SIGSEGV (Segmentation fault)"
std::string signal_description(int sig);

} // namespace sph::runner
