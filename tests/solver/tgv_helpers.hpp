// Helpers of the short analytic-flow tests (tests/solver/test_analytic_*.cpp): the 2D Taylor-Green
// vortex u = U (-cos kx sin ky, sin kx cos ky), k = 2 pi, on a periodic unit square, its amplitude
// measured by least squares, and the exact eigenvalue of a pair-sum Laplacian on the perfect
// lattice for this mode. Scheme-independent.
#pragma once

#include "core/lattice.hpp"
#include "core/particles.hpp"

#include <cmath>
#include <numbers>

namespace sph::testing {

constexpr double tgv_k = 2.0 * std::numbers::pi;

inline Vec2 tgv_shape(const Vec2& x) {
  const double k = tgv_k;
  return Vec2(-std::cos(k * x[0]) * std::sin(k * x[1]), std::sin(k * x[0]) * std::cos(k * x[1]));
}

// n^2 particles of mass dx^2, density 1, on the cell-centred lattice, velocity U tgv_shape.
inline void tgv_lattice(Particles<2>& p, int n, double U) {
  const double dx = 1.0 / n;
  for_each_lattice_point<2>({0, 0}, {n, n}, dx, [&](const Vec2& x, const std::array<int, 2>&) {
    const std::size_t i = p.add(x, dx * dx, 1.0);
    p.v[i] = U * tgv_shape(x);
    p.V[i] = dx * dx;
  });
}

// Least-squares amplitude of the velocity field in the mode, at the particles' current positions
// (the Taylor-Green solution is u(x, t) = A(t) tgv_shape(x)).
inline double tgv_amplitude(const Particles<2>& p) {
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] != Kind::Fluid)
      continue;
    const Vec2 s = tgv_shape(p.r[i]);
    num += s.dot(p.v[i]), den += s.squaredNorm();
  }
  return num / den;
}

// sum over the perfect lattice's offsets r (spacing dx, |r| < support) of w(r) (cos(k r_x)
// cos(k r_y) - 1): the eigenvalue, for the Taylor-Green mode, of L u_i = sum_j w_ij (u_j - u_i).
template <class F>
double tgv_eigenvalue(double dx, double support, F w) {
  const int m = static_cast<int>(std::ceil(support / dx)) + 1;
  double s = 0.0;
  for (int a = -m; a <= m; ++a)
    for (int b = -m; b <= m; ++b) {
      const double r = dx * std::hypot(a, b);
      if (r == 0.0 || r >= support)
        continue;
      s += w(r) * (std::cos(tgv_k * a * dx) * std::cos(tgv_k * b * dx) - 1.0);
    }
  return s;
}

} // namespace sph::testing
