// Helpers of the end-to-end tests that drive the `runner` binary (RUNNER_EXE): run it to
// completion with captured output, start it in the background to kill it, read the database.
#pragma once

#include "helpers.hpp"
#include "sqlite.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <utility>
#include <vector>

namespace sph::runner::test {

struct CmdResult {
  int code;
  std::string out;
};

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The binary under test: RUNNER_EXE, or SPH_RUNNER_EXE when set (to run the end-to-end tests
// against another build, e.g. the code before a fix, to see them fail there).
inline std::string runner_exe() {
  const char* e = std::getenv("SPH_RUNNER_EXE");
  return e && *e ? std::string(e) : std::string(RUNNER_EXE);
}

// Runs `runner ARGS` (a shell command line) in dir with extra environment assignments.
inline CmdResult run_runner(const TempDir& dir, const std::string& args,
                            const std::string& env = "", const std::string& out_name = "out.txt") {
  std::string cmd = "cd '" + dir.path().string() + "' && " + env + " '" + runner_exe() + "' " +
                    args + " > " + out_name + " 2>&1";
  int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_file(dir / out_name)};
}

// Starts `runner args...` in dir in the background (stdout+stderr to log); returns its pid.
inline pid_t spawn_runner(const std::filesystem::path& dir, const std::vector<std::string>& args,
                          const std::vector<std::pair<std::string, std::string>>& env,
                          const std::filesystem::path& log) {
  pid_t pid = fork();
  if (pid == 0) {
    if (chdir(dir.c_str()) != 0)
      _exit(126);
    int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    for (const auto& [k, v] : env)
      setenv(k.c_str(), v.c_str(), 1);
    std::vector<char*> argv;
    std::string exe = runner_exe();
    argv.push_back(exe.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(exe.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

// Exit code of a child (128+signal when killed); blocks.
inline int wait_exit(pid_t pid) {
  int status = 0;
  if (waitpid(pid, &status, 0) != pid)
    return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

inline std::int64_t sql_int(const std::filesystem::path& db, const std::string& sql) {
  Db d = Db::reader(db.string());
  sqlite3_busy_timeout(d.handle(), 5000);
  return d.scalar_int(sql);
}

inline std::string sql_text(const std::filesystem::path& db, const std::string& sql) {
  Db d = Db::reader(db.string());
  sqlite3_busy_timeout(d.handle(), 5000);
  Stmt s = d.prepare(sql);
  std::string out;
  while (s.step()) {
    for (int i = 0; i < s.columns(); ++i)
      out += (i ? "|" : "") + (s.is_null(i) ? std::string() : s.text(i));
    out += "\n";
  }
  return out;
}

} // namespace sph::runner::test
