// Diagnostics of sampled time signals (force coefficients, probes), generic over the case:
//   time_mean  (1/T) int_{t0}^{t1} f dt           seed 004 eqs. (21), (22)
//   time_rms   [(1/T) int_{t0}^{t1} f^2 dt]^(1/2)  seed 004 eq. (23)
//   dominant_frequency: the shedding frequency f of a periodic signal, from which St = f D / U
//     (seed 004 section 4.1, Sr = f D / U).
//   gaussian_lowpass: a smoothed copy of a noisy force signal (SPH particle noise) before the above
// Samples may be non-uniform in time; integrals use the trapezoidal rule over [t0, t1].
#pragma once

#include <cstddef>
#include <vector>

namespace sph::diag {

// Trapezoidal time average of f over the samples with t_start <= t <= t_stop (all by default).
// NaN when fewer than two samples qualify.
double time_mean(const std::vector<double>& t, const std::vector<double>& f,
                 double t_start = -1e300, double t_stop = 1e300);
// Trapezoidal root mean square, as eq. (23) (not mean-removed).
double time_rms(const std::vector<double>& t, const std::vector<double>& f, double t_start = -1e300,
                double t_stop = 1e300);

struct Frequency {
  double f = 0.0;          // frequency (1 / time unit of t); 0 when no period was found
  int cycles = 0;          // full periods used
  double period_std = 0.0; // standard deviation of the individual periods (zero crossings)
  double t_first = 0.0;    // zero crossings: first and last upward crossing used, so that
  double t_last = 0.0;     // [t_first, t_last] holds exactly `cycles` whole periods
};

// Frequency from upward zero crossings of the mean-removed signal (samples with t >= t_start),
// crossing times located by linear interpolation between samples. f = cycles / (t_last - t_first)
// over the first and last crossing. A crossing counts only after the signal has gone below
// -hysteresis * (max-min)/2 since the previous one: half a swing by default, so particle noise
// around zero (SPH force signals jitter by a quarter of their amplitude from sample to sample)
// does not count extra crossings. Needs at least 2 crossings (1 cycle); otherwise f = 0, cycles = 0.
Frequency zero_crossing_frequency(const std::vector<double>& t, const std::vector<double>& f,
                                  double t_start = -1e300, double hysteresis = 0.5);

// Frequency of the largest peak of the periodogram of the mean-removed signal (samples resampled
// to a uniform grid by linear interpolation, Hann window), refined by fitting a parabola to the
// log-magnitudes of the peak bin and its two neighbours (sub-bin interpolation). `cycles` is the
// number of periods in the window, floor(f T). O(n^2) DFT: meant for signals of <= ~1e5 samples.
Frequency spectral_peak_frequency(const std::vector<double>& t, const std::vector<double>& f,
                                  double t_start = -1e300, std::size_t max_samples = 8192);

// Gaussian low-pass: g_i = sum_k w_ik f_k / sum_k w_ik, w_ik = exp(-(t_k - t_i)^2 / (2 sigma^2))
// over |t_k - t_i| <= 4 sigma (window truncated and renormalised at the ends). On uniform samples
// much denser than sigma it multiplies a sine of frequency f by exp(-2 pi^2 sigma^2 f^2) and keeps
// the mean. sigma <= 0 returns f unchanged.
std::vector<double> gaussian_lowpass(const std::vector<double>& t, const std::vector<double>& f,
                                     double sigma);

} // namespace sph::diag
