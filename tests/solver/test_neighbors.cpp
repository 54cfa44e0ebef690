// Cell-linked list and cached neighbour list: exactly the brute-force neighbour sets (with the
// minimum image on periodic axes), on random and lattice particles, 2D and 3D, periodic and not;
// particle fields follow the reordering.
#include "core/cell_list.hpp"
#include "core/kernels/wendland_c2.hpp"
#include "core/lattice.hpp"
#include "core/neighbor_list.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

using namespace sph;

namespace {

template <int D>
Vec<D> min_image(Vec<D> d, const Domain<D>& box) {
  for (int a = 0; a < D; ++a)
    if (box.periodic[a]) {
      const double L = box.hi[a] - box.lo[a];
      d[a] -= L * std::round(d[a] / L);
    }
  return d;
}

template <int D>
void check(Particles<D> p, const Domain<D>& box, double support) {
  CellList<D> cells(box, support);
  Particles<D> q = p;
  cells.build(q);
  ASSERT_EQ(q.size(), p.size());
  // Fields follow the permutation: id maps back to the original particle.
  for (std::size_t i = 0; i < q.size(); ++i) {
    const auto o = static_cast<std::size_t>(q.id[i]);
    EXPECT_EQ(q.m[i], p.m[o]);
    EXPECT_LT(min_image<D>(q.r[i] - p.r[o], box).norm(), 1e-12);
  }
  WendlandC2<D> kernel(support / 2);
  NeighborList<D> nl;
  nl.build(cells, q.r, kernel);
  std::size_t total = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    std::set<std::int64_t> brute, found;
    for (std::size_t j = 0; j < q.size(); ++j)
      if (j != i && min_image<D>(q.r[i] - q.r[j], box).squaredNorm() < support * support)
        brute.insert(q.id[j]);
    for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
      const auto j = nl.j[k];
      EXPECT_TRUE(found.insert(q.id[j]).second) << "duplicate neighbour";
      const Vec<D> expect = min_image<D>(q.r[i] - q.r[j], box);
      EXPECT_LT((nl.r_ij[k] - expect).norm(), 1e-12);
      EXPECT_NEAR(nl.r[k], expect.norm(), 1e-12);
      EXPECT_EQ(nl.W[k], kernel.W(nl.r[k]));
    }
    EXPECT_EQ(brute, found) << "particle " << i;
    total += found.size();
  }
  EXPECT_GT(total, q.size()); // the test is not vacuous
}

template <int D>
Particles<D> random_particles(std::size_t n, const Domain<D>& box, std::uint64_t seed) {
  Particles<D> p;
  UniformRandom rn(seed);
  for (std::size_t k = 0; k < n; ++k) {
    Vec<D> x;
    for (int a = 0; a < D; ++a)
      x[a] = box.lo[a] + rn() * (box.hi[a] - box.lo[a]);
    p.add(x, 1.0 + k, 1.0);
  }
  return p;
}

template <int D>
Particles<D> lattice_particles(int n, double dx) {
  Particles<D> p;
  std::array<int, D> lo{}, hi;
  hi.fill(n);
  for_each_lattice_point<D>(lo, hi, dx, [&](const Vec<D>& x, const std::array<int, D>&) {
    p.add(x, static_cast<double>(p.size()), 1.0);
  });
  return p;
}

} // namespace

TEST(CellList, Random2DOpen) {
  Domain<2> box;
  check(random_particles<2>(1500, box, 1), box, 0.07);
}
TEST(CellList, Random2DPeriodic) {
  Domain<2> box;
  box.periodic = {true, true};
  check(random_particles<2>(1500, box, 2), box, 0.07);
}
TEST(CellList, Random2DPeriodicXOnly) {
  Domain<2> box;
  box.hi = Vec2(1.0, 0.5);
  box.periodic = {true, false};
  check(random_particles<2>(1000, box, 3), box, 0.1);
}
TEST(CellList, Random3DOpen) {
  Domain<3> box;
  check(random_particles<3>(2000, box, 4), box, 0.15);
}
TEST(CellList, Random3DPeriodic) {
  Domain<3> box;
  box.periodic = {true, true, true};
  check(random_particles<3>(2000, box, 5), box, 0.15);
}
TEST(CellList, Random3DPeriodicYOnly) {
  Domain<3> box;
  box.periodic = {false, true, false};
  check(random_particles<3>(2000, box, 6), box, 0.2);
}
TEST(CellList, Lattice2DPeriodicExactlyThreeCells) {
  // Lattice spacing 0.1, support 0.3 + a hair: distances equal to the spacing multiples sit on
  // cell boundaries, and the box is exactly 3 cells wide.
  Domain<2> box;
  box.periodic = {true, true};
  check(lattice_particles<2>(10, 0.1), box, 1.0 / 3.0);
}
TEST(CellList, Lattice3DOpen) {
  Domain<3> box;
  check(lattice_particles<3>(12, 1.0 / 12), box, 2.6 / 12);
}
TEST(CellList, ParticlesOutsideTheBoxWrapOnPeriodicAxes) {
  Domain<2> box;
  box.periodic = {true, false};
  Particles<2> p = random_particles<2>(500, box, 7);
  for (std::size_t i = 0; i < p.size(); i += 3)
    p.r[i][0] += (i % 2 ? 3.0 : -2.0);
  check(p, box, 0.1);
}
TEST(CellList, RejectsPeriodicAxisShorterThanThreeSupports) {
  Domain<2> box;
  box.periodic = {true, false};
  EXPECT_THROW(CellList<2>(box, 0.4), std::invalid_argument);
}
