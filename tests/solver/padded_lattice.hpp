// Test fixture shared by the scheme-term tests: a perfect (or disordered) 2D lattice of spacing
// dx = 1/n, n^2 sampled particles (Kind::Fluid) in the unit box and `pad` layers of Kind::Buffer
// particles around them (they carry the fields, so no sampled particle has a truncated support),
// with its neighbour list. Independent of any scheme: port-friendly.
#pragma once

#include "core/cell_list.hpp"
#include "core/lattice.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"

#include <cmath>

namespace sph::testing {

template <class K>
struct PaddedLattice {
  Particles<2> p;
  NeighborList<2> nl;
  K kernel;
  double dx;

  PaddedLattice(int n, double h_over_dx, double disorder = 0.0, std::uint64_t seed = 1)
      : kernel(h_over_dx / n), dx(1.0 / n) {
    const int pad = static_cast<int>(std::ceil(kernel.support() / dx)) + 1;
    UniformRandom rn(seed);
    for_each_lattice_point<2>({-pad, -pad}, {n + pad, n + pad}, dx,
                              [&](Vec2 x, const std::array<int, 2>& i) {
                                const bool in = i[0] >= 0 && i[0] < n && i[1] >= 0 && i[1] < n;
                                for (int a = 0; a < 2; ++a)
                                  x[a] += (rn() - 0.5) * disorder * dx;
                                p.add(x, dx * dx, 1.0, in ? Kind::Fluid : Kind::Buffer);
                              });
    for (std::size_t i = 0; i < p.size(); ++i)
      p.V[i] = dx * dx;
    CellList<2> cells(Domain<2>{}, kernel.support());
    cells.build(p);
    nl.build(cells, p.r, kernel);
  }
  bool fluid(std::size_t i) const { return p.kind[i] == Kind::Fluid; }
  auto sampled() const {
    return [this](std::size_t i) { return fluid(i); };
  }
  // Sum over the offsets of the perfect lattice (excluding 0) of f(offset r_ij, |r_ij|).
  template <class F>
  double offset_sum(F f) const {
    const int m = static_cast<int>(std::ceil(kernel.support() / dx)) + 1;
    double s = 0.0;
    for (int a = -m; a <= m; ++a)
      for (int b = -m; b <= m; ++b)
        if (a != 0 || b != 0) {
          const Vec2 r(a * dx, b * dx);
          s += f(r, r.norm());
        }
    return s;
  }
};

} // namespace sph::testing
