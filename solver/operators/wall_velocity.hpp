// No-slip wall velocity of a wall (or body) particle w: the fluid velocity mirrored about the
// wall's prescribed velocity,
//   u_w = 2 u_prescribed,w - sum_f u_f W_wf / sum_f W_wf
// (Adami, Hu & Adams 2012, J. Comput. Phys. 231, 7057, eqs. 22-23), so that a kernel sum across
// the wall sees u = u_prescribed at the wall. A wall particle with no fluid neighbour keeps its
// prescribed velocity. Used by scheme isph (stage 2) and by the cavity cases' profiles.
#pragma once

#include "core/particles.hpp"
#include "operators/interact.hpp"

#include <vector>

namespace sph {

template <int D>
struct WallVelocity {
  const std::vector<Kind>& kind;
  const std::vector<Vec<D>>& v_wall; // prescribed velocity per particle
  std::vector<Vec<D>>& v;
  struct Acc {
    Vec<D> s = Vec<D>::Zero();
    double w = 0.0;
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t, const Pair<D>& q, Acc& a) const {
    if (kind[q.j] == Kind::Fluid)
      a.s += q.W * v[q.j], a.w += q.W;
  }
  void finish(std::size_t i, const Acc& a) {
    v[i] = a.w > 0.0 ? Vec<D>(2.0 * v_wall[i] - a.s / a.w) : v_wall[i];
  }
};

} // namespace sph
