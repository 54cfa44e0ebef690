// Checkpoints on top of the HDF5 writer/reader: datasets meta/step, meta/time, state/<name>.
#include "io/checkpoint.hpp"

#include "io/hdf5.hpp"

#include <cmath>
#include <stdexcept>

namespace sph::io {

Checkpointer::Checkpointer(std::filesystem::path dir, std::int64_t every_steps,
                           double every_seconds)
    : dir_(std::move(dir)), every_steps_(every_steps), every_seconds_(every_seconds),
      last_(std::chrono::steady_clock::now()) {}

std::optional<CheckpointState> Checkpointer::load(const std::vector<std::string>& names) const {
  if (!enabled())
    return std::nullopt;
  std::error_code ec;
  if (!std::filesystem::exists(file(), ec))
    return std::nullopt;
  CheckpointState s;
  auto step = read_dataset(file(), "meta/step");
  auto time = read_dataset(file(), "meta/time");
  if (step.size() != 1 || time.size() != 1 || !(step[0] >= 0) || step[0] != std::floor(step[0]))
    throw std::runtime_error("checkpoint '" + file().string() + "' is malformed");
  s.step = static_cast<std::int64_t>(step[0]);
  s.time = time[0];
  for (const auto& n : names)
    s.arrays[n] = read_dataset(file(), "state/" + n);
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
    H5Writer w(file());
    w.write("meta/step", {static_cast<double>(s.step)});
    w.write("meta/time", {s.time});
    for (const auto& [name, data] : s.arrays)
      w.write("state/" + name, data);
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
