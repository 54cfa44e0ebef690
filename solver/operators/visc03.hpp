// VISC-03: Schwaiger (2008) corrected Laplacian, seed 001 eqs. (17)-(19):
//   lap u_i = N_i { 2 sum_j V_j u_ij (r_ij . grad_i W_ij) / (r_ij^2 + eta^2)
//                   - 2 grad u_i . sum_j V_j grad_i W_ij },
//   grad u_i from the corrected gradient (eq. 18) with Gamma_i (eq. 19).
// Taylor-expanding u_j about r_i (eta = 0), the braces equal B_i : H(u) + O(h), with
//   B_i = sum_j V_j grad_i W_ij (x) (r_j - r_i) = -sum_j V_j (W'/r) r_ji (x) r_ji
// the correction matrix of eq. (19) (see CorrectionMatrix; the seed's H_ab is -B_ab), -> I in the
// continuum limit. The paper prints the factor N_i as "H_bb^{-1} / kappa" and says the size of
// H_bb^{-1} is D x D; the notation admits two readings, both selectable:
//   scalar  N_i = D / tr B_i         (invert the trace H_bb = tr B_i; registry key "visc03"),
//   tensor  N_i = tr(B_i^{-1}) / D = tr Gamma_i / D
//                                    (trace of the D x D inverse, (H^{-1})_bb; key "visc03t").
// Both equal 1 / (tr B_i / D) where B_i is isotropic (a uniform lattice), so there the readings
// agree and the paper's "becomes unity" holds; they differ by the factor tr B_i tr Gamma_i / D^2
// >= 1 (arithmetic vs harmonic mean of the eigenvalues of B_i) on disordered particles. The scalar
// reading is exact for isotropic quadratics (H(u) = c I) given the exact gradient; the tensor
// reading is exact where H(u) is proportional to Gamma_i. Neither can recover tr H(u) from the
// scalar B_i : H(u) for every quadratic. Where B_i is singular, Gamma_i = I (CorrectionMatrix), so
// the tensor factor falls back to 1. The second term removes the first-order error of eq. (15)
// where the kernel-gradient sum does not vanish (disorder, truncated support). On a uniform
// lattice Gamma_i = (D / tr B_i) I and the second term vanishes, so VISC-03 equals VISC-04
// (section 4.4).
#pragma once

#include "operators/field_traits.hpp"
#include "operators/interact.hpp"

namespace sph {

// Which reading of eq. (17)'s factor "H_bb^{-1} / kappa" (see above).
enum class Visc03Reading { Scalar, Tensor };

template <int D, class T>
struct Visc03 {
  const std::vector<double>& V;
  const std::vector<T>& u;
  const std::vector<Grad<D, T>>& grad_u; // corrected gradient of u (eq. 18)
  const std::vector<double>& h_bb;       // tr B_i
  const std::vector<Mat<D>>& gamma;      // Gamma_i = B_i^{-1} (eq. 19)
  Visc03Reading reading;
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
  // N_i of eq. (17) in the chosen reading.
  double normalisation(std::size_t i) const {
    return reading == Visc03Reading::Tensor ? gamma[i].trace() / D : D / h_bb[i];
  }
  void finish(std::size_t i, const Acc& a) {
    out[i] = normalisation(i) * (a.s - 2.0 * along<D>(grad_u[i], a.gw));
  }
};

} // namespace sph
