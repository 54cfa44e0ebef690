// Worker side of a job: spec file in, case.run(), result file out; SIGTERM requests cancellation.
#include "job_worker.hpp"

#include "job_file.hpp"
#include "params.hpp"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <string>
#include <sys/prctl.h>
#include <thread>
#include <unistd.h>

namespace sph::runner {

namespace {

std::atomic<bool> cancel_requested{false};

struct Cancelled {};

extern "C" void on_term(int) {
  cancel_requested.store(true);
}

// The fault to inject for this job, or "" (see job_worker.hpp).
std::string fault_for(const JobFileSpec& spec) {
  const char* fault = std::getenv("SPH_RUNNER_FAULT");
  if (!fault || !*fault)
    return "";
  if (const char* match = std::getenv("SPH_RUNNER_FAULT_MATCH"); match && *match) {
    std::string m = match;
    auto eq = m.find('=');
    if (eq == std::string::npos)
      return "";
    auto it = spec.params.find(m.substr(0, eq));
    if (it == spec.params.end() || format_value_plain(it->second) != m.substr(eq + 1))
      return "";
  }
  return fault;
}

// Misbehaves as asked; returns normally for faults that act on the result (nan) or none.
void inject(const std::string& fault) {
  if (fault == "segv") {
    std::raise(SIGSEGV);
  } else if (fault == "abort") {
    std::abort();
  } else if (fault == "exit3") {
    std::_Exit(3);
  } else if (fault == "throw") {
    throw std::runtime_error("injected failure (SPH_RUNNER_FAULT=throw)");
  } else if (fault == "hang") {
    while (!cancel_requested.load())
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
  } else if (fault == "hang-hard") {
    std::signal(SIGTERM, SIG_IGN);
    for (;;)
      std::this_thread::sleep_for(std::chrono::seconds(1));
  } else if (fault.rfind("slow=", 0) == 0) {
    std::this_thread::sleep_for(std::chrono::duration<double>(std::stod(fault.substr(5))));
  }
}

} // namespace

int run_job_files(const std::filesystem::path& spec_path, const std::filesystem::path& out,
                  bool die_with_parent, int parent_pid) {
  if (die_with_parent) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    // The parent died before we could arm the signal: we were given to another process (init,
    // or a subreaper). Without the parent's pid, reparenting to init is all that can be seen.
    if (parent_pid > 0 ? getppid() != parent_pid : getppid() == 1)
      return 4;
  }
  struct sigaction sa {};
  sa.sa_handler = on_term;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGTERM, &sa, nullptr);

  JobFileSpec spec;
  try {
    spec = read_spec_file(spec_path);
  } catch (const std::exception& e) {
    std::cerr << "runner job: bad job spec '" << spec_path.string() << "': " << e.what() << "\n";
    return 2;
  }
  JobFileResult result;
  result.key = spec.key;
  try {
    const CaseInfo* info = find_case(spec.case_name);
    if (!info)
      throw std::runtime_error("unknown case '" + spec.case_name + "'");
    std::string fault = fault_for(spec);
    inject(fault);
    if (cancel_requested.load())
      throw Cancelled{};
    RunContext ctx;
    ctx.threads = spec.threads;
    ctx.output_dir = spec.output_dir;
    ctx.job_key = spec.key;
    ctx.cancel = &cancel_requested;
    ctx.attempt = spec.attempt;
    ctx.checkpoint_dir = spec.output_dir;
    ctx.checkpoint_every_steps = spec.checkpoint_every_steps;
    ctx.checkpoint_every_s = spec.checkpoint_every_s;
    ctx.fingerprint = case_fingerprint(spec.case_name);
    auto last = std::chrono::steady_clock::time_point{};
    if (!spec.progress_file.empty())
      ctx.progress = [&](double fraction) {
        auto now = std::chrono::steady_clock::now();
        if (now - last < std::chrono::seconds(1))
          return;
        last = now;
        try {
          write_file_atomic(spec.progress_file, std::to_string(fraction) + "\n");
        } catch (...) {
          // progress is advisory
        }
      };
    RunResult r = info->run(spec.params, ctx);
    result.status = r.status == RunStatus::Done       ? "done"
                    : r.status == RunStatus::Diverged ? "diverged"
                                                      : "cancelled";
    result.metrics = std::move(r.metrics);
    result.message = std::move(r.message);
    if (fault == "nan")
      result.metrics.emplace_back("injected_nan", std::numeric_limits<double>::quiet_NaN());
  } catch (const Cancelled&) {
    result.status = "cancelled";
    result.message = "cancelled before the case started";
  } catch (const std::exception& e) {
    result.status = "failed";
    result.message = e.what();
  } catch (...) {
    result.status = "failed";
    result.message = "unknown exception";
  }
  try {
    write_result_file(out, result);
  } catch (const std::exception& e) {
    std::cerr << "runner job: " << e.what() << "\n";
    return 3;
  }
  return 0;
}

} // namespace sph::runner
