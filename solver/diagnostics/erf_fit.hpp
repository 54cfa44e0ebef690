// The impulsively started shear layer (../shared/reference/analytic_solutions.md, section 2; seed
// 003 eq. 10) and least-squares fits of its viscosity to particle velocities.
//
//   u(x, t) = U0 erf(x / sqrt(4 nu t))                       one fluid, unbounded
//   u(x, t) = U0 sum_k (-1)^k erf((x - 2 k L) / sqrt(4 nu t))  one fluid, slip walls at x = +-L
// The second form is the first plus its images in the walls (the even extension of sign(x) about
// x = +-L is a square wave of period 4L); it equals the first to within erfc(L / sqrt(4 nu t)) and
// stays exact when the layer has grown to the walls. Two fluids (left x < 0: nu_l, rho_l; right:
// nu_r, rho_r), unbounded: each side is an erfc profile around the interface velocity
//   Uc = U0 (b_r - b_l) / (b_r + b_l),  b = rho sqrt(nu) = sqrt(eta rho),
//   u = -U0 + (Uc + U0) erfc(-x / sqrt(4 nu_l t))  (x < 0),  U0 + (Uc - U0) erfc(x / sqrt(4 nu_r
//   t)),
// which is continuous in u and in the shear stress eta du/dx at x = 0 (Carslaw & Jaeger's
// composite-medium solution; the same contact weights as seed 003 eq. 27).
#pragma once

#include <vector>

namespace sph {

struct ShearLayer {
  double U0 = 1.0;         // far-field speed: +U0 for x > 0, -U0 for x < 0
  double half_width = 0.0; // slip walls at x = +-half_width; <= 0: unbounded
  int images = 3;          // wall images per side, used when half_width > 0
};

// One fluid of kinematic viscosity nu (nu = 0: the initial step U0 sign(x)).
double shear_layer_u(const ShearLayer& s, double x, double t, double nu);
// Two fluids (walls ignored).
double shear_layer_u2(const ShearLayer& s, double x, double t, double nu_l, double rho_l,
                      double nu_r, double rho_r);

struct ErfFit {
  double nu = 0.0;       // fitted kinematic viscosity (one fluid), m^2/s
  double nu_left = 0.0;  // two fluids
  double nu_right = 0.0; //
  double rms = 0.0;      // RMS residual of the fit / U0
  int iterations = 0;
  bool converged = false;
};

// Least-squares fit of nu to samples (x_k, u_k) at time t > 0: a scan over the layer width for
// a start, then Gauss-Newton in log(nu) with step halving. Exact data gives nu to round-off.
ErfFit fit_shear_layer(const ShearLayer& s, const std::vector<double>& x,
                       const std::vector<double>& u, double t);
// Two fluids: fits nu_left, nu_right jointly (rho_l, rho_r fixed).
ErfFit fit_shear_layer2(const ShearLayer& s, const std::vector<double>& x,
                        const std::vector<double>& u, double t, double rho_l, double rho_r);

} // namespace sph
