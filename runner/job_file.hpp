// The job-spec and result files: how a head process hands one job to a worker process and gets
// its outcome back, without the worker touching the database. The same format serves the local
// pool (runner job --spec --out) and, later, Slurm array tasks. Files are written to NAME.tmp and
// renamed, so a reader sees either no file or a complete one. Format in docs/runner.md.
#pragma once

#include "cases/case.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sph::runner {

inline constexpr const char* job_spec_format = "sph-job-spec/1";
inline constexpr const char* job_result_format = "sph-job-result/1";

struct JobFileSpec {
  std::string key;
  std::string case_name;
  std::string scheme;
  Params params; // every parameter of the case, typed
  int threads = 1;
  int attempt = 1;
  std::string output_dir;    // "" for none
  std::string progress_file; // "" for none: the worker writes its progress fraction there
  // Checkpoint policy handed to the case (RunContext); the checkpoint lives in output_dir.
  std::int64_t checkpoint_every_steps = 0;
  double checkpoint_every_s = 0;
};

// Outcome reported by the worker. status: done, diverged, cancelled or failed (run() threw).
struct JobFileResult {
  std::string key;
  std::string status;
  std::vector<std::pair<std::string, double>> metrics; // non-finite values survive the round trip
  std::string message;
};

// params.json in a job's folder: what the folder holds, without the database. Written by the
// runner when an attempt starts (finished_at null, state "running") and again when it ends.
inline constexpr const char* job_record_format = "sph-job-params/1";
inline constexpr const char* job_record_name = "params.json";

struct JobRecord {
  std::string key, study, tier, case_name, scheme;
  Params params;             // every parameter of the job, resolved and typed
  std::string identity_json; // the canonical identity parameters the key hashes ("" unknown)
  int attempt = 1;
  std::string host;
  double started_at = 0;             // Unix seconds
  std::optional<double> finished_at; // none while running
  std::string state = "running";     // then the job state
};

// The JSON text of params.json: format, job, study, tier, case, scheme, params (every one,
// typed), identity_params, numerics_version, code_version, compiler, build_type,
// solver_fingerprint, attempt, host, state, started_at / finished_at (ISO 8601 UTC) and
// started_at_unix / finished_at_unix.
std::string job_record_json(const JobRecord& r);
// Writes <dir>/params.json atomically.
void write_job_record(const std::filesystem::path& dir, const JobRecord& r);
// "2026-12-01T22:45:07.123Z"
std::string iso_utc(double unix_s);

// Writes `text` to path.tmp, flushes it to disk and renames it to path. Throws on error.
void write_file_atomic(const std::filesystem::path& path, const std::string& text);
// The whole file, byte for byte. Throws std::runtime_error naming the file when it cannot be read.
std::string read_file(const std::filesystem::path& path);

std::string spec_to_json(const JobFileSpec& spec);
// Parses a spec; the case must be registered (parameters are typed by its specs).
JobFileSpec spec_from_json(const std::string& text);

std::string result_to_json(const JobFileResult& result);
JobFileResult result_from_json(const std::string& text);

JobFileSpec read_spec_file(const std::filesystem::path& path);
void write_result_file(const std::filesystem::path& path, const JobFileResult& result);
// nullopt when the file does not exist; throws when it exists but is malformed.
std::optional<JobFileResult> read_result_file(const std::filesystem::path& path);

} // namespace sph::runner
