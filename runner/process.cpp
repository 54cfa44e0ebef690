// Spawning, supervising and reaping job processes.
#include "process.hpp"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <spawn.h>
#include <sstream>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char** environ;

namespace sph::runner {

std::vector<std::pair<std::string, std::string>> job_environment(int threads) {
  std::vector<std::pair<std::string, std::string>> env = {
      {"OMP_NUM_THREADS", std::to_string(threads)}};
  if (!std::getenv("OMP_WAIT_POLICY"))
    env.emplace_back("OMP_WAIT_POLICY", "passive");
  return env;
}

bool pid_alive(int pid) {
  if (pid <= 0)
    return false;
  if (::kill(pid, 0) != 0 && errno != EPERM)
    return false;
  // A killed process whose parent has not reaped it yet is a zombie: dead for our purpose.
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(stat, text))
    return true;
  auto paren = text.rfind(')');
  if (paren == std::string::npos || paren + 2 >= text.size())
    return true;
  char state = text[paren + 2];
  return state != 'Z' && state != 'X';
}

std::optional<double> process_start_time(int pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (pid <= 0 || !std::getline(stat, text))
    return std::nullopt;
  const auto paren = text.rfind(')');
  if (paren == std::string::npos)
    return std::nullopt;
  std::istringstream rest(text.substr(paren + 2)); // field 3 (state) on
  std::string field;
  for (int k = 3; k < 22 && rest >> field; ++k) {
  }
  unsigned long long ticks = 0;
  if (!(rest >> ticks))
    return std::nullopt; // field 22: starttime
  std::ifstream boot("/proc/stat");
  std::string line;
  while (std::getline(boot, line))
    if (line.rfind("btime ", 0) == 0) {
      const long hz = ::sysconf(_SC_CLK_TCK);
      if (hz <= 0)
        return std::nullopt;
      return std::stod(line.substr(6)) + static_cast<double>(ticks) / static_cast<double>(hz);
    }
  return std::nullopt;
}

std::string signal_description(int sig) {
  const char* abbrev = sigabbrev_np(sig);
  const char* desc = strsignal(sig);
  std::string s = abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(sig);
  if (desc)
    s += std::string(" (") + desc + ")";
  return s;
}

std::string file_tail(const std::filesystem::path& path, std::size_t max_bytes) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in)
    return "";
  auto size = static_cast<std::size_t>(in.tellg());
  std::size_t start = size > max_bytes ? size - max_bytes : 0;
  in.seekg(static_cast<std::streamoff>(start));
  std::string s(size - start, '\0');
  in.read(s.data(), static_cast<std::streamsize>(s.size()));
  if (start > 0)
    if (auto nl = s.find('\n'); nl != std::string::npos && nl + 1 < s.size())
      s = s.substr(nl + 1);
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r'))
    s.pop_back();
  return s;
}

namespace {

struct SpawnResources {
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attr;
  SpawnResources() {
    posix_spawn_file_actions_init(&actions);
    posix_spawnattr_init(&attr);
  }
  ~SpawnResources() {
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
  }
};

double seconds(const timeval& tv) {
  return static_cast<double>(tv.tv_sec) + tv.tv_usec * 1e-6;
}

} // namespace

ChildOutcome run_child(const ChildRequest& req, std::optional<double> timeout_s,
                       const std::atomic<int>& stop, double kill_grace_s) {
  ChildOutcome out;
  SpawnResources r;
  posix_spawn_file_actions_addopen(&r.actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&r.actions, 1, req.log_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&r.actions, 1, 2);
  // Own process group (so a timeout kills whatever the job started, and a terminal's Ctrl-C
  // reaches only the runner), default signal dispositions, nothing blocked.
  sigset_t none, defaults;
  sigemptyset(&none);
  sigemptyset(&defaults);
  for (int s : {SIGINT, SIGTERM, SIGPIPE, SIGHUP, SIGCHLD})
    sigaddset(&defaults, s);
  posix_spawnattr_setflags(&r.attr,
                           POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  posix_spawnattr_setpgroup(&r.attr, 0);
  posix_spawnattr_setsigmask(&r.attr, &none);
  posix_spawnattr_setsigdefault(&r.attr, &defaults);

  std::vector<std::string> env_strings;
  for (char** e = environ; e && *e; ++e) {
    std::string s = *e;
    bool overridden = false;
    for (const auto& [k, v] : req.env)
      overridden = overridden || s.rfind(k + "=", 0) == 0;
    if (!overridden)
      env_strings.push_back(std::move(s));
  }
  for (const auto& [k, v] : req.env)
    env_strings.push_back(k + "=" + v);
  std::vector<char*> envp;
  for (auto& s : env_strings)
    envp.push_back(s.data());
  envp.push_back(nullptr);
  std::vector<std::string> args{req.exe};
  args.insert(args.end(), req.args.begin(), req.args.end());
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);

  auto t0 = std::chrono::steady_clock::now();
  pid_t pid = 0;
  int rc = posix_spawn(&pid, req.exe.c_str(), &r.actions, &r.attr, argv.data(), envp.data());
  if (rc != 0) {
    out.spawn_error = "cannot start '" + req.exe + "': " + std::strerror(rc);
    return out;
  }
  out.pid = pid;

  using clock = std::chrono::steady_clock;
  bool term_sent = false, kill_sent = false;
  clock::time_point term_at{};
  auto delay = std::chrono::microseconds(500);
  int status = 0;
  rusage ru{};
  for (;;) {
    pid_t w = wait4(pid, &status, WNOHANG, &ru);
    if (w == pid)
      break;
    if (w < 0 && errno != EINTR) {
      out.spawn_error = std::string("wait4 failed: ") + std::strerror(errno);
      return out;
    }
    auto now = clock::now();
    double elapsed = std::chrono::duration<double>(now - t0).count();
    int s = stop.load();
    if (!term_sent && (s > 0 || (timeout_s && elapsed > *timeout_s))) {
      if (s > 0)
        out.stopped = true;
      else
        out.timed_out = true;
      ::kill(-pid, SIGTERM);
      term_sent = true;
      term_at = now;
    }
    if (term_sent && !kill_sent &&
        (stop.load() > 1 || std::chrono::duration<double>(now - term_at).count() > kill_grace_s)) {
      ::kill(-pid, SIGKILL);
      kill_sent = true;
    }
    std::this_thread::sleep_for(delay);
    delay = std::min(delay * 2, std::chrono::microseconds(20000));
  }
  out.wall_s = std::chrono::duration<double>(clock::now() - t0).count();
  out.cpu_s = seconds(ru.ru_utime) + seconds(ru.ru_stime);
  out.peak_rss_kb = ru.ru_maxrss;
  if (WIFEXITED(status)) {
    out.exited = true;
    out.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    out.term_signal = WTERMSIG(status);
  }
  return out;
}

} // namespace sph::runner
