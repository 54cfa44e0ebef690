// VISC-01: hybrid (Morris / Cummins & Rudman) viscous Laplacian, seed 001 (Zheng, Ma & Shao 2018)
// eq. (15):
//   lap u_i = 2 sum_j V_j u_ij (r_ij . grad_i W_ij) / (r_ij^2 + eta^2),   u_ij = u_i - u_j.
// With r_ij . grad_i W_ij = r dW/dr. Registry key "visc01".
#pragma once

#include "operators/field_traits.hpp"
#include "operators/interact.hpp"

namespace sph {

template <int D, class T>
struct Visc01 {
  const std::vector<double>& V;
  const std::vector<T>& u;
  double eta2;
  std::vector<T>& out;

  struct Acc {
    T s = zero<T>();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    const double F = q.r * q.dW / (q.r * q.r + eta2);
    a.s += (2.0 * V[q.j] * F) * (u[i] - u[q.j]);
  }
  void finish(std::size_t i, const Acc& a) { out[i] = a.s; }
};

} // namespace sph
