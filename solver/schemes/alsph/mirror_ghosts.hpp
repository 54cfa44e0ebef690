// Free-slip mirror ghost particles for plane walls (seed 004 section 3 and Figure 2; Kolukisa et
// al. 2020, IJNME 121). A ghost is the mirror image of a source particle lying within one kernel
// support of a wall x_axis = plane: position 2 plane - x_axis, the same scalar values (pressure,
// velocity divergence), the tangential velocity kept and the normal velocity reversed.
// The case creates the ghosts once per time step (before the neighbour search) and records
// (ghost, source) index pairs here after the cell list has reordered the particles; the scheme
// calls the copy functions after each update inside its iterations.
#pragma once

#include "core/vec.hpp"

#include <cstdint>
#include <vector>

namespace sph {

template <int D>
struct MirrorGhosts {
  std::vector<std::uint32_t> ghost, src; // particle indices (current order)
  std::vector<std::uint8_t> axis;        // wall normal axis
  std::vector<double> plane;             // wall position along that axis

  std::size_t size() const { return ghost.size(); }
  void clear() { ghost.clear(), src.clear(), axis.clear(), plane.clear(); }
  void add(std::uint32_t g, std::uint32_t s, int a, double x) {
    ghost.push_back(g), src.push_back(s), axis.push_back(static_cast<std::uint8_t>(a));
    plane.push_back(x);
  }

  Vec<D> mirror_point(Vec<D> x, std::size_t k) const {
    x[axis[k]] = 2.0 * plane[k] - x[axis[k]];
    return x;
  }
  Vec<D> mirror_vector(Vec<D> v, std::size_t k) const {
    v[axis[k]] = -v[axis[k]];
    return v;
  }

  void copy_scalar(std::vector<double>& f) const {
    for (std::size_t k = 0; k < ghost.size(); ++k)
      f[ghost[k]] = f[src[k]];
  }
  void copy_vector(std::vector<Vec<D>>& f) const {
    for (std::size_t k = 0; k < ghost.size(); ++k)
      f[ghost[k]] = mirror_vector(f[src[k]], k);
  }
  void copy_positions(std::vector<Vec<D>>& r) const {
    for (std::size_t k = 0; k < ghost.size(); ++k)
      r[ghost[k]] = mirror_point(r[src[k]], k);
  }
};

} // namespace sph
