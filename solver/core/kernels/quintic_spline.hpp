// Quintic spline kernel (Morris, Fox & Zhu 1997, J. Comput. Phys. 136; Liu & Liu 2010,
// Arch. Comput. Methods Eng. 17, eq. 25), the kernel of seed 004; support radius 3h:
//   W(q) = sigma_D [(3-q)^5 - 6 (2-q)^5 + 15 (1-q)^5],  each bracket only while positive,
//   sigma_2 = 7 / (478 pi h^2),  sigma_3 = 1 / (120 pi h^3),  q = r/h.
// Registry key "quintic_spline".
#pragma once

#include <numbers>

namespace sph {

template <int D>
struct QuinticSpline {
  static constexpr const char* name = "quintic_spline";
  static constexpr double support_factor = 3.0;

  double h, inv_h, sigma;

  explicit QuinticSpline(double h_)
      : h(h_), inv_h(1.0 / h_), sigma(D == 2 ? 7.0 / (478.0 * std::numbers::pi * h_ * h_)
                                             : 1.0 / (120.0 * std::numbers::pi * h_ * h_ * h_)) {}

  double support() const { return support_factor * h; }

  double W(double r) const {
    const double q = r * inv_h;
    return sigma * (p5(3.0 - q) - 6.0 * p5(2.0 - q) + 15.0 * p5(1.0 - q));
  }
  double dW(double r) const {
    const double q = r * inv_h;
    return -5.0 * sigma * inv_h * (p4(3.0 - q) - 6.0 * p4(2.0 - q) + 15.0 * p4(1.0 - q));
  }
  double d2W(double r) const {
    const double q = r * inv_h;
    return 20.0 * sigma * inv_h * inv_h * (p3(3.0 - q) - 6.0 * p3(2.0 - q) + 15.0 * p3(1.0 - q));
  }

private:
  static double pos(double t) { return t > 0.0 ? t : 0.0; }
  static double p3(double t) {
    t = pos(t);
    return t * t * t;
  }
  static double p4(double t) {
    t = pos(t);
    const double t2 = t * t;
    return t2 * t2;
  }
  static double p5(double t) {
    t = pos(t);
    const double t2 = t * t;
    return t2 * t2 * t;
  }
};

} // namespace sph
