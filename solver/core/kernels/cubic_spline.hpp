// Cubic B-spline kernel (Monaghan 1992, Rep. Prog. Phys. 55, eq. 2.6 of Monaghan & Lattanzio 1985),
// support radius 2h:
//   W(q) = sigma_D [1 - 3/2 q^2 + 3/4 q^3]   0 <= q < 1
//        = sigma_D 1/4 (2 - q)^3            1 <= q < 2,     q = r/h
//   sigma_2 = 10 / (7 pi h^2),  sigma_3 = 1 / (pi h^3).
// Registry key "cubic_spline".
#pragma once

#include <numbers>

namespace sph {

template <int D>
struct CubicSpline {
  static constexpr const char* name = "cubic_spline";
  static constexpr double support_factor = 2.0;

  double h, inv_h, sigma;

  explicit CubicSpline(double h_)
      : h(h_), inv_h(1.0 / h_), sigma(D == 2 ? 10.0 / (7.0 * std::numbers::pi * h_ * h_)
                                             : 1.0 / (std::numbers::pi * h_ * h_ * h_)) {}

  double support() const { return support_factor * h; }

  double W(double r) const {
    const double q = r * inv_h;
    if (q < 1.0)
      return sigma * (1.0 - 1.5 * q * q + 0.75 * q * q * q);
    if (q < 2.0) {
      const double t = 2.0 - q;
      return sigma * 0.25 * t * t * t;
    }
    return 0.0;
  }
  // dW/dr
  double dW(double r) const {
    const double q = r * inv_h;
    if (q < 1.0)
      return sigma * inv_h * (-3.0 * q + 2.25 * q * q);
    if (q < 2.0) {
      const double t = 2.0 - q;
      return -sigma * inv_h * 0.75 * t * t;
    }
    return 0.0;
  }
  // d2W/dr2
  double d2W(double r) const {
    const double q = r * inv_h;
    if (q < 1.0)
      return sigma * inv_h * inv_h * (-3.0 + 4.5 * q);
    if (q < 2.0)
      return sigma * inv_h * inv_h * 1.5 * (2.0 - q);
    return 0.0;
  }
};

} // namespace sph
