// VISC-03: Schwaiger (2008) corrected Laplacian, seed 001 eqs. (17)-(19):
//   lap u_i = (D / H_bb) { 2 sum_j V_j u_ij (r_ij . grad_i W_ij) / (r_ij^2 + eta^2)
//                          - 2 grad u_i . sum_j V_j grad_i W_ij },
//   grad u_i from the corrected gradient (eq. 18) with Gamma_i (eq. 19),
//   H_bb = sum_j V_j (r_j - r_i) . grad_i W_ij = tr B_i (see CorrectionMatrix), -> D in the limit.
// The second term removes the first-order error of eq. (15) where the kernel-gradient sum does not
// vanish (disorder, truncated support); the factor D / H_bb normalises the second moment. The paper
// prints the factor as H_bb^{-1} / kappa and says it "becomes unity" on a uniform lattice: that
// holds for D / H_bb with H_bb as defined here, which is what we use. On a uniform lattice
// Gamma_i = (D / H_bb) I and the second term vanishes, so VISC-03 equals VISC-04 (section 4.4).
// Registry key "visc03".
#pragma once

#include "operators/field_traits.hpp"
#include "operators/interact.hpp"

namespace sph {

template <int D, class T>
struct Visc03 {
  const std::vector<double>& V;
  const std::vector<T>& u;
  const std::vector<Grad<D, T>>& grad_u; // corrected gradient of u (eq. 18)
  const std::vector<double>& h_bb;       // tr B_i
  double eta2;
  std::vector<T>& out;

  struct Acc {
    T s = zero<T>();
    Vec<D> gw = Vec<D>::Zero(); // sum_j V_j grad_i W_ij
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    const double F = q.r * q.dW / (q.r * q.r + eta2);
    a.s += (2.0 * V[q.j] * F) * (u[i] - u[q.j]);
    a.gw += V[q.j] * q.grad();
  }
  void finish(std::size_t i, const Acc& a) {
    out[i] = (D / h_bb[i]) * (a.s - 2.0 * along<D>(grad_u[i], a.gw));
  }
};

} // namespace sph
