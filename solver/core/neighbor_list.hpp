// Cached neighbour list (compressed rows) with per-pair geometry and kernel values.
//
// Iterative schemes (ISPH matrix assembly, ALSPH inner iterations, acoustic sub-steps) evaluate
// many pair loops on the same configuration; they build this list once per step from the cell list
// and every later loop streams over it instead of searching again (SPHinXsys keeps a Neighborhood
// per particle for the same reason; ../notes/performance.md).
//
// Per ordered pair (i, j != i): j, r_ij = r_i - r_j (minimum image), r = |r_ij|, W_ij and
// dW_ij = dW/dr(r). The kernel gradient is grad_i W_ij = dW_ij r_ij / r (see Pair::grad()).
#pragma once

#include "core/cell_list.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace sph {

// One neighbour pair as an operator sees it, whichever driver produced it.
template <int D>
struct Pair {
  std::uint32_t j;
  Vec<D> r_ij; // r_i - r_j
  double r;    // |r_ij|
  double W;    // W(r, h)
  double dW;   // dW/dr at r (<= 0)
  // grad_i W(r_i - r_j, h)
  Vec<D> grad() const { return (dW / r) * r_ij; }
};

template <int D>
class NeighborList {
public:
  std::vector<std::uint32_t> offset; // pairs of particle i are [offset[i], offset[i+1])
  std::vector<std::uint32_t> j;
  std::vector<Vec<D>> r_ij;
  std::vector<double> r, W, dW;

  std::size_t num_pairs() const { return j.size(); }
  std::size_t num_particles() const { return offset.empty() ? 0 : offset.size() - 1; }

  // Rebuilds from a cell list built on positions x (same order). Reuses capacity: after the
  // first steps it does not allocate.
  template <class Kernel>
  void build(const CellList<D>& cells, const std::vector<Vec<D>>& x, const Kernel& kernel) {
    build_pairs(
        cells, x, [](std::size_t, std::uint32_t, double) { return true; },
        [&](std::size_t, std::uint32_t, double rr, double& w, double& dw) {
          w = kernel.W(rr), dw = kernel.dW(rr);
        });
  }

  // Variable smoothing length (h[i] per particle): the pair's kernel has h_ij = (h_i + h_j) / 2,
  // evaluated by scaling `kernel` (smoothing length h0 = kernel.h): W(r, h) = (h0/h)^D W(r h0/h)
  // and dW(r, h) = (h0/h)^(D+1) dW(r h0/h), exact for kernels of the form h^-D f(r/h). Pairs
  // beyond their own support are left out; the cell list must be built for the largest support.
  template <class Kernel>
  void build(const CellList<D>& cells, const std::vector<Vec<D>>& x, const Kernel& kernel,
             const std::vector<double>& h) {
    const double h0 = kernel.h, s0 = kernel.support() / h0;
    build_pairs(
        cells, x,
        [&](std::size_t i, std::uint32_t jj, double r2) {
          const double s = s0 * 0.5 * (h[i] + h[jj]);
          return r2 < s * s;
        },
        [&](std::size_t i, std::uint32_t jj, double rr, double& w, double& dw) {
          const double a = h0 / (0.5 * (h[i] + h[jj])), aD = D == 2 ? a * a : a * a * a;
          w = aD * kernel.W(rr * a), dw = aD * a * kernel.dW(rr * a);
        });
  }

  Pair<D> pair(std::size_t k) const { return {j[k], r_ij[k], r[k], W[k], dW[k]}; }

private:
  std::vector<std::uint32_t> count_;

  // The candidates of the cell list that accept(i, j, r2) keeps, with eval(i, j, r, W, dW):
  // pass 1 counts, pass 2 fills (each in parallel over particles).
  template <class Accept, class Eval>
  void build_pairs(const CellList<D>& cells, const std::vector<Vec<D>>& x, Accept&& accept,
                   Eval&& eval) {
    const std::size_t N = x.size();
    offset.resize(N + 1);
    count_.resize(N);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::size_t i = 0; i < N; ++i) {
      std::uint32_t n = 0;
      cells.for_each_neighbor(
          i, x, [&](std::uint32_t jj, const Vec<D>&, double r2) { n += accept(i, jj, r2); });
      count_[i] = n;
    }
    offset[0] = 0;
    for (std::size_t i = 0; i < N; ++i)
      offset[i + 1] = offset[i] + count_[i];
    const std::size_t P = offset[N];
    j.resize(P), r_ij.resize(P), r.resize(P), W.resize(P), dW.resize(P);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::size_t i = 0; i < N; ++i) {
      std::uint32_t k = offset[i];
      cells.for_each_neighbor(i, x, [&](std::uint32_t jj, const Vec<D>& rij, double r2) {
        if (!accept(i, jj, r2))
          return;
        const double rr = std::sqrt(r2);
        j[k] = jj, r_ij[k] = rij, r[k] = rr;
        eval(i, jj, rr, W[k], dW[k]);
        ++k;
      });
    }
  }
};

} // namespace sph
