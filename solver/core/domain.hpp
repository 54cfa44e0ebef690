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

} // namespace sph
