// Vortex-shedding metrics of a body's force-coefficient series, shared by the cylinder cases
// (cylinder_channel, seed 004 section 3; cylinder_free_stream, seed 002 section 4.4):
//   St            f D / U of the lift, f from its upward zero crossings after t_settle
//                 (diagnostics/signal.hpp); recorded when at least one period was found
//   st_cycles     whole periods found;  st_period_cv  spread of the periods / their mean
//   St_spectral   f D / U from the periodogram peak of the lift after t_settle
//   cd_mean       time mean of C_D (seed 004 eq. 21; seed 002 Table 2 "C_D")
//   cl_rms        root mean square of C_L (seed 004 eq. 23, not mean-removed)
//   cd_amplitude, cl_amplitude   half the peak-to-peak of C_D and C_L (seed 002 Table 2 lists
//                 C_D's as "+-" and C_L's amplitude)
// When the lift after t_settle holds >= 2 whole periods the averages and amplitudes are taken
// over exactly those periods, otherwise over [t_settle, end].
#pragma once

#include "cases/case.hpp"

#include <vector>

namespace sph {

struct AveragingWindow {
  double t0 = 0.0, t1 = 0.0;  // the interval the averages were taken over
  bool whole_periods = false; // [t0, t1] holds whole lift periods (else t1 is the last sample)
  double cd_mean = 0.0;       // the recorded cd_mean (NaN: none)
  double cl_lo = 1e300, cl_hi = -1e300; // C_L's range over [t0, t1] (cl_hi < cl_lo: no sample)
};

// Adds the metrics above to res (t, cd, cl: the sampled series; D_over_U: D / U of St).
AveragingWindow add_shedding_metrics(const std::vector<double>& t, const std::vector<double>& cd,
                                     const std::vector<double>& cl, double t_settle,
                                     double D_over_U, RunResult& res);

} // namespace sph
