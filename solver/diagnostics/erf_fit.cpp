// Least-squares fits of the shear-layer viscosity (see erf_fit.hpp).
#include "diagnostics/erf_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sph {

double shear_layer_u(const ShearLayer& s, double x, double t, double nu) {
  if (!(nu > 0.0) || !(t > 0.0))
    return x > 0.0 ? s.U0 : (x < 0.0 ? -s.U0 : 0.0);
  const double w = std::sqrt(4.0 * nu * t);
  double u = std::erf(x / w);
  if (s.half_width > 0.0)
    for (int k = 1; k <= s.images; ++k) {
      const double sign = (k % 2) ? -1.0 : 1.0;
      const double L2 = 2.0 * k * s.half_width;
      u += sign * (std::erf((x - L2) / w) + std::erf((x + L2) / w));
    }
  return s.U0 * u;
}

double shear_layer_u2(const ShearLayer& s, double x, double t, double nu_l, double rho_l,
                      double nu_r, double rho_r) {
  const double bl = rho_l * std::sqrt(std::max(nu_l, 0.0));
  const double br = rho_r * std::sqrt(std::max(nu_r, 0.0));
  const double Uc = bl + br > 0.0 ? s.U0 * (br - bl) / (br + bl) : 0.0;
  if (x < 0.0) {
    if (!(nu_l > 0.0) || !(t > 0.0))
      return -s.U0;
    return -s.U0 + (Uc + s.U0) * std::erfc(-x / std::sqrt(4.0 * nu_l * t));
  }
  if (!(nu_r > 0.0) || !(t > 0.0))
    return s.U0;
  return s.U0 + (Uc - s.U0) * std::erfc(x / std::sqrt(4.0 * nu_r * t));
}

namespace {

// Gauss-Newton on theta = log(nu) (P parameters) with a finite-difference Jacobian.
template <int P, class Model>
ErfFit gauss_newton(const std::vector<double>& x, const std::vector<double>& u, double U0,
                    std::array<double, P> th, Model&& model) {
  const std::size_t n = x.size();
  auto sse = [&](const std::array<double, P>& q) {
    double s = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      const double d = model(x[k], q) - u[k];
      s += d * d;
    }
    return s;
  };
  ErfFit fit;
  double f = sse(th);
  std::vector<std::array<double, P>> J(n);
  std::vector<double> res(n);
  for (int it = 0; it < 200; ++it) {
    fit.iterations = it + 1;
    for (std::size_t k = 0; k < n; ++k)
      res[k] = model(x[k], th) - u[k];
    for (int a = 0; a < P; ++a) {
      const double hstep = 1e-6;
      auto tp = th, tm = th;
      tp[a] += hstep, tm[a] -= hstep;
      for (std::size_t k = 0; k < n; ++k)
        J[k][a] = (model(x[k], tp) - model(x[k], tm)) / (2.0 * hstep);
    }
    // Normal equations (P <= 2).
    double A[2][2] = {{0, 0}, {0, 0}}, g[2] = {0, 0};
    for (std::size_t k = 0; k < n; ++k)
      for (int a = 0; a < P; ++a) {
        g[a] += J[k][a] * res[k];
        for (int b = 0; b < P; ++b)
          A[a][b] += J[k][a] * J[k][b];
      }
    std::array<double, P> step{};
    if constexpr (P == 1) {
      if (!(A[0][0] > 0.0))
        break;
      step[0] = -g[0] / A[0][0];
    } else {
      const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
      if (!(std::abs(det) > 0.0))
        break;
      step[0] = -(A[1][1] * g[0] - A[0][1] * g[1]) / det;
      step[1] = -(A[0][0] * g[1] - A[1][0] * g[0]) / det;
    }
    double lambda = 1.0;
    std::array<double, P> tn{};
    double fn = f;
    for (int half = 0; half < 40; ++half) {
      for (int a = 0; a < P; ++a)
        tn[a] = th[a] + lambda * std::clamp(step[a], -2.0, 2.0);
      fn = sse(tn);
      if (fn <= f)
        break;
      lambda *= 0.5;
    }
    double move = 0.0;
    for (int a = 0; a < P; ++a)
      move = std::max(move, std::abs(tn[a] - th[a]));
    if (!(fn <= f)) { // no descent along the Gauss-Newton direction: a minimum to round-off
      fit.converged = true;
      break;
    }
    th = tn, f = fn;
    if (move < 1e-12) {
      fit.converged = true;
      break;
    }
  }
  fit.rms = n ? std::sqrt(f / n) / U0 : 0.0;
  if constexpr (P == 1)
    fit.nu = std::exp(th[0]);
  else
    fit.nu_left = std::exp(th[0]), fit.nu_right = std::exp(th[1]);
  return fit;
}

// Start: the best of a geometric scan of the layer width sqrt(4 nu t) from 1e-4 to 10 times the
// sampled extent.
template <class Model1>
double scan_start(const std::vector<double>& x, const std::vector<double>& u, double t,
                  Model1&& model) {
  double extent = 0.0;
  for (double xi : x)
    extent = std::max(extent, std::abs(xi));
  if (!(extent > 0.0) || !(t > 0.0))
    throw std::invalid_argument("fit_shear_layer: need samples at x != 0 and t > 0");
  double best = std::numeric_limits<double>::infinity(), best_nu = 0.0;
  for (int k = 0; k <= 100; ++k) {
    const double w = extent * std::pow(10.0, -4.0 + 5.0 * k / 100.0);
    const double nu = w * w / (4.0 * t);
    double s = 0.0;
    for (std::size_t m = 0; m < x.size(); ++m) {
      const double d = model(x[m], nu) - u[m];
      s += d * d;
    }
    if (s < best)
      best = s, best_nu = nu;
  }
  return best_nu;
}

} // namespace

ErfFit fit_shear_layer(const ShearLayer& s, const std::vector<double>& x,
                       const std::vector<double>& u, double t) {
  auto m1 = [&](double xi, double nu) { return shear_layer_u(s, xi, t, nu); };
  const double nu0 = scan_start(x, u, t, m1);
  return gauss_newton<1>(x, u, s.U0, {std::log(nu0)},
                         [&](double xi, const std::array<double, 1>& q) {
                           return shear_layer_u(s, xi, t, std::exp(q[0]));
                         });
}

ErfFit fit_shear_layer2(const ShearLayer& s, const std::vector<double>& x,
                        const std::vector<double>& u, double t, double rho_l, double rho_r) {
  auto m1 = [&](double xi, double nu) { return shear_layer_u2(s, xi, t, nu, rho_l, nu, rho_r); };
  const double nu0 = scan_start(x, u, t, m1);
  return gauss_newton<2>(
      x, u, s.U0, {std::log(nu0), std::log(nu0)}, [&](double xi, const std::array<double, 2>& q) {
        return shear_layer_u2(s, xi, t, std::exp(q[0]), rho_l, std::exp(q[1]), rho_r);
      });
}

} // namespace sph
