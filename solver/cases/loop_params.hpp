// The shared time loop's own parameters (cases/time_loop.hpp), stated once here and appended to
// the parameters of every case on the loop (add_loop_params in its CaseInfo), so a study sets
// them like any case parameter.
//
//   output_interval   simulated time between two particle snapshots (io/particle_snapshot.hpp:
//                     ParaView's .pvd of .vtp files in the job's output folder); 0 (the default):
//                     the final state only. Not part of the job key: an output option, which
//                     changes no metric (docs/fields.md).
#pragma once

#include "core/params.hpp"

#include <vector>

namespace sph {

inline ParamSpec output_interval_spec() {
  ParamSpec s{"output_interval", ParamType::Real, 0.0,
              "simulated time between particle snapshots for ParaView (particles.pvd in the job "
              "folder; 0: the final state only)",
              0.0};
  s.identity = false;
  return s;
}

inline void add_loop_params(std::vector<ParamSpec>& params) {
  params.push_back(output_interval_spec());
}

// The job's output_interval (0 when the parameters do not hold it: a caller that does not go
// through the runner, such as a unit test).
inline double output_interval(const Params& prm) {
  return prm.count("output_interval") ? get_real(prm, "output_interval") : 0.0;
}

} // namespace sph
