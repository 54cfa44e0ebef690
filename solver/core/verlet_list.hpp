// Verlet neighbour list with a skin (Verlet 1967; LAMMPS's `neighbor SKIN bin` with
// `neigh_modify every 1 delay 0 check yes`): the candidate pairs within cutoff = support + skin of
// a configuration r0, kept across steps and rebuilt only when some particle has moved more than
// skin/2 from r0 (checked every step). Until then every pair within the support is a candidate: two
// particles that each moved at most skin/2 are at most skin closer than they were at the build.
//
// The candidates come from the cell list (core/cell_list.hpp) with cells of edge >= the cutoff: a
// build wraps the periodic coordinates, sorts the particles by cell (reordering every field, so the
// particle order changes only at a build) and scans the 3 (2D) or 9 (3D) contiguous x-rows of each
// particle's neighbour cells. The scan is branch-free, as LAMMPS's binned build: every candidate
// is written and the write position advances by (r2 < cutoff^2), so a neighbour test never
// mispredicts; each thread fills its own buffer over a contiguous range of particles and the
// buffers are concatenated, so the rows come out in the same order for any number of threads.
//
// The pair geometry of the current positions (r_ij, r, W, dW of the pairs within the support) is
// not stored here: NeighborList::build(VerletList, ...) recomputes it from the candidates every
// step (core/neighbor_list.hpp), with the minimum image on periodic axes.
#pragma once

#include "core/cell_list.hpp"
#include "core/domain.hpp"
#include "core/particles.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <omp.h>
#include <stdexcept>
#include <vector>

namespace sph {

// Candidate rows in compressed form: the candidates of particle i are j[offset[i] .. offset[i+1]).
template <int D>
class CandidateRows {
public:
  std::vector<std::uint32_t> offset, j;

  std::size_t size() const { return j.size(); }
  std::size_t num_particles() const { return offset.empty() ? 0 : offset.size() - 1; }

  // Every pair (i, j != i) with |r_i - r_j + shift|^2 < cutoff^2 (the cell list's minimum image),
  // in the order of the cell list's scan; cutoff <= the cells' edge, x in the order of the
  // cells' last build. Reuses its buffers: after the first builds it does not allocate.
  void build(const CellList<D>& cells, const std::vector<Vec<D>>& x, double cutoff) {
    const std::size_t N = x.size();
    const double c2 = cutoff * cutoff;
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
        cells.for_each_range(i, [&](std::uint32_t jb, std::uint32_t je, const Vec<D>& shift) {
          if (buf.size() < n + (je - jb))
            buf.resize(2 * (n + (je - jb)));
          std::uint32_t* out = buf.data();
          for (std::uint32_t jj = jb; jj < je; ++jj) {
            const Vec<D> rij = xi - x[jj] + shift; // as CellList::for_each_neighbor rounds it
            out[n] = jj;
            n += (rij.squaredNorm() < c2) & (jj != i);
          }
        });
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

private:
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
    rows_.build(cells_, r0_, cutoff());
    built_ = true;
    ++builds_;
  }

  // A resumed run: the list of the build whose reference positions r0 a checkpoint saved (the
  // particles are in that build's order, so the cell sort is the identity and nothing moves).
  // The same candidates in the same order as the uninterrupted run; `builds` counts on from it.
  void restore(const std::vector<Vec<D>>& r0, long builds) {
    r0_ = r0;
    cells_.index_sorted(r0_);
    rows_.build(cells_, r0_, cutoff());
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
  CandidateRows<D> rows_;
  std::vector<Vec<D>> r0_;
  bool built_ = false;
  long builds_ = 0;
};

} // namespace sph
