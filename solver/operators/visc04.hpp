// VISC-04: Oger / Hosseini & Feng / Khayyer corrected form, seed 001 eq. (20):
//   lap u_i = 2 sum_j V_j u_ij (r_ij . Gamma_i grad_i W_ij) / (r_ij^2 + eta^2),
// the hybrid form (15) with the corrected kernel gradient, Gamma_i from eq. (19).
// Registry key "visc04".
#pragma once

#include "operators/field_traits.hpp"
#include "operators/interact.hpp"

namespace sph {

template <int D, class T>
struct Visc04 {
  const std::vector<double>& V;
  const std::vector<T>& u;
  const std::vector<Mat<D>>& gamma;
  double eta2;
  std::vector<T>& out;

  struct Acc {
    T s = zero<T>();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    const double rGw = q.r_ij.dot(gamma[i] * q.grad());
    a.s += (2.0 * V[q.j] * rGw / (q.r * q.r + eta2)) * (u[i] - u[q.j]);
  }
  void finish(std::size_t i, const Acc& a) { out[i] = a.s; }
};

} // namespace sph
