// Cell-linked list neighbour search, O(N) per build.
//
// build() bins particles into cells of edge >= the support radius, sorts them by cell with a
// counting sort (histogram, prefix sum, scatter) and reorders every particle field through that
// permutation, so that the particles of one cell, and of one x-row of cells, are contiguous in
// memory. Cells are numbered x-fastest: the 3 cells of a neighbouring x-row form one contiguous
// particle range, so a particle's candidates are 3 ranges in 2D and 9 in 3D, each a straight
// streaming loop (DualSPHysics and SPHinXsys do the same; ../notes/performance.md).
//
// Periodic axes: positions are wrapped into the box and a neighbour cell that wraps around
// contributes the image shift to r_ij = r_i - r_j, so r_ij is always the minimum image. A periodic
// axis needs at least 3 cells (box length >= 3 support radii) so that no cell is visited twice.
// Non-periodic axes follow the particles' bounding box at every build.
#pragma once

#include "core/domain.hpp"
#include "core/particles.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph {

template <int D>
class CellList {
public:
  CellList(const Domain<D>& domain, double support) : domain_(domain), support_(support) {
    if (!(support > 0.0))
      throw std::invalid_argument("CellList: support radius must be > 0");
    for (int a = 0; a < D; ++a) {
      if (!domain.periodic[a])
        continue;
      const double L = domain.hi[a] - domain.lo[a];
      if (std::floor(L / support) < 3.0)
        throw std::invalid_argument(
            "CellList: periodic axis " + std::to_string(a) + " has length " + std::to_string(L) +
            ", needs at least 3 support radii (" + std::to_string(3 * support) + ")");
    }
  }

  double support() const { return support_; }
  const Domain<D>& domain() const { return domain_; }

  // Wraps periodic coordinates, sorts the particles by cell (reordering every field of p).
  void build(Particles<D>& p) {
    wrap(p.r);
    index(p.r);
    p.reorder(perm_);
    // Cell of every particle in the new order, for neighbour look-ups.
    cell_sorted_.resize(perm_.size());
    for (std::size_t i = 0; i < perm_.size(); ++i)
      cell_sorted_[i] = cell_[perm_[i]];
  }

  // Permutation of the last build: new index i holds old index perm()[i].
  const std::vector<std::uint32_t>& perm() const { return perm_; }
  std::size_t num_cells() const { return start_.empty() ? 0 : start_.size() - 1; }

  // Calls f(j, r_ij, r2) for every particle j != i with |r_ij|^2 < support^2, where
  // r_ij = r_i - r_j (minimum image). r must be the positions in the order of the last build.
  template <class F>
  void for_each_neighbor(std::size_t i, const std::vector<Vec<D>>& r, F&& f) const {
    const double s2 = support_ * support_;
    const Vec<D> ri = r[i];
    for_each_range(i, [&](std::uint32_t b, std::uint32_t e, const Vec<D>& shift) {
      for (std::uint32_t j = b; j < e; ++j) {
        const Vec<D> rij = ri - r[j] + shift;
        const double r2 = rij.squaredNorm();
        if (r2 < s2 && j != i)
          f(j, rij, r2);
      }
    });
  }

  // The candidates of particle i (i itself included) as contiguous ranges of the particle order:
  // f(b, e, shift) for the particles [b, e) of one neighbour x-row of cells, shift the periodic
  // image to add to r_i - r_j. The cells within k of i's cell along every axis (k = 1: 3 ranges in
  // 2D, 9 in 3D; k = 2: 5 and 25), plus one wrapped block of cells per row on a periodic x axis.
  // A periodic axis must have at least 2k + 1 cells (max_reach()).
  template <class F>
  void for_each_range(std::size_t i, F&& f, int k = 1) const {
    std::array<int, D> c;
    decode(cell_sorted_[i], c);
    // Loop over the neighbour rows (all offsets of axes 1..D-1), then the x-range of each row.
    const int w = 2 * k + 1, rows = D == 2 ? w : w * w;
    for (int row = 0; row < rows; ++row) {
      Vec<D> shift = Vec<D>::Zero();
      int off = 0, stride = n_[0];
      bool skip = false;
      for (int a = 1; a < D; ++a) {
        const int d = (a == 1 ? row % w : row / w) - k;
        int ca = c[a] + d;
        if (ca < 0 || ca >= n_[a]) {
          if (!domain_.periodic[a]) {
            skip = true;
            break;
          }
          shift[a] = ca < 0 ? len_[a] : -len_[a];
          ca = ca < 0 ? ca + n_[a] : ca - n_[a];
        }
        off += ca * stride;
        stride *= n_[a];
      }
      if (skip)
        continue;
      // x-range: contiguous cells [x0, x1] plus, on a periodic x axis, the wrapped block.
      int x0 = c[0] - k, x1 = c[0] + k;
      if (x0 < 0) {
        if (domain_.periodic[0]) {
          shift[0] = len_[0];
          f(start_[off + n_[0] + x0], start_[off + n_[0]], shift);
        }
        x0 = 0;
      }
      if (x1 >= n_[0]) {
        if (domain_.periodic[0]) {
          shift[0] = -len_[0];
          f(start_[off], start_[off + x1 - n_[0] + 1], shift);
        }
        x1 = n_[0] - 1;
      }
      shift[0] = 0.0;
      f(start_[off + x0], start_[off + x1 + 1], shift);
    }
  }

  // The largest k of for_each_range the periodic axes allow (2k + 1 cells; unbounded: INT_MAX).
  int max_reach() const {
    int k = std::numeric_limits<int>::max();
    for (int a = 0; a < D; ++a)
      if (domain_.periodic[a])
        k = std::min(
            k, static_cast<int>(std::floor((domain_.hi[a] - domain_.lo[a]) / support_) - 1) / 2);
    return k;
  }

  // out[i] = the largest v[j] over the particles j in the cells within k of particle i's cell
  // along every axis (the cells for_each_range(i, f, k) visits); v in the order of the last build.
  // A max filter over the cells, one axis at a time: O(cells x (2k + 1) x D).
  void neighbourhood_max(const std::vector<double>& v, int k, std::vector<double>& out) {
    const std::size_t N = v.size(), total = num_cells();
    cell_max_.assign(total, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < N; ++i)
      cell_max_[cell_sorted_[i]] = std::max(cell_max_[cell_sorted_[i]], v[i]);
    std::size_t stride = 1;
    for (int a = 0; a < D; ++a) {
      const int n = n_[a];
      tmp_.resize(total);
      for (std::size_t c = 0; c < total; ++c) {
        const int ca = static_cast<int>((c / stride) % static_cast<std::size_t>(n));
        const std::size_t base = c - static_cast<std::size_t>(ca) * stride;
        double m = cell_max_[c];
        for (int d = -k; d <= k; ++d) {
          int cb = ca + d;
          if (cb < 0 || cb >= n) {
            if (!domain_.periodic[a])
              continue;
            cb = (cb + n) % n;
          }
          m = std::max(m, cell_max_[base + static_cast<std::size_t>(cb) * stride]);
        }
        tmp_[c] = m;
      }
      cell_max_.swap(tmp_);
      stride *= static_cast<std::size_t>(n);
    }
    out.resize(N);
    for (std::size_t i = 0; i < N; ++i)
      out[i] = cell_max_[cell_sorted_[i]];
  }

  // Wraps the coordinates of periodic axes into [lo, hi) (build() does it first).
  void wrap(std::vector<Vec<D>>& r) const {
    for (int a = 0; a < D; ++a) {
      if (!domain_.periodic[a])
        continue;
      const double lo = domain_.lo[a], L = domain_.hi[a] - lo;
      for (auto& x : r) {
        double y = x[a] - lo;
        if (y < 0.0 || y >= L) {
          y -= L * std::floor(y / L);
          if (y >= L)
            y = 0.0; // round-off at the top edge
          x[a] = lo + y;
        }
      }
    }
  }

  // The cells of positions that an earlier build() left wrapped and sorted (a resumed run
  // rebuilding the list of a saved configuration): the same cells as that build, no reordering.
  void index_sorted(const std::vector<Vec<D>>& r) {
    index(r);
    for (std::size_t i = 0; i < perm_.size(); ++i)
      if (perm_[i] != i)
        throw std::logic_error("CellList::index_sorted: the positions are not in cell order");
    cell_sorted_ = cell_;
  }

private:
  Domain<D> domain_;
  double support_;
  std::array<int, D> n_{};      // cells per axis
  Vec<D> lo_, cell_size_, len_; // grid origin, cell edge, periodic length
  std::vector<std::uint32_t> cell_, cell_sorted_, perm_, start_, count_;
  std::vector<double> cell_max_, tmp_; // neighbourhood_max's buffers

  void index(const std::vector<Vec<D>>& r) {
    const std::size_t N = r.size();
    Vec<D> lo, hi;
    if (N > 0) {
      lo = hi = r[0];
      for (const auto& x : r)
        lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    } else {
      lo = domain_.lo, hi = domain_.hi;
    }
    std::size_t total = 1;
    for (int a = 0; a < D; ++a) {
      if (domain_.periodic[a]) {
        lo[a] = domain_.lo[a];
        len_[a] = domain_.hi[a] - domain_.lo[a];
        n_[a] = static_cast<int>(std::floor(len_[a] / support_));
        cell_size_[a] = len_[a] / n_[a];
      } else {
        len_[a] = 0.0;
        n_[a] = std::max(1, static_cast<int>(std::floor((hi[a] - lo[a]) / support_)) + 1);
        cell_size_[a] = support_;
      }
      total *= static_cast<std::size_t>(n_[a]);
    }
    lo_ = lo;
    if (total > (std::size_t{1} << 31))
      throw std::runtime_error("CellList: too many cells");
    cell_.resize(N);
    count_.assign(total + 1, 0);
    for (std::size_t i = 0; i < N; ++i) {
      std::uint32_t c = 0, stride = 1;
      for (int a = 0; a < D; ++a) {
        int ca = static_cast<int>((r[i][a] - lo_[a]) / cell_size_[a]);
        ca = std::clamp(ca, 0, n_[a] - 1);
        c += static_cast<std::uint32_t>(ca) * stride;
        stride *= static_cast<std::uint32_t>(n_[a]);
      }
      cell_[i] = c;
      ++count_[c + 1];
    }
    start_.resize(total + 1);
    start_[0] = 0;
    for (std::size_t c = 0; c < total; ++c)
      start_[c + 1] = start_[c] + count_[c + 1];
    // Scatter, stable in the old order.
    perm_.resize(N);
    for (std::size_t c = 0; c < total; ++c)
      count_[c] = start_[c];
    for (std::size_t i = 0; i < N; ++i)
      perm_[count_[cell_[i]]++] = static_cast<std::uint32_t>(i);
  }

  void decode(std::uint32_t c, std::array<int, D>& out) const {
    for (int a = 0; a < D; ++a) {
      out[a] = static_cast<int>(c % static_cast<std::uint32_t>(n_[a]));
      c /= static_cast<std::uint32_t>(n_[a]);
    }
  }
};

} // namespace sph
