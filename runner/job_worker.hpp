// The worker side of a job: reads a job-spec file, runs the case, writes the result file. This is
// what the hidden `runner job --spec SPEC --out RESULT` subcommand executes in a child process.
//
// For tests of the runner's resilience, the environment variable SPH_RUNNER_FAULT makes the
// worker misbehave on purpose: segv, abort, throw, exit3, nan, hang (until SIGTERM), hang-hard
// (ignores SIGTERM), slow=SECONDS (sleeps, then runs normally). SPH_RUNNER_FAULT_MATCH=param=value
// restricts the fault to jobs with that parameter value.
#pragma once

#include <filesystem>

namespace sph::runner {

// Returns the process exit code: 0 when a result file was written (whatever the job's status).
// die_with_parent: the worker is killed if the process that started it dies; parent_pid: that
// process (0: unknown), so that a parent which is PID 1 (a runner in a container) is not taken
// for one that died before the worker could arm the signal.
int run_job_files(const std::filesystem::path& spec, const std::filesystem::path& out,
                  bool die_with_parent, int parent_pid = 0);

} // namespace sph::runner
