// Kernel-gradient correction matrix (seed 001, Zheng, Ma & Shao 2018, eq. 19; Oger et al. 2007;
// seed 004 eq. 16):
//   B_i = sum_j V_j grad_i W_ij (x) (r_j - r_i),     Gamma_i = B_i^{-1},
// so that the corrected gradient sum_j V_j (f_j - f_i) Gamma_i grad_i W_ij is exact for linear f
// (see CorrectedGradient). Also stores tr B_i = sum_j V_j (r_j - r_i) . grad_i W_ij, which is the
// H_bb of VISC-03 (eq. 17) and equals the dimension D in the continuum limit.
// Where B_i is singular (too few neighbours) Gamma_i falls back to the identity.
#pragma once

#include "operators/field_traits.hpp"
#include "operators/interact.hpp"

#include <vector>

namespace sph {

template <int D>
struct CorrectionMatrix {
  const std::vector<double>& V;
  std::vector<Mat<D>>& gamma;
  std::vector<double>& trace_b; // may alias a scratch array; written for every selected particle

  struct Acc {
    Mat<D> b = Mat<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t, const Pair<D>& q, Acc& a) const {
    a.b.noalias() -= V[q.j] * q.grad() * q.r_ij.transpose(); // r_j - r_i = -r_ij
  }
  void finish(std::size_t i, const Acc& a) {
    trace_b[i] = a.b.trace();
    const double det = a.b.determinant();
    const double scale = std::pow(a.b.norm(), D);
    gamma[i] = std::abs(det) > 1e-12 * scale ? Mat<D>(a.b.inverse()) : Mat<D>::Identity();
  }
};

// Corrected gradient (seed 001 eq. 18): grad f_i = sum_j V_j (f_j - f_i) Gamma_i grad_i W_ij.
// Exact for linear fields on any particle arrangement with invertible B_i.
template <int D, class T>
struct CorrectedGradient {
  const std::vector<double>& V;
  const std::vector<Mat<D>>& gamma;
  const std::vector<T>& f;
  std::vector<Grad<D, T>>& grad;

  struct Acc {
    Grad<D, T> g = zero<Grad<D, T>>();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    a.g += V[q.j] * outer<D>(f[q.j] - f[i], Vec<D>(gamma[i] * q.grad()));
  }
  void finish(std::size_t i, const Acc& a) { grad[i] = a.g; }
};

} // namespace sph
