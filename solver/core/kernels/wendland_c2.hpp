// Wendland C2 kernel (Wendland 1995, Adv. Comput. Math. 4), support radius 2h:
//   W(q) = sigma_D (1 - q/2)^4 (2q + 1),  0 <= q < 2,  q = r/h,
//   sigma_2 = 7 / (4 pi h^2),  sigma_3 = 21 / (16 pi h^3).
//   dW/dq = -5 q sigma_D (1 - q/2)^3,  d2W/dq2 = sigma_D (1 - q/2)^2 (10 q - 5).
// Registry key "wendland_c2".
#pragma once

#include <numbers>

namespace sph {

template <int D>
struct WendlandC2 {
  static constexpr const char* name = "wendland_c2";
  static constexpr double support_factor = 2.0;

  double h, inv_h, sigma;

  explicit WendlandC2(double h_)
      : h(h_), inv_h(1.0 / h_), sigma(D == 2 ? 7.0 / (4.0 * std::numbers::pi * h_ * h_)
                                             : 21.0 / (16.0 * std::numbers::pi * h_ * h_ * h_)) {}

  double support() const { return support_factor * h; }

  double W(double r) const {
    const double q = r * inv_h;
    if (q >= 2.0)
      return 0.0;
    const double t = 1.0 - 0.5 * q, t2 = t * t;
    return sigma * t2 * t2 * (2.0 * q + 1.0);
  }
  double dW(double r) const {
    const double q = r * inv_h;
    if (q >= 2.0)
      return 0.0;
    const double t = 1.0 - 0.5 * q;
    return -5.0 * sigma * inv_h * q * t * t * t;
  }
  double d2W(double r) const {
    const double q = r * inv_h;
    if (q >= 2.0)
      return 0.0;
    const double t = 1.0 - 0.5 * q;
    return sigma * inv_h * inv_h * t * t * (10.0 * q - 5.0);
  }
};

} // namespace sph
