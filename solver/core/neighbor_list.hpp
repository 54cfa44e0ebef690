// Cached neighbour list (compressed rows) with per-pair geometry and kernel values.
//
// Iterative schemes (ISPH matrix assembly, ALSPH inner iterations, acoustic sub-steps) evaluate
// many pair loops on the same configuration; they build this list once per step and every later
// loop streams over it instead of searching again (SPHinXsys keeps a Neighborhood per particle
// for the same reason; ../notes/performance.md). Its pairs come from candidate rows: those of a
// Verlet list kept across steps (core/verlet_list.hpp; the schemes), or those of a cell list
// built for this one call (cells of edge >= the support: every pair within it is a candidate).
//
// Per ordered pair (i, j != i): j, r_ij = r_i - r_j (minimum image), r = |r_ij|, W_ij and
// dW_ij = dW/dr(r). The kernel gradient is grad_i W_ij = dW_ij r_ij / r (see Pair::grad()).
#pragma once

#include "core/cell_list.hpp"
#include "core/verlet_list.hpp"

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
  PairArray<std::uint32_t> j;
  PairArray<Vec<D>> r_ij;
  PairArray<double> r, W, dW;

  std::size_t num_pairs() const { return j.size(); }
  std::size_t num_particles() const { return offset.empty() ? 0 : offset.size() - 1; }

  // The pairs within the support of a Verlet list (core/verlet_list.hpp) on the current
  // positions x (same order), every step: its candidates within kernel.support().
  template <class Kernel>
  void build(const VerletList<D>& vl, const std::vector<Vec<D>>& x, const Kernel& kernel) {
    build_constant_h(vl.rows(), vl.image(), x, kernel, vl.support());
  }
  // Variable smoothing length on a Verlet list (see the cell-list overload below).
  template <class Kernel>
  void build(const VerletList<D>& vl, const std::vector<Vec<D>>& x, const Kernel& kernel,
             const std::vector<double>& h) {
    build_variable_h(vl.rows(), vl.image(), x, kernel, h, vl.support());
  }

  // Rebuilds from a cell list built on positions x (same order): its candidates within the cells'
  // support, then their geometry. Reuses capacity: after the first steps it does not allocate.
  // The candidate rows' scan keeps exactly the pairs with |r_ij|^2 < support^2 (r_ij the same
  // minimum image, to the bit), so their geometry is filled directly, without a second test.
  template <class Kernel>
  void build(const CellList<D>& cells, const std::vector<Vec<D>>& x, const Kernel& kernel) {
    rows_.build(cells, x, cells.support());
    offset = rows_.offset;
    fill_pairs(rows_.j.data(), rows_.offset, x, MinimumImage<D>(cells.domain()),
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
    rows_.build(cells, x, cells.support());
    build_variable_h(rows_, MinimumImage<D>(cells.domain()), x, kernel, h, cells.support());
  }

  Pair<D> pair(std::size_t k) const { return {j[k], r_ij[k], r[k], W[k], dW[k]}; }

private:
  std::vector<std::uint32_t> count_, kept_;
  CandidateRows<D> rows_; // the cell-list overloads' candidates

  template <class Kernel>
  void build_constant_h(const CandidateRows<D>& rows, const MinimumImage<D>& image,
                        const std::vector<Vec<D>>& x, const Kernel& kernel, double support) {
    const double s2 = support * support;
    build_pairs(
        rows, image, x, [s2](std::size_t, std::uint32_t, double r2) { return r2 < s2; },
        [&](std::size_t, std::uint32_t, double rr, double& w, double& dw) {
          w = kernel.W(rr), dw = kernel.dW(rr);
        });
  }

  template <class Kernel>
  void build_variable_h(const CandidateRows<D>& rows, const MinimumImage<D>& image,
                        const std::vector<Vec<D>>& x, const Kernel& kernel,
                        const std::vector<double>& h, double support) {
    const double h0 = kernel.h, s0 = kernel.support() / h0, c2 = support * support;
    build_pairs(
        rows, image, x,
        [&](std::size_t i, std::uint32_t jj, double r2) {
          const double s = s0 * 0.5 * (h[i] + h[jj]);
          return (r2 < c2) & (r2 < s * s);
        },
        [&](std::size_t i, std::uint32_t jj, double rr, double& w, double& dw) {
          const double a = h0 / (0.5 * (h[i] + h[jj])), aD = D == 2 ? a * a : a * a * a;
          w = aD * kernel.W(rr * a), dw = aD * a * kernel.dW(rr * a);
        });
  }

  // The candidates (i, j) that accept(i, j, r2) keeps, r_ij = image(x_i - x_j), with
  // eval(i, j, r, W, dW). Pass 1 tests every candidate branch-free and notes the kept ones in
  // kept_ (at the candidate row's own positions, so particles are independent); the offsets
  // follow from the counts; pass 2 fills the kept pairs. Both passes are parallel over
  // particles and the result does not depend on the number of threads.
  template <class Accept, class Eval>
  void build_pairs(const CandidateRows<D>& rows, const MinimumImage<D>& image,
                   const std::vector<Vec<D>>& x, Accept&& accept, Eval&& eval) {
    const std::size_t N = x.size();
    offset.resize(N + 1);
    count_.resize(N);
    if (kept_.size() < rows.size())
      kept_.resize(rows.size());
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < N; ++i) {
      const Vec<D> xi = x[i];
      const std::uint32_t b = rows.offset[i], e = rows.offset[i + 1];
      std::uint32_t* out = kept_.data() + b;
      std::uint32_t n = 0;
      for (std::uint32_t c = b; c < e; ++c) {
        const std::uint32_t jj = rows.j[c];
        out[n] = jj;
        n += accept(i, jj, image(xi - x[jj]).squaredNorm());
      }
      count_[i] = n;
    }
    offset[0] = 0;
    for (std::size_t i = 0; i < N; ++i)
      offset[i + 1] = offset[i] + count_[i];
    fill_pairs(kept_.data(), rows.offset, x, image, eval);
  }

  // Pass 2 of build_pairs, given the offsets: the pairs of particle i are the first
  // offset[i+1] - offset[i] entries of kept + start[i], filled with j, r_ij = image(x_i - x_j),
  // r and eval(i, j, r, W, dW).
  template <class Eval>
  void fill_pairs(const std::uint32_t* kept, const std::vector<std::uint32_t>& start,
                  const std::vector<Vec<D>>& x, const MinimumImage<D>& image, Eval&& eval) {
    const std::size_t N = x.size();
    const std::size_t P = offset[N];
    j.resize(P), r_ij.resize(P), r.resize(P), W.resize(P), dW.resize(P);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < N; ++i) {
      const Vec<D> xi = x[i];
      const std::uint32_t* in = kept + start[i];
      const std::uint32_t k0 = offset[i], n = offset[i + 1] - offset[i];
      for (std::uint32_t c = 0; c < n; ++c) {
        const std::uint32_t jj = in[c], k = k0 + c;
        const Vec<D> rij = image(xi - x[jj]);
        const double rr = std::sqrt(rij.squaredNorm());
        j[k] = jj, r_ij[k] = rij, r[k] = rr;
        eval(i, jj, rr, W[k], dW[k]);
      }
    }
  }
};

} // namespace sph
