// Two resolution levels whose particles keep the level of where they are (issue 19, section 2):
// fluid particles of the coarse level (spacing dx_c = 2 dx_f, mass m_c = rho0 dx_c^D) that move
// deep enough into the fine region are split, and fine ones (m_f = m_c / 2^D) that move far enough
// out of it are merged, 2^D at a time, so the refinement region does not fill with coarse
// particles over time and the coarse region does not keep fine ones (seed 002 section 4.4 refines
// a region around the cylinder; SPHinXsys, which the seed's code is, adapts the resolution by
// particle splitting and merging, src/shared/adaptations and particle_dynamics/
// particle_split_merge; the patterns follow Vacondio, Rogers, Stansby, Mignosa & Feldman 2013,
// "Variable resolution for SPH: a dynamic particle coalescing and splitting scheme", CMAME 256,
// 132-148, here in their simplest, lattice-like form):
//   split   a coarse particle at r becomes 2^D fine ones at r + (dx_f / 2) s, s in {-1, 1}^D, each
//           with m_c / 2^D and the parent's velocity, density, pressure and extra fields: mass and
//           momentum are kept exactly, the daughters fill the parent's lattice cell;
//   merge   the eligible fine particles in a cell of size dx_c of the global grid, 2^D at a time
//           (those nearest the cell's centre first), become one particle of mass sum m, at the
//           centre of mass sum m r / sum m, velocity sum m v / sum m, density and pressure
//           mass-weighted means: mass and momentum are kept exactly, kinetic energy of the
//           relative motion is lost (as Vacondio et al.'s coalescing); a cell with fewer than 2^D
//           waits for a later step (the flow changes what it holds).
// The region is given by a signed depth d(r) (positive inside the fine region); hysteresis: split
// where d > margin, merge where d < -margin, so a particle moving along the interface is not split
// and merged back every step. Only Kind::Fluid particles change level (buffer, wall particles
// keep theirs). The smoothing length follows the mass: h_i = h_over_dx (m_i / rho0)^(1/D) (2 h_f
// or h_f), written into the scalar field "h" (schemes/wcsph_tvf's variable resolution) for every
// particle.
// Used between steps, like the emitter and the disposer (boundaries/free_stream_domain.hpp); the
// scheme is told through FlowScheme::particles_changed().
#pragma once

#include "core/particles.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <tuple>
#include <utility>
#include <vector>

namespace sph::refinement {

// Fine point s (s in [0, 2^D): bit a set is +, clear is -, along axis a) of the coarse lattice
// cell of spacing dx_c centred at x: x + (dx_c / 4) (+-1, ..., +-1), the fine lattice of that
// cell. Used by the split and by the cases that fill a fine region on a coarse lattice.
template <int D>
Vec<D> fine_point(const Vec<D>& x, double dx_c, int s) {
  Vec<D> y = x;
  for (int a = 0; a < D; ++a)
    y[a] += (s >> a & 1 ? 0.25 : -0.25) * dx_c;
  return y;
}

template <int D>
class TwoLevels {
public:
  struct Config {
    double dx_fine = 0.05; // the fine spacing; the coarse one is 2 dx_fine
    double rho0 = 1.0;
    double h_over_dx = 1.3;
    std::function<double(const Vec<D>&)> depth; // signed distance into the fine region
    double margin = 0.1;                        // hysteresis (a coarse spacing, say)
  };

  // Adds (or finds) the scalar field "h".
  TwoLevels(Particles<D>& p, Config c) : c_(std::move(c)) {
    h_ = p.find_scalar("h");
    if (h_ < 0)
      h_ = p.add_scalar("h");
    m_f_ = c_.rho0 * std::pow(c_.dx_fine, D);
  }
  int h_field() const { return h_; }
  bool is_coarse(double m) const { return m > 1.5 * m_f_; }

  // Splits, merges and sets h. next_id numbers new particles. Returns the number of particles
  // split plus the number of groups merged (0: the particle set is unchanged).
  std::size_t update(Particles<D>& p, std::int64_t& next_id) {
    const std::size_t n_split = split(p, next_id), n_merged = merge(p);
    set_h(p);
    splits_ += n_split, merges_ += n_merged;
    return n_split + n_merged;
  }

  // h_i = h_over_dx (m_i / rho0)^(1/D) for every particle: 2 h_f for the coarse mass, h_f for
  // the fine (the only two masses splits and merges of whole lattice cells make).
  void set_h(Particles<D>& p) const {
    auto& h = p.scalar(h_);
    const double h_f = c_.h_over_dx * c_.dx_fine;
    for (std::size_t i = 0; i < p.size(); ++i)
      h[i] = is_coarse(p.m[i]) ? 2.0 * h_f : h_f;
  }

  std::size_t splits() const { return splits_; } // cumulative, for metrics
  std::size_t merges() const { return merges_; }
  void set_counts(std::size_t s, std::size_t m) { splits_ = s, merges_ = m; }

private:
  Config c_;
  int h_ = -1;
  double m_f_ = 0.0;
  std::size_t splits_ = 0, merges_ = 0;
  struct Entry { // a merge candidate: its grid cell, squared distance to the cell's centre, index
    std::array<std::int64_t, D> cell;
    double d2;
    std::uint32_t i;
    bool operator<(const Entry& o) const {
      return std::tie(cell, d2, i) < std::tie(o.cell, o.d2, o.i);
    }
  };
  std::vector<Entry> bins_; // merge()'s scratch, kept so that the time loop does not allocate
  std::vector<char> keep_;

  std::size_t split(Particles<D>& p, std::int64_t& next_id) const {
    const std::size_t n0 = p.size();
    std::size_t n = 0;
    for (std::size_t i = 0; i < n0; ++i) {
      if (p.kind[i] != Kind::Fluid || !is_coarse(p.m[i]) || !(c_.depth(p.r[i]) > c_.margin))
        continue;
      const Vec<D> r0 = p.r[i];
      p.m[i] /= (1 << D), p.V[i] /= (1 << D);
      for (int s = 0; s < (1 << D); ++s) {
        const std::size_t k = s == 0 ? i : p.append_copy(i);
        p.r[k] = fine_point<D>(r0, 2.0 * c_.dx_fine, s);
        if (s > 0)
          p.id[k] = next_id++;
      }
      ++n;
    }
    return n;
  }

  std::size_t merge(Particles<D>& p) {
    constexpr int group = 1 << D;
    const double dx_c = 2.0 * c_.dx_fine;
    // The candidates binned on the cells of size dx_c of the global grid, sorted by cell and, in
    // a cell, by distance to its centre (then index: deterministic).
    auto& bins = bins_;
    bins.clear();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.kind[i] != Kind::Fluid || is_coarse(p.m[i]) || !(c_.depth(p.r[i]) < -c_.margin))
        continue;
      Entry e{{}, 0.0, static_cast<std::uint32_t>(i)};
      for (int a = 0; a < D; ++a) {
        e.cell[a] = static_cast<std::int64_t>(std::floor(p.r[i][a] / dx_c));
        const double d = p.r[i][a] - (static_cast<double>(e.cell[a]) + 0.5) * dx_c;
        e.d2 += d * d;
      }
      bins.push_back(e);
    }
    std::sort(bins.begin(), bins.end());
    auto& keep = keep_;
    keep.assign(p.size(), 1);
    std::size_t merged = 0;
    for (std::size_t b = 0; b < bins.size();) {
      std::size_t e = b;
      while (e < bins.size() && bins[e].cell == bins[b].cell)
        ++e;
      for (; b + group <= e; b += group) { // the 2^D nearest the centre, then the next 2^D ...
        const std::uint32_t i = bins[b].i;
        double m = 0.0, V = 0.0, rho = 0.0, pr = 0.0;
        Vec<D> mr = Vec<D>::Zero(), mv = Vec<D>::Zero();
        for (int k = 0; k < group; ++k) {
          const std::uint32_t j = bins[b + k].i;
          m += p.m[j], V += p.V[j], rho += p.m[j] * p.rho[j], pr += p.m[j] * p.p[j];
          mr += p.m[j] * p.r[j], mv += p.m[j] * p.v[j];
          keep[j] = k == 0;
        }
        p.m[i] = m, p.V[i] = V, p.r[i] = mr / m, p.v[i] = mv / m;
        p.rho[i] = rho / m, p.p[i] = pr / m;
        ++merged;
      }
      b = e; // fewer than 2^D left in the cell: they wait
    }
    if (merged > 0)
      p.keep_only(keep);
    return merged;
  }
};

} // namespace sph::refinement
