// Vortex-shedding metrics (see shedding.hpp).
#include "cases/shedding.hpp"

#include "diagnostics/signal.hpp"

#include <algorithm>
#include <cmath>

namespace sph {

AveragingWindow add_shedding_metrics(const std::vector<double>& t, const std::vector<double>& cd,
                                     const std::vector<double>& cl, double t_settle,
                                     double D_over_U, RunResult& res) {
  auto add_if = [&](const char* name, double v) {
    if (std::isfinite(v))
      res.add(name, v);
  };
  const diag::Frequency fz = diag::zero_crossing_frequency(t, cl, t_settle);
  const diag::Frequency fs = diag::spectral_peak_frequency(t, cl, t_settle);
  AveragingWindow w{t_settle, t.empty() ? t_settle : t.back(), false};
  if (fz.cycles >= 2)
    w = {fz.t_first, fz.t_last, true};
  w.cd_mean = diag::time_mean(t, cd, w.t0, w.t1);
  add_if("cd_mean", w.cd_mean);
  add_if("cl_rms", diag::time_rms(t, cl, w.t0, w.t1));
  res.add("st_cycles", fz.cycles);
  if (fz.cycles >= 1) {
    res.add("St", fz.f * D_over_U);
    res.add("st_period_cv", fz.period_std * fz.f);
  }
  if (fs.f > 0.0)
    res.add("St_spectral", fs.f * D_over_U);
  double cdmin = 1e300, cdmax = -1e300;
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] >= w.t0 && t[k] <= w.t1)
      cdmin = std::min(cdmin, cd[k]), cdmax = std::max(cdmax, cd[k]),
      w.cl_lo = std::min(w.cl_lo, cl[k]), w.cl_hi = std::max(w.cl_hi, cl[k]);
  if (cdmax >= cdmin) {
    res.add("cd_amplitude", 0.5 * (cdmax - cdmin));
    res.add("cl_amplitude", 0.5 * (w.cl_hi - w.cl_lo));
  }
  return w;
}

} // namespace sph
