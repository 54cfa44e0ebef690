// Field sampling and flow integrals for diagnostics.
//
// shepard_sample: velocity at arbitrary points by the normalised (Shepard) SPH interpolation
//   u(x) = sum_j V_j u_j W(x - r_j) / sum_j V_j W(x - r_j)   (Shepard 1968; Liu & Liu 2003, 4.2),
//   over the particles `use(j)` accepts. Walls carry their no-slip (mirrored) velocity, so
//   including them gives the wall value at the wall instead of a one-sided average. Brute force
//   O(points x particles), meant for a few hundred points at the end of a run.
// kinetic_energy: E_k = 1/2 sum_fluid m_i |u_i|^2.
#pragma once

#include "core/particles.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace sph {

template <int D, class Kernel, class Use>
std::vector<Vec<D>> shepard_sample(const Particles<D>& p, const Kernel& kernel,
                                   const std::vector<Vec<D>>& points, Use use) {
  std::vector<Vec<D>> out(points.size());
  const double s2 = kernel.support() * kernel.support();
#pragma omp parallel for schedule(dynamic, 8)
  for (std::size_t k = 0; k < points.size(); ++k) {
    Vec<D> num = Vec<D>::Zero();
    double den = 0.0;
    for (std::size_t j = 0; j < p.size(); ++j) {
      const double r2 = (points[k] - p.r[j]).squaredNorm();
      if (r2 >= s2 || !use(j))
        continue;
      const double w = p.V[j] * kernel.W(std::sqrt(r2));
      num += w * p.v[j], den += w;
    }
    out[k] =
        den > 0.0 ? Vec<D>(num / den) : Vec<D>::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  return out;
}

template <int D>
double kinetic_energy(const Particles<D>& p) {
  double e = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == Kind::Fluid)
      e += 0.5 * p.m[i] * p.v[i].squaredNorm();
  return e;
}

} // namespace sph
