// Checkpoints of a long job: the particle state (any named arrays of doubles), the step and the
// simulated time, saved to <dir>/checkpoint.h5 every N steps and/or every M seconds of wall
// clock, and loaded when the job starts again (after a kill, a timeout or a node failure).
//
// The file is written through H5Writer (to checkpoint.h5.tmp, then renamed), so a kill during a
// save leaves the previous checkpoint intact. Doubles round-trip exactly, so a deterministic
// integrator resumed from a checkpoint reproduces an uninterrupted run bit for bit.
//
// A checkpoint is continued only by the solver code that wrote it and only with the bytes it
// wrote: the file carries the solver fingerprint of its build (core/fingerprint.hpp) and the
// SHA-256 of its contents (fingerprint, step, time, every array's name and values), both as
// attributes of the same file, so they are replaced together with it. A checkpoint of another
// fingerprint (or of none: written before this check), one whose contents do not match their
// SHA-256 (damaged bytes) and one that cannot be read are removed, and the job starts again from
// t = 0 with the reason in its message (Checkpointer::rejection()): nothing of such a state is
// used.
//
//   io::Checkpointer ck(ctx.checkpoint_dir, ctx.checkpoint_every_steps, ctx.checkpoint_every_s);
//   if (auto s = ck.load({"x", "v"})) { step = s->step; t = s->time; x = s->arrays["x"]; ... }
//   for (; step < n; ++step) { ...; if (ck.due(step + 1)) ck.save({step + 1, t, {{"x", x}, ...}});
//   } ck.discard(); // optional, once the job's results are final
#pragma once

#include "core/fingerprint.hpp"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph::io {

struct CheckpointState {
  std::int64_t step = 0; // steps completed
  double time = 0;       // simulated time reached
  std::map<std::string, std::vector<double>> arrays;
};

class Checkpointer {
public:
  // dir empty: checkpoints off (due() is always false, load() finds nothing).
  // every_steps <= 0 and every_seconds <= 0: only explicit saves (e.g. on cancellation).
  // fingerprint: the solver code whose checkpoints are written and continued (this build's).
  Checkpointer(std::filesystem::path dir, std::int64_t every_steps = 0, double every_seconds = 0,
               std::string fingerprint = solver_fingerprint());

  bool enabled() const { return !dir_.empty(); }
  std::filesystem::path file() const { return dir_ / "checkpoint.h5"; }

  // The saved state with the arrays `names`, or nullopt when there is no checkpoint to continue.
  // A checkpoint of other solver code, with damaged contents or unreadable is removed and
  // rejection() says why (a sentence for the job's message; "" otherwise). A verified checkpoint
  // that lacks one of `names` is reported by an exception (the caller asks for state it never
  // saved).
  std::optional<CheckpointState> load(const std::vector<std::string>& names);
  const std::string& rejection() const { return rejection_; }

  // True when a save is due after `step` completed steps (every N steps, or M seconds since the
  // last save or the start).
  bool due(std::int64_t step) const;

  void save(const CheckpointState& s);
  // Removes the checkpoint file.
  void discard();

  int saves() const { return saves_; }

private:
  std::filesystem::path dir_;
  std::string fingerprint_;
  std::string rejection_;
  std::int64_t every_steps_;
  double every_seconds_;
  std::chrono::steady_clock::time_point last_;
  int saves_ = 0;
};

// Throws unless a restored state array holds n values ("<what> has <size> values, expected <n>"):
// a checkpoint of another version of a loop or scheme.
inline void expect_state_size(const std::vector<double>& a, std::size_t n,
                              const std::string& what) {
  if (a.size() != n)
    throw std::runtime_error(what + " has " + std::to_string(a.size()) + " values, expected " +
                             std::to_string(n));
}

// The message of a job that continued from its checkpoint.
// t with 6 significant digits (%g), so that a time of order 1e-10 s reads as such.
inline std::string resumed_message(double t, int attempt) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", t);
  return "resumed at t = " + std::string(buf) + " (attempt " + std::to_string(attempt) + ")";
}

} // namespace sph::io
