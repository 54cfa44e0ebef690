// The box particles live in, and which of its axes are periodic.
// On a periodic axis positions are wrapped into [lo, hi) and pair vectors use the minimum image.
#pragma once

#include "core/vec.hpp"

#include <array>

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

// A plane wall with a slip (free-slip, impermeable) condition: x_axis = position, the fluid on the
// side `side` (+1: above, -1: below). A scheme imposes it its own way (contact: mirror particles).
struct SlipWall {
  int axis = 0;
  double position = 0.0;
  int side = +1;
};

} // namespace sph
