// VISC-02: direct form (Gotoh et al. 2001), the divergence of the SPH gradient, i.e. the SPH
// interpolant differentiated twice, seed 001 section 3.2 / eq. (16):
//   lap u_i = sum_j V_j (u_j - u_i) lap W_ij,   lap W = d2W/dr2 + (D - 1)/r dW/dr.
// Note on eq. (16) as printed, sum_j V_j u_ij (d2W/dr2 - dW/dr / r): expanding u_ij = u_i - u_j to
// second order gives -2 lap u in 2D, not lap u, so the printed signs cannot be what the authors
// ran; the form above is the one the text derives and is consistent (exact on quadratics in the
// continuum limit). Registry key "visc02".
#pragma once

#include "operators/field_traits.hpp"
#include "operators/interact.hpp"

namespace sph {

template <int D, class T, class Kernel>
struct Visc02 {
  const std::vector<double>& V;
  const std::vector<T>& u;
  const Kernel& kernel;
  std::vector<T>& out;

  struct Acc {
    T s = zero<T>();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    const double lapW = kernel.d2W(q.r) + (D - 1) * q.dW / q.r;
    a.s += (V[q.j] * lapW) * (u[q.j] - u[i]);
  }
  void finish(std::size_t i, const Acc& a) { out[i] = a.s; }
};

} // namespace sph
