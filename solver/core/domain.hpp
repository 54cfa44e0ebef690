// The box particles live in, and which of its axes are periodic.
// On a periodic axis positions are wrapped into [lo, hi) and pair vectors use the minimum image.
#pragma once

#include "core/vec.hpp"

#include <array>
#include <limits>

namespace sph {

template <int D>
struct Domain {
  Vec<D> lo = Vec<D>::Zero();
  Vec<D> hi = Vec<D>::Ones();
  std::array<bool, D> periodic{};

  Vec<D> length() const { return hi - lo; }
  bool any_periodic() const {
    for (bool b : periodic)
      if (b)
        return true;
    return false;
  }
};

// The minimum image of a pair vector d = r_i - r_j whose components lie in (-L, L) (both positions
// wrapped into the box): on a periodic axis a component beyond half the box length moves by -+L.
// Written as (r_i - r_j) -+ L, the same rounding as the cell list's (r_i - r_j) + shift, so a pair
// gets bitwise the same r_ij from either. Non-periodic axes have half = infinity and never move.
template <int D>
struct MinimumImage {
  Vec<D> L, half;
  explicit MinimumImage(const Domain<D>& box) {
    for (int a = 0; a < D; ++a) {
      L[a] = box.periodic[a] ? box.hi[a] - box.lo[a] : 0.0;
      half[a] = box.periodic[a] ? 0.5 * L[a] : std::numeric_limits<double>::infinity();
    }
  }
  Vec<D> operator()(Vec<D> d) const {
    for (int a = 0; a < D; ++a) {
      if (d[a] > half[a])
        d[a] -= L[a];
      else if (d[a] < -half[a])
        d[a] += L[a];
    }
    return d;
  }
};

// A plane wall with a slip (free-slip, impermeable) condition: x_axis = position, the fluid on the
// side `side` (+1: above, -1: below). A scheme imposes it its own way (contact: mirror particles).
struct SlipWall {
  int axis = 0;
  double position = 0.0;
  int side = +1;
};

} // namespace sph
