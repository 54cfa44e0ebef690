// One time step of a contact-SPH case (schemes/contact/): the scheme's stable dt (seed 003 CFL and
// viscous limits), shortened to land exactly on t_end. Shared by the cases that run scheme
// "contact" (shear_layer, cylinder_array).
#pragma once

#include "cases/case.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace sph {

// Advances `scheme` by one step from t (updated; t_end exactly on the last step) and returns the
// step taken, or returns 0 with res marked Cancelled (a cancellation request) or Diverged (a
// non-finite or non-positive stable step), in which case the run must stop.
template <class Scheme>
double contact_step(Scheme& scheme, double& t, double t_end, const RunContext& ctx,
                    RunResult& res) {
  if (stop_if_cancelled(ctx, t, res, [] {}))
    return 0.0;
  const double dt = std::min(scheme.stable_dt(), t_end - t);
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    res.status = RunStatus::Diverged;
    res.message = "time step " + std::to_string(dt) + " at t = " + std::to_string(t);
    return 0.0;
  }
  scheme.step(dt);
  t = (t_end - t - dt <= 1e-12 * t_end) ? t_end : t + dt;
  return dt;
}

} // namespace sph
