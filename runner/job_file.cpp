// Job-spec and result files (JSON), written atomically.
#include "job_file.hpp"

#include "job_key.hpp"
#include "params.hpp"
#include "provenance.hpp"

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace sph::runner {

namespace fs = std::filesystem;
using nlohmann::json;

void write_file_atomic(const fs::path& path, const std::string& text) {
  fs::path tmp = path;
  tmp += ".tmp";
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    throw std::runtime_error("cannot write '" + tmp.string() + "': " + std::strerror(errno));
  const char* p = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR)
      continue;
    if (n < 0) {
      int err = errno;
      ::close(fd);
      throw std::runtime_error("cannot write '" + tmp.string() + "': " + std::strerror(err));
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  ::fdatasync(fd);
  ::close(fd);
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot rename '" + tmp.string() + "': " + std::strerror(errno));
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error("cannot read '" + path.string() + "'");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

namespace {

json number_to_json(double x) {
  if (std::isnan(x))
    return "nan";
  if (std::isinf(x))
    return x > 0 ? "inf" : "-inf";
  return x;
}

double number_from_json(const json& j) {
  if (j.is_number())
    return j.get<double>();
  if (j.is_string()) {
    auto s = j.get<std::string>();
    if (s == "nan")
      return std::nan("");
    if (s == "inf")
      return HUGE_VAL;
    if (s == "-inf")
      return -HUGE_VAL;
  }
  throw std::invalid_argument("bad metric value " + j.dump());
}

void expect_format(const json& j, const char* format) {
  if (!j.is_object() || j.value("format", "") != format)
    throw std::invalid_argument(std::string("not a ") + format + " file");
}

} // namespace

std::string iso_utc(double unix_s) {
  const auto whole = static_cast<std::time_t>(std::floor(unix_s));
  const int ms = static_cast<int>(std::floor((unix_s - static_cast<double>(whole)) * 1000));
  std::tm tm{};
  gmtime_r(&whole, &tm);
  char buf[40], out[48];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  std::snprintf(out, sizeof out, "%s.%03dZ", buf, ms);
  return out;
}

#ifndef SPH_BUILD_TYPE
#define SPH_BUILD_TYPE ""
#endif

std::string job_record_json(const JobRecord& r) {
  json identity = nullptr;
  if (!r.identity_json.empty())
    identity = json::parse(r.identity_json);
  json j = {{"format", job_record_format},
            {"job", r.key},
            {"study", r.study},
            {"tier", r.tier},
            {"case", r.case_name},
            {"scheme", r.scheme},
            {"params", all_params_json(r.params)},
            {"identity_params", identity},
            {"numerics_version", numerics_version},
            {"code_version", code_version()},
            {"compiler", compiler_id()},
            {"build_type", SPH_BUILD_TYPE},
            {"solver_fingerprint", solver_fingerprint(r.case_name)},
            {"attempt", r.attempt},
            {"host", r.host},
            {"state", r.state},
            {"started_at", iso_utc(r.started_at)},
            {"started_at_unix", r.started_at},
            {"finished_at", r.finished_at ? json(iso_utc(*r.finished_at)) : json()},
            {"finished_at_unix", r.finished_at ? json(*r.finished_at) : json()}};
  return j.dump(1) + "\n";
}

void write_job_record(const fs::path& dir, const JobRecord& r) {
  write_file_atomic(dir / job_record_name, job_record_json(r));
}

std::string spec_to_json(const JobFileSpec& s) {
  json params = json::object();
  for (const auto& [k, v] : s.params)
    params[k] = value_to_json(v);
  json j = {{"format", job_spec_format},
            {"key", s.key},
            {"case", s.case_name},
            {"scheme", s.scheme},
            {"params", params},
            {"threads", s.threads},
            {"attempt", s.attempt},
            {"output_dir", s.output_dir},
            {"progress_file", s.progress_file},
            {"checkpoint_every_steps", s.checkpoint_every_steps},
            {"checkpoint_every_s", s.checkpoint_every_s}};
  return j.dump(1) + "\n";
}

JobFileSpec spec_from_json(const std::string& text) {
  json j = json::parse(text);
  expect_format(j, job_spec_format);
  JobFileSpec s;
  s.key = j.at("key").get<std::string>();
  s.case_name = j.at("case").get<std::string>();
  s.scheme = j.value("scheme", "");
  s.threads = j.value("threads", 1);
  s.attempt = j.value("attempt", 1);
  s.output_dir = j.value("output_dir", "");
  s.progress_file = j.value("progress_file", "");
  s.checkpoint_every_steps = j.value("checkpoint_every_steps", std::int64_t{0});
  s.checkpoint_every_s = j.value("checkpoint_every_s", 0.0);
  const CaseInfo* info = find_case(s.case_name);
  if (!info)
    throw std::invalid_argument("unknown case '" + s.case_name + "'");
  const json& params = j.at("params");
  for (const auto& spec : job_specs(*info, s.scheme)) {
    auto it = params.find(spec.name);
    s.params[spec.name] = it == params.end() ? spec.default_value : value_from_json(spec, *it);
  }
  for (const auto& [k, v] : params.items())
    if (!s.params.count(k))
      throw std::invalid_argument("case '" + s.case_name + "' has no parameter '" + k + "'");
  return s;
}

std::string result_to_json(const JobFileResult& r) {
  json metrics = json::array();
  for (const auto& [name, value] : r.metrics)
    metrics.push_back({name, number_to_json(value)});
  json j = {{"format", job_result_format},
            {"key", r.key},
            {"status", r.status},
            {"metrics", metrics},
            {"message", r.message}};
  return j.dump(1) + "\n";
}

JobFileResult result_from_json(const std::string& text) {
  json j = json::parse(text);
  expect_format(j, job_result_format);
  JobFileResult r;
  r.key = j.at("key").get<std::string>();
  r.status = j.at("status").get<std::string>();
  r.message = j.value("message", "");
  for (const auto& m : j.at("metrics"))
    r.metrics.emplace_back(m.at(0).get<std::string>(), number_from_json(m.at(1)));
  static const char* statuses[] = {"done", "diverged", "cancelled", "failed"};
  bool ok = false;
  for (const char* s : statuses)
    ok = ok || r.status == s;
  if (!ok)
    throw std::invalid_argument("unknown job status '" + r.status + "'");
  return r;
}

JobFileSpec read_spec_file(const fs::path& path) {
  return spec_from_json(read_file(path));
}

void write_result_file(const fs::path& path, const JobFileResult& result) {
  write_file_atomic(path, result_to_json(result));
}

std::optional<JobFileResult> read_result_file(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    return std::nullopt;
  return result_from_json(read_file(path));
}

} // namespace sph::runner
