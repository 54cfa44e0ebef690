// Particle lattices for case set-up: a Cartesian lattice of cell-centred points, optionally
// disordered by r' = r + (Rn - 0.5) a dx per axis with Rn uniform in [0, 1) (seed 001, section 4:
// "r~ = r + (Rn - 0.5) dr"; a = 1 there). Rn comes from a 64-bit Mersenne Twister (the paper used a
// quasi-random generator); the mapping to [0, 1) is done here so results are the same on every
// platform and standard library.
#pragma once

#include "core/vec.hpp"

#include <array>
#include <cstdint>
#include <random>

namespace sph {

class UniformRandom {
public:
  explicit UniformRandom(std::uint64_t seed) : rng_(seed) {}
  double operator()() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }

private:
  std::mt19937_64 rng_;
};

// Calls f(position, index) for every lattice point (i + 1/2) dx, i_a in [lo_a, hi_a), x-fastest.
template <int D, class F>
void for_each_lattice_point(const std::array<int, D>& lo, const std::array<int, D>& hi, double dx,
                            F&& f) {
  std::array<int, D> i = lo;
  while (true) {
    Vec<D> x;
    for (int a = 0; a < D; ++a)
      x[a] = (i[a] + 0.5) * dx;
    f(x, i);
    int a = 0;
    while (a < D && ++i[a] == hi[a])
      i[a] = lo[a], ++a;
    if (a == D)
      break;
  }
}

} // namespace sph
