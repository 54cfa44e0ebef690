// Time-signal diagnostics: means, rms, shedding frequency (see signal.hpp; seed 004 eqs. 21-23).
#include "diagnostics/signal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace sph::diag {
namespace {

// First sample index with t >= t_start.
std::size_t first_index(const std::vector<double>& t, double t_start) {
  return static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), t_start) - t.begin());
}

template <class F>
double trapezoid_mean(const std::vector<double>& t, const std::vector<double>& f, double t_start,
                      double t_stop, F&& g) {
  const std::size_t k0 = first_index(t, t_start);
  const std::size_t n =
      std::min(std::min(t.size(), f.size()),
               static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), t_stop) - t.begin()));
  if (n < 2 || k0 + 1 >= n)
    return std::numeric_limits<double>::quiet_NaN();
  double s = 0.0;
  for (std::size_t k = k0 + 1; k < n; ++k)
    s += 0.5 * (g(f[k]) + g(f[k - 1])) * (t[k] - t[k - 1]);
  const double T = t[n - 1] - t[k0];
  return T > 0.0 ? s / T : std::numeric_limits<double>::quiet_NaN();
}

} // namespace

double time_mean(const std::vector<double>& t, const std::vector<double>& f, double t_start,
                 double t_stop) {
  return trapezoid_mean(t, f, t_start, t_stop, [](double x) { return x; });
}

double time_rms(const std::vector<double>& t, const std::vector<double>& f, double t_start,
                double t_stop) {
  return std::sqrt(trapezoid_mean(t, f, t_start, t_stop, [](double x) { return x * x; }));
}

Frequency zero_crossing_frequency(const std::vector<double>& t, const std::vector<double>& f,
                                  double t_start, double hysteresis) {
  Frequency out;
  const std::size_t k0 = first_index(t, t_start);
  const std::size_t n = std::min(t.size(), f.size());
  if (k0 + 2 > n)
    return out;
  const double mean = time_mean(t, f, t_start);
  double lo = f[k0], hi = f[k0];
  for (std::size_t k = k0; k < n; ++k)
    lo = std::min(lo, f[k]), hi = std::max(hi, f[k]);
  const double band = hysteresis * 0.5 * (hi - lo);
  if (!(hi > lo))
    return out;
  std::vector<double> crossings;
  bool armed = false; // the signal went below -band since the last crossing
  for (std::size_t k = k0 + 1; k < n; ++k) {
    const double a = f[k - 1] - mean, b = f[k] - mean;
    if (a < -band || b < -band)
      armed = true;
    if (armed && a < 0.0 && b >= 0.0) {
      crossings.push_back(t[k - 1] + (t[k] - t[k - 1]) * (-a) / (b - a));
      armed = false;
    }
  }
  if (crossings.size() < 2)
    return out;
  out.cycles = static_cast<int>(crossings.size()) - 1;
  out.t_first = crossings.front(), out.t_last = crossings.back();
  out.f = out.cycles / (crossings.back() - crossings.front());
  double s2 = 0.0;
  const double T = 1.0 / out.f;
  for (std::size_t c = 1; c < crossings.size(); ++c)
    s2 += std::pow(crossings[c] - crossings[c - 1] - T, 2);
  out.period_std = std::sqrt(s2 / out.cycles);
  return out;
}

Frequency spectral_peak_frequency(const std::vector<double>& t, const std::vector<double>& f,
                                  double t_start, std::size_t max_samples) {
  Frequency out;
  const std::size_t k0 = first_index(t, t_start);
  const std::size_t n = std::min(t.size(), f.size());
  if (k0 + 8 > n)
    return out;
  const double ta = t[k0], tb = t[n - 1], T = tb - ta;
  if (!(T > 0.0))
    return out;
  const std::size_t M = std::min(max_samples, n - k0);
  // Uniform resampling on [ta, tb) with M points, mean removed, Hann window.
  std::vector<double> x(M);
  const double dt = T / static_cast<double>(M);
  std::size_t k = k0;
  for (std::size_t m = 0; m < M; ++m) {
    const double tm = ta + m * dt;
    while (k + 1 < n && t[k + 1] < tm)
      ++k;
    const std::size_t k1 = std::min(k + 1, n - 1);
    const double w = t[k1] > t[k] ? (tm - t[k]) / (t[k1] - t[k]) : 0.0;
    x[m] = f[k] + w * (f[k1] - f[k]);
  }
  double mean = 0.0;
  for (double v : x)
    mean += v;
  mean /= static_cast<double>(M);
  for (std::size_t m = 0; m < M; ++m)
    x[m] =
        (x[m] - mean) * (0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(m) / M));
  // Magnitude of bins 1..M/2 - 1.
  const std::size_t B = M / 2;
  std::vector<double> mag(B, 0.0);
  for (std::size_t b = 1; b < B; ++b) {
    double re = 0.0, im = 0.0;
    const double w = 2.0 * std::numbers::pi * static_cast<double>(b) / static_cast<double>(M);
    // Recurrence for cos/sin(w m) to avoid M trig calls per bin.
    const double cw = std::cos(w), sw = std::sin(w);
    double c = 1.0, s = 0.0;
    for (std::size_t m = 0; m < M; ++m) {
      re += x[m] * c, im -= x[m] * s;
      const double cn = c * cw - s * sw;
      s = s * cw + c * sw, c = cn;
    }
    mag[b] = std::hypot(re, im);
  }
  std::size_t bp = 1;
  for (std::size_t b = 2; b + 1 < B; ++b)
    if (mag[b] > mag[bp])
      bp = b;
  if (!(mag[bp] > 0.0))
    return out;
  double delta = 0.0;
  if (bp >= 1 && bp + 1 < B && mag[bp - 1] > 0.0 && mag[bp + 1] > 0.0) {
    const double a = std::log(mag[bp - 1]), b = std::log(mag[bp]), c = std::log(mag[bp + 1]);
    const double den = a - 2.0 * b + c;
    if (den < 0.0)
      delta = std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
  }
  out.f = (static_cast<double>(bp) + delta) / T;
  out.cycles = static_cast<int>(std::floor(out.f * T));
  return out;
}

std::vector<double> gaussian_lowpass(const std::vector<double>& t, const std::vector<double>& f,
                                     double sigma) {
  if (!(sigma > 0.0))
    return f;
  const std::size_t n = std::min(t.size(), f.size());
  std::vector<double> g(n);
  std::size_t lo = 0, hi = 0; // window [lo, hi) of samples within 4 sigma of t[i]
  for (std::size_t i = 0; i < n; ++i) {
    while (t[lo] < t[i] - 4.0 * sigma)
      ++lo;
    while (hi < n && t[hi] <= t[i] + 4.0 * sigma)
      ++hi;
    double sw = 0.0, sf = 0.0;
    for (std::size_t k = lo; k < hi; ++k) {
      const double d = (t[k] - t[i]) / sigma;
      const double w = std::exp(-0.5 * d * d);
      sw += w, sf += w * f[k];
    }
    g[i] = sf / sw;
  }
  return g;
}

} // namespace sph::diag
