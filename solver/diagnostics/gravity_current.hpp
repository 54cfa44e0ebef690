// A viscometer from the late spreading of a 2D drop (case spreading_drop, seed 003 section 5.6):
// the similarity solution of a viscous gravity current of constant area on a no-slip floor.
//
// Thin-film (lubrication) equation of a 2D layer of depth h(x, t) on a no-slip floor with a free
// surface, gravity g, kinematic viscosity nu (Huppert 1982, J. Fluid Mech. 121, 43-58, eq. 2.5
// with alpha = 0):
//   h_t = g / (3 nu) (h^3 h_x)_x = g / (12 nu) (h^4)_xx.
// With tau = g t / (12 nu) this is the porous-medium equation h_tau = (h^m)_xx, m = 4, whose
// source-type (Barenblatt) solution of area Q is
//   h = tau^(-1/5) (C - k xi^2)^(1/3),  xi = x tau^(-1/5),  k = (m - 1) / (2 m (m + 1)) = 3/40,
// with its front at x_N = sqrt(C / k) tau^(1/5) and Q = C^(5/6) B / sqrt(k), where
//   B = int_{-1}^{1} (1 - s^2)^(1/3) ds = sqrt(pi) Gamma(4/3) / Gamma(11/6) = 1.68263...
// Eliminating C:
//   x_N^5 = Q^3 tau / (k B^3) = (10/9) (Q / B)^3 g t / nu,                                    (1)
// i.e. the front's fifth power grows linearly in time at the rate (10/9) (Q/B)^3 g / nu. Huppert's
// half-current (a wall at x = 0, area q = Q/2) has x_N = eta_N (g q^3 t / (3 nu))^(1/5) with
// eta_N = (80 / (3 B^3))^(1/5) = 1.411, his value; the test pins this.
// A drop released from rest reaches (1) only once it is thin (h << x_N) and slow (inertia
// negligible), and then with a virtual time origin: the viscosity follows from the slope of
// x_N^5 against t, not from x_N itself.
#pragma once

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace sph {

// B of eq. (1): the integral of the Barenblatt profile's shape.
inline double gravity_current_shape_integral() {
  return std::sqrt(std::numbers::pi) * std::tgamma(4.0 / 3.0) / std::tgamma(11.0 / 6.0);
}

// d(x_N^5)/dt of eq. (1) for area Q (m^2 per unit width), gravity g and kinematic viscosity nu.
inline double gravity_current_front5_rate(double Q, double g, double nu) {
  const double qb = Q / gravity_current_shape_integral();
  return (10.0 / 9.0) * qb * qb * qb * g / nu;
}

// The kinematic viscosity whose current of area Q under gravity g has d(x_N^5)/dt = rate (eq. 1
// solved for nu).
inline double gravity_current_viscosity(double Q, double g, double rate) {
  if (!(rate > 0.0))
    throw std::invalid_argument("gravity_current_viscosity: the front must advance (rate > 0)");
  return gravity_current_front5_rate(Q, g, 1.0) / rate;
}

// Least-squares line y = a + b x through the points with x in [x_from, x_to]; r2 the coefficient
// of determination (1 for points on a line).
struct LineFit {
  double a = 0.0, b = 0.0, r2 = 0.0;
  int n = 0;
};
inline LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y,
                        double x_from = -1e300, double x_to = 1e300) {
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0;
  LineFit f;
  for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) {
    if (x[i] < x_from || x[i] > x_to)
      continue;
    sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i], syy += y[i] * y[i];
    ++f.n;
  }
  if (f.n < 2)
    return f;
  const double n = f.n, cxx = sxx - sx * sx / n, cxy = sxy - sx * sy / n, cyy = syy - sy * sy / n;
  if (!(cxx > 0.0))
    return f;
  f.b = cxy / cxx;
  f.a = (sy - f.b * sx) / n;
  f.r2 = cyy > 0.0 ? cxy * cxy / (cxx * cyy) : 1.0;
  return f;
}

} // namespace sph
