// Checkpoints on top of the HDF5 writer/reader: datasets meta/step, meta/time, state/<name>, and
// root attributes solver_fingerprint, state_arrays (the array names, one a line) and sha256 (of
// the contents, content_sha256 below).
#include "io/checkpoint.hpp"

#include "io/hdf5.hpp"

#include <openssl/evp.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace sph::io {

namespace {

// SHA-256 (hex) of what a checkpoint says: the fingerprint, the step, the time and every array's
// name, length and values (their bytes), arrays in name order.
std::string content_sha256(const std::string& fingerprint, const CheckpointState& s) {
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), EVP_MD_CTX_free);
  bool ok = ctx && EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) == 1;
  auto add = [&](const void* data, std::size_t n) {
    ok = ok && EVP_DigestUpdate(ctx.get(), data, n) == 1;
  };
  auto add_u64 = [&](std::uint64_t v) {
    unsigned char b[8];
    for (int k = 0; k < 8; ++k)
      b[k] = static_cast<unsigned char>(v >> (8 * k));
    add(b, 8);
  };
  auto add_double = [&](double v) {
    std::uint64_t u;
    std::memcpy(&u, &v, 8);
    add_u64(u);
  };
  add_u64(fingerprint.size());
  add(fingerprint.data(), fingerprint.size());
  add_u64(static_cast<std::uint64_t>(s.step));
  add_double(s.time);
  for (const auto& [name, data] : s.arrays) {
    add_u64(name.size());
    add(name.data(), name.size());
    add_u64(data.size());
    for (double v : data)
      add_double(v);
  }
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  ok = ok && EVP_DigestFinal_ex(ctx.get(), md, &len) == 1;
  if (!ok)
    throw std::runtime_error("checkpoint: SHA-256 failed (OpenSSL)");
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (unsigned int k = 0; k < len; ++k) {
    out += hex[md[k] >> 4];
    out += hex[md[k] & 15];
  }
  return out;
}

std::string time_text(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", t);
  return buf;
}

} // namespace

Checkpointer::Checkpointer(std::filesystem::path dir, std::int64_t every_steps,
                           double every_seconds, std::string fingerprint)
    : dir_(std::move(dir)), fingerprint_(std::move(fingerprint)), every_steps_(every_steps),
      every_seconds_(every_seconds), last_(std::chrono::steady_clock::now()) {}

std::optional<CheckpointState> Checkpointer::load(const std::vector<std::string>& names) {
  rejection_.clear();
  if (!enabled())
    return std::nullopt;
  std::error_code ec;
  if (!std::filesystem::exists(file(), ec))
    return std::nullopt;
  auto reject = [&](const std::string& why) -> std::optional<CheckpointState> {
    rejection_ = "the checkpoint " + why + ": removed, the job restarted from t = 0";
    std::error_code rm;
    std::filesystem::remove(file(), rm);
    return std::nullopt;
  };
  CheckpointState s;
  std::optional<std::string> fingerprint, sha256;
  try {
    fingerprint = read_string_attribute(file(), "solver_fingerprint");
    sha256 = read_string_attribute(file(), "sha256");
    const auto listed = read_string_attribute(file(), "state_arrays");
    if (!fingerprint || !sha256 || !listed)
      return reject("carries no solver fingerprint and checksum (written by an older build)");
    auto step = read_dataset(file(), "meta/step");
    auto time = read_dataset(file(), "meta/time");
    if (step.size() != 1 || time.size() != 1 || !(step[0] >= 0) || step[0] != std::floor(step[0]))
      throw std::runtime_error("meta/step or meta/time is malformed");
    s.step = static_cast<std::int64_t>(step[0]);
    s.time = time[0];
    for (std::size_t a = 0; a < listed->size();) {
      std::size_t b = listed->find('\n', a);
      if (b == std::string::npos)
        b = listed->size();
      const std::string n = listed->substr(a, b - a);
      s.arrays[n] = read_dataset(file(), "state/" + n);
      a = b + 1;
    }
  } catch (const std::exception& e) {
    return reject("could not be read (" + std::string(e.what()) + ")");
  }
  if (content_sha256(*fingerprint, s) != *sha256)
    return reject("failed its SHA-256 check (damaged contents)");
  if (*fingerprint != fingerprint_)
    return reject("at t = " + time_text(s.time) + " was written by solver fingerprint " +
                  *fingerprint + ", not by this build's " + fingerprint_);
  for (const auto& n : names)
    if (!s.arrays.count(n))
      throw std::runtime_error("checkpoint '" + file().string() + "' has no array " + n);
  return s;
}

bool Checkpointer::due(std::int64_t step) const {
  if (!enabled())
    return false;
  if (every_steps_ > 0 && step % every_steps_ == 0)
    return true;
  if (every_seconds_ > 0 &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_).count() >=
          every_seconds_)
    return true;
  return false;
}

void Checkpointer::save(const CheckpointState& s) {
  if (!enabled())
    return;
  std::filesystem::create_directories(dir_);
  {
    std::string listed;
    for (const auto& [name, data] : s.arrays) {
      if (name.empty() || name.find('\n') != std::string::npos)
        throw std::runtime_error("checkpoint: bad array name '" + name + "'");
      listed += (listed.empty() ? "" : "\n") + name;
    }
    H5Writer w(file());
    w.write("meta/step", {static_cast<double>(s.step)});
    w.write("meta/time", {s.time});
    for (const auto& [name, data] : s.arrays)
      w.write("state/" + name, data);
    w.attribute("solver_fingerprint", fingerprint_);
    w.attribute("state_arrays", listed);
    w.attribute("sha256", content_sha256(fingerprint_, s)); // last: a file without it is refused
    w.close(); // renames checkpoint.h5.tmp over the previous checkpoint
  }
  last_ = std::chrono::steady_clock::now();
  ++saves_;
}

void Checkpointer::discard() {
  std::error_code ec;
  if (enabled())
    std::filesystem::remove(file(), ec);
}

} // namespace sph::io
