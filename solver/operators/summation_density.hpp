// Summation density, rho_i = sum_j m_j W_ij (including j = i), and the particle volume
// V_i = 1 / sum_j W_ij used by seed 004 (Kolukisa et al. 2021, after eq. 14).
// The reference operator of the pair-loop design, and the density loop of the benchmark.
#pragma once

#include "core/particles.hpp"
#include "operators/interact.hpp"

namespace sph {

template <int D, class Kernel>
struct SummationDensity {
  Particles<D>& p;
  const Kernel& kernel;

  struct Acc {
    double rho = 0.0, w = 0.0;
  };
  Acc init(std::size_t i) const {
    const double W0 = kernel.W(0.0);
    return {p.m[i] * W0, W0};
  }
  void pair(std::size_t, const Pair<D>& q, Acc& a) const {
    a.rho += p.m[q.j] * q.W;
    a.w += q.W;
  }
  void finish(std::size_t i, const Acc& a) {
    p.rho[i] = a.rho;
    p.V[i] = 1.0 / a.w;
  }
};

} // namespace sph
