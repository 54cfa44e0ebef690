// VISC-02: direct form (Gotoh et al. 2001), the divergence of the SPH gradient, i.e. the SPH
// interpolant differentiated twice, seed 001 section 3.2 / eq. (16):
//   lap u_i = sum_j V_j (u_j - u_i) lap W_ij,   lap W = d2W/dr2 + (D - 1)/r dW/dr.
// Note on eq. (16) as printed, sum_j V_j u_ij (d2W/dr2 - dW/dr / r): expanding u_ij = u_i - u_j to
// second order gives -2 lap u in 2D, not lap u, so the printed signs cannot be what the authors
// ran; the form above is the one the text derives and is consistent (exact on quadratics in the
// continuum limit). Registry key "visc02".
//
// Visc02Printed (registry key "visc02p"): the weight of eq. (16) as printed, with the sign and the
// factor that make it consistent,
//   lap u_i = 2 / (D + 2) sum_j V_j (u_j - u_i) (d2W/dr2 - dW/dr / r),
// (the second moment of W'' - W'/r is D (D + 2), against 2 D for lap W). For the cubic spline
// W'' - W'/r > 0 at every q (2.25 q sigma / h^2 for q < 1, 1.5 (2 - q) + 0.75 (2 - q)^2 / q
// beyond), so every pair weight is positive and the operator is non-positive (a weighted graph
// Laplacian) on any particle arrangement, where lap W changes sign at q = 0.889 (h = 1.2 dx: the
// nearest lattice neighbours, q = 0.833, get negative weights, and a disordered arrangement has
// positive eigenvalues: tests/solver/test_visc_spectrum.cpp). In 2D it is the mean of lap W and the
// Brookshaw weight -2 W'/r of VISC-01.
#pragma once

#include "operators/field_traits.hpp"
#include "operators/interact.hpp"

namespace sph {

// The pair weight of each reading and its overall factor (policies of Visc02Form).
struct LapWWeight { // lap W = W'' + (D - 1) W'/r
  template <int D, class Kernel>
  static double weight(const Kernel& kernel, const Pair<D>& q) {
    return kernel.d2W(q.r) + (D - 1) * q.dW / q.r;
  }
  template <int D>
  static constexpr double factor = 1.0;
};
struct PrintedWeight { // eq. (16) as printed, W'' - W'/r, with the factor 2 / (D + 2)
  template <int D, class Kernel>
  static double weight(const Kernel& kernel, const Pair<D>& q) {
    return kernel.d2W(q.r) - q.dW / q.r;
  }
  template <int D>
  static constexpr double factor = 2.0 / (D + 2);
};

// lap u_i = factor sum_j V_j (u_j - u_i) weight_ij.
template <int D, class T, class Kernel, class Weight>
struct Visc02Form {
  const std::vector<double>& V;
  const std::vector<T>& u;
  const Kernel& kernel;
  std::vector<T>& out;

  struct Acc {
    T s = zero<T>();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    const double w = Weight::template weight<D>(kernel, q);
    a.s += (V[q.j] * w) * (u[q.j] - u[i]);
  }
  void finish(std::size_t i, const Acc& a) { out[i] = Weight::template factor<D> * a.s; }
};

template <int D, class T, class Kernel>
using Visc02 = Visc02Form<D, T, Kernel, LapWWeight>;
template <int D, class T, class Kernel>
using Visc02Printed = Visc02Form<D, T, Kernel, PrintedWeight>;

} // namespace sph
