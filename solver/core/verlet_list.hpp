// Verlet neighbour list with a skin (Verlet 1967; LAMMPS's `neighbor SKIN bin` with
// `neigh_modify every 1 delay 0 check yes`): the candidate pairs within cutoff = support + skin of
// a configuration r0, kept across steps and rebuilt only when some particle has moved more than
// skin/2 from r0 (checked every step). Until then every pair within the support is a candidate: two
// particles that each moved at most skin/2 are at most skin closer than they were at the build.
//
// The candidates come from the cell list (core/cell_list.hpp) with cells of edge >= the cutoff: a
// build wraps the periodic coordinates, sorts the particles by cell (reordering every field, so the
// particle order changes only at a build) and scans the 3 (2D) or 9 (3D) contiguous x-rows of each
// particle's neighbour cells (CandidateRows::scan).
//
// Variable smoothing length (two resolution levels, boundaries/refinement.hpp): the cutoff of a
// pair is s0 (h_i + h_j) / 2 + skin, the cells are sized for the smallest pair, and each particle
// scans as many cells as the largest h near it needs (CandidateRows' second build), so a fine
// particle's candidates are those of the fine support, not of the coarse one.
//
// The pair geometry of the current positions (r_ij, r, W, dW of the pairs within the support) is
// not stored here: NeighborList::build(VerletList, ...) recomputes it from the candidates every
// step (core/neighbor_list.hpp), with the minimum image on periodic axes.
#pragma once

#include "core/cell_list.hpp"
#include "core/domain.hpp"
#include "core/pair_array.hpp"
#include "core/particles.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <omp.h>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph {

// Candidate rows in compressed form: the candidates of particle i are j[offset[i] .. offset[i+1]).
template <int D>
class CandidateRows {
public:
  std::vector<std::uint32_t> offset;
  PairArray<std::uint32_t> j;

  std::size_t size() const { return j.size(); }
  std::size_t num_particles() const { return offset.empty() ? 0 : offset.size() - 1; }

  // Every pair (i, j != i) with |r_i - r_j + shift|^2 < cutoff^2 (the cell list's minimum image),
  // in the order of the cell list's scan; cutoff <= the cells' edge, x in the order of the
  // cells' last build. Reuses its buffers: after the first builds it does not allocate.
  void build(const CellList<D>& cells, const std::vector<Vec<D>>& x, double cutoff) {
    const double c2 = cutoff * cutoff;
    scan(
        cells, x, [](std::size_t) { return 1; },
        [c2](std::size_t, std::uint32_t, double r2) { return r2 < c2; });
  }

  // Variable smoothing length: every pair (i, j != i) with |r_ij| < s0 (h_i + h_j) / 2 + skin,
  // s0 the kernel's support per unit h, h and x in the order of the cells' last build, H[i] the
  // largest h in the cells within reach of particle i's (CellList::neighbourhood_max). Particle i
  // scans the cells within k_i = ceil((s0 (h_i + H_i) / 2 + skin) / edge) of its own: with cells
  // sized for the smallest pair, a fine particle with no coarse one near scans the 3^D cells of
  // its own support, not those of the coarse support (issue 19: the cell list per level).
  void build(const CellList<D>& cells, const std::vector<Vec<D>>& x, const std::vector<double>& h,
             const std::vector<double>& H, double s0, double skin) {
    const double half = 0.5 * s0, edge = cells.support();
    scan(
        cells, x,
        [&](std::size_t i) {
          return std::max(1, static_cast<int>(std::ceil((half * (h[i] + H[i]) + skin) / edge)));
        },
        [&](std::size_t i, std::uint32_t jj, double r2) {
          const double c = half * (h[i] + h[jj]) + skin;
          return r2 < c * c;
        });
  }

private:
  // The rows: particle i scans the cells within reach(i) of its own and keeps the candidates j
  // != i with accept(i, j, r2). The scan is branch-free, as LAMMPS's binned build: every
  // candidate is written and the write position advances by the test, so a neighbour test never
  // mispredicts; each thread fills its own buffer over a contiguous range of particles and the
  // buffers are concatenated, so the rows come out in the same order for any number of threads.
  template <class Reach, class Accept>
  void scan(const CellList<D>& cells, const std::vector<Vec<D>>& x, Reach&& reach,
            Accept&& accept) {
    const std::size_t N = x.size();
    offset.resize(N + 1);
    const int T = omp_get_max_threads();
    if (buf_.size() < static_cast<std::size_t>(T))
      buf_.resize(T);
    base_.assign(T + 1, 0);
    bool overflow = false;
#pragma omp parallel num_threads(T)
    {
      const int t = omp_get_thread_num(), nt = omp_get_num_threads();
      const std::size_t a = N * t / nt, b = N * (t + 1) / nt;
      std::vector<std::uint32_t>& buf = buf_[t];
      std::size_t n = 0;
      for (std::size_t i = a; i < b; ++i) {
        offset[i] = static_cast<std::uint32_t>(n);
        const Vec<D> xi = x[i];
        cells.for_each_range(
            i,
            [&](std::uint32_t jb, std::uint32_t je, const Vec<D>& shift) {
              if (buf.size() < n + (je - jb))
                buf.resize(2 * (n + (je - jb)));
              std::uint32_t* out = buf.data();
              for (std::uint32_t jj = jb; jj < je; ++jj) {
                const Vec<D> rij = xi - x[jj] + shift; // as CellList::for_each_neighbor rounds it
                out[n] = jj;
                n += accept(i, jj, rij.squaredNorm()) & (jj != i);
              }
            },
            reach(i));
      }
      base_[t + 1] = n;
#pragma omp barrier
#pragma omp single
      {
        for (int s = 0; s < nt; ++s)
          base_[s + 1] += base_[s];
        overflow = base_[nt] > std::numeric_limits<std::uint32_t>::max();
        j.resize(overflow ? 0 : base_[nt]);
        offset[N] = static_cast<std::uint32_t>(overflow ? 0 : base_[nt]);
      }
      const std::size_t s = overflow ? 0 : base_[t];
      if (overflow)
        n = 0;
      std::copy(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n),
                j.begin() + static_cast<std::ptrdiff_t>(s));
      for (std::size_t i = a; i < b; ++i)
        offset[i] += static_cast<std::uint32_t>(s);
    }
    if (overflow)
      throw std::runtime_error("CandidateRows: more than 2^32 candidate pairs");
  }

  std::vector<std::vector<std::uint32_t>> buf_; // one per thread
  std::vector<std::size_t> base_;               // each thread's first row position
};

template <int D>
class VerletList {
public:
  // support: the largest pair distance the loops need; skin >= 0. A periodic axis must hold 3
  // cutoffs (see largest_skin).
  VerletList(const Domain<D>& box, double support, double skin)
      : cells_(box, support + skin), image_(box), support_(support), skin_(skin) {
    if (!(skin >= 0.0))
      throw std::invalid_argument("VerletList: skin must be >= 0");
  }

  // Variable smoothing length h, the scalar field h_field of the particles: the cutoff of a pair
  // is s0 (h_i + h_j) / 2 + skin (s0 the kernel's support per unit h), the cells are sized for the
  // smallest pair, s0 h_min + skin, and support() is the largest pair's, s0 h_max (no particle's
  // h may exceed h_max; a build checks it).
  VerletList(const Domain<D>& box, double s0, double h_min, double h_max, double skin, int h_field)
      : cells_(box, s0 * h_min + skin), image_(box), support_(s0 * h_max), skin_(skin), s0_(s0),
        h_field_(h_field) {
    if (!(skin >= 0.0) || !(h_min > 0.0) || h_max < h_min || h_field < 0)
      throw std::invalid_argument("VerletList: needs skin >= 0, 0 < h_min <= h_max, an h field");
  }

  // The largest skin up to `wanted` that the box allows: 3 cutoffs per periodic axis, the cell
  // list's condition (0 when the box holds no more than 3 supports).
  static double largest_skin(const Domain<D>& box, double support, double wanted) {
    double s = wanted;
    for (int a = 0; a < D; ++a)
      if (box.periodic[a])
        s = std::min(s, (box.hi[a] - box.lo[a]) / 3.0 * (1.0 - 1e-12) - support);
    return std::max(s, 0.0);
  }

  double support() const { return support_; }
  double skin() const { return skin_; }
  double cutoff() const { return support_ + skin_; }
  const CandidateRows<D>& rows() const { return rows_; }
  const MinimumImage<D>& image() const { return image_; }
  const CellList<D>& cells() const { return cells_; }
  // Reference positions: those of the last build, in the current particle order (checkpoints).
  const std::vector<Vec<D>>& reference() const { return r0_; }
  long builds() const { return builds_; }

  // Once per step, before the pair geometry is recomputed: wraps the periodic coordinates of p
  // and rebuilds (sorting p by cell) when there is no list yet, the particle count changed or the
  // largest displacement since the last build exceeds skin/2. Returns whether it rebuilt.
  bool update(Particles<D>& p) {
    cells_.wrap(p.r);
    if (built_ && r0_.size() == p.size() && max_displacement2(p.r) <= 0.25 * skin_ * skin_)
      return false;
    rebuild(p);
    return true;
  }

  // Sorts p by cell and builds the candidates of its current positions.
  void rebuild(Particles<D>& p) {
    cells_.build(p);
    r0_ = p.r;
    build_rows(p);
    built_ = true;
    ++builds_;
  }

  // A resumed run: the list of the build whose reference positions r0 a checkpoint saved (the
  // particles p are in that build's order, so the cell sort is the identity and nothing moves).
  // The same candidates in the same order as the uninterrupted run; `builds` counts on from it.
  void restore(const Particles<D>& p, const std::vector<Vec<D>>& r0, long builds) {
    r0_ = r0;
    cells_.index_sorted(r0_);
    build_rows(p);
    built_ = true;
    builds_ = builds;
  }

  // max_i |r_i - r0_i|^2 (minimum image).
  double max_displacement2(const std::vector<Vec<D>>& r) const {
    double m = 0.0;
    const std::size_t N = r.size();
#pragma omp parallel for schedule(static) reduction(max : m)
    for (std::size_t i = 0; i < N; ++i)
      m = std::max(m, image_(r[i] - r0_[i]).squaredNorm());
    return m;
  }

private:
  CellList<D> cells_;
  MinimumImage<D> image_;
  double support_, skin_;
  double s0_ = 0.0;       // variable h: the kernel's support per unit h
  int h_field_ = -1;      // variable h: the particles' h field (-1: one support)
  std::vector<double> H_; // variable h: the largest h within reach of each particle's cell
  CandidateRows<D> rows_;
  std::vector<Vec<D>> r0_;
  bool built_ = false;
  long builds_ = 0;

  // The candidates of the reference positions r0_ (p: the particles in the cells' order).
  void build_rows(const Particles<D>& p) {
    if (h_field_ < 0) {
      rows_.build(cells_, r0_, cutoff());
      return;
    }
    const std::vector<double>& h = p.scalar(h_field_);
    double h_max = 0.0;
    for (double v : h)
      h_max = std::max(h_max, v);
    if (s0_ * h_max > support_ * (1.0 + 1e-12))
      throw std::logic_error("VerletList: a particle's h exceeds the h_max the list was made for");
    const int K = static_cast<int>(std::ceil((s0_ * h_max + skin_) / cells_.support()));
    if (K > cells_.max_reach())
      throw std::invalid_argument("VerletList: a periodic axis is shorter than " +
                                  std::to_string(2 * K + 1) + " cells of the smallest cutoff");
    cells_.neighbourhood_max(h, K, H_);
    rows_.build(cells_, r0_, h, H_, s0_, skin_);
  }
};

} // namespace sph
