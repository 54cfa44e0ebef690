// Cell-linked list, cached neighbour list and Verlet list: exactly the brute-force neighbour sets
// (with the minimum image on periodic axes), on random and lattice particles, 2D and 3D, periodic
// and not; particle fields follow the reordering. The Verlet list stays complete while particles
// move by less than skin/2, rebuilds when one moves more, gives the same pairs as the cell list,
// the same rows for any number of threads, and the same rows again when restored from its
// reference positions (a resumed run).
#include "core/cell_list.hpp"
#include "core/kernels/wendland_c2.hpp"
#include "core/lattice.hpp"
#include "core/neighbor_list.hpp"
#include "core/verlet_list.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <omp.h>
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

// nl holds exactly the pairs (i, j != i) of q with |r_ij| < support(i, j) (brute force, minimum
// image), each once, with r_ij and r of the current positions and check(k) for each; returns the
// number of pairs.
template <int D, class Support, class Check>
std::size_t expect_pairs(const NeighborList<D>& nl, const Particles<D>& q, const Domain<D>& box,
                         Support&& support, Check&& check) {
  std::size_t total = 0;
  EXPECT_EQ(nl.num_particles(), q.size());
  for (std::size_t i = 0; i < q.size(); ++i) {
    std::set<std::int64_t> brute, found;
    for (std::size_t j = 0; j < q.size(); ++j) {
      const double s = support(i, j);
      if (j != i && min_image<D>(q.r[i] - q.r[j], box).squaredNorm() < s * s)
        brute.insert(q.id[j]);
    }
    for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
      const auto j = nl.j[k];
      EXPECT_TRUE(found.insert(q.id[j]).second) << "duplicate neighbour";
      const Vec<D> expect = min_image<D>(q.r[i] - q.r[j], box);
      EXPECT_LT((nl.r_ij[k] - expect).norm(), 1e-12);
      EXPECT_NEAR(nl.r[k], expect.norm(), 1e-12);
      check(k);
    }
    EXPECT_EQ(brute, found) << "particle " << i;
    total += found.size();
  }
  EXPECT_GT(total, q.size()); // the test is not vacuous
  return total;
}

// The same within the kernel's support, with W of the current positions.
template <int D>
std::size_t expect_brute_force(const NeighborList<D>& nl, const Particles<D>& q,
                               const Domain<D>& box, const WendlandC2<D>& kernel) {
  return expect_pairs(
      nl, q, box, [&](std::size_t, std::size_t) { return kernel.support(); },
      [&](std::size_t k) { EXPECT_EQ(nl.W[k], kernel.W(nl.r[k])); });
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
  expect_brute_force(nl, q, box, kernel);
  // The on-the-fly driver's search (operators/interact.hpp) visits the same pairs, r_ij bitwise.
  for (std::size_t i = 0; i < q.size(); ++i) {
    std::map<std::uint32_t, Vec<D>> fly;
    cells.for_each_neighbor(i, q.r, [&](std::uint32_t j, const Vec<D>& rij, double) {
      EXPECT_TRUE(fly.emplace(j, rij).second) << "duplicate neighbour";
    });
    ASSERT_EQ(fly.size(), nl.offset[i + 1] - nl.offset[i]) << "particle " << i;
    for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k)
      EXPECT_EQ(fly.at(nl.j[k]), nl.r_ij[k]);
  }
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

namespace {

template <int D>
Domain<D> periodic_box() {
  Domain<D> box;
  box.periodic.fill(true);
  return box;
}

// Moves every particle by a random vector of length `len` (uniform direction).
template <int D>
void random_move(Particles<D>& p, double len, UniformRandom& rn) {
  for (auto& x : p.r) {
    Vec<D> d;
    do {
      for (int a = 0; a < D; ++a)
        d[a] = 2.0 * rn() - 1.0;
    } while (d.squaredNorm() > 1.0 || d.squaredNorm() < 1e-4);
    x += (len / d.norm()) * d;
  }
}

// Random (disordered) particles in a periodic box, about `nbrs` neighbours within the support:
// every particle moves by 0.3 skin per step for 20 steps, so the largest displacement crosses
// skin/2 now and then. After every update() the pairs on the Verlet list are exactly the
// brute-force pairs within the support; the list rebuilt, but not every step.
template <int D>
void verlet_stays_complete(std::size_t n, double nbrs, std::uint64_t seed) {
  const Domain<D> box = periodic_box<D>();
  Particles<D> p = random_particles<D>(n, box, seed);
  const double ball = D == 2 ? M_PI : 4.0 * M_PI / 3.0; // unit ball volume
  const double support = std::pow(nbrs / (n * ball), 1.0 / D), skin = 0.4 * support;
  WendlandC2<D> kernel(support / 2);
  VerletList<D> vl(box, support, skin);
  NeighborList<D> nl;
  UniformRandom rn(seed + 100);
  long builds = 0, steps = 20;
  for (long s = 0; s < steps; ++s) {
    if (s > 0)
      random_move(p, 0.3 * skin, rn);
    builds += vl.update(p);
    nl.build(vl, p.r, kernel);
    expect_brute_force(nl, p, box, kernel);
    if (::testing::Test::HasFailure())
      FAIL() << "step " << s;
  }
  EXPECT_EQ(vl.builds(), builds);
  EXPECT_GT(builds, 3);         // rebuilt: displacements crossed skin/2
  EXPECT_LT(builds, steps - 3); // but not every step: the list was kept between builds
}

} // namespace

TEST(VerletList, StaysCompleteWhileParticlesMove2DPeriodic) {
  verlet_stays_complete<2>(1500, 20.0, 11);
}
TEST(VerletList, StaysCompleteWhileParticlesMove3DPeriodic) {
  verlet_stays_complete<3>(1500, 40.0, 12);
}

// The rebuild criterion: no rebuild while the largest displacement is at most skin/2 (a move of
// 0.49 skin), a rebuild as soon as one particle has moved more (0.51 skin), counted from the last
// build (two moves of 0.3 skin in the same direction).
TEST(VerletList, RebuildsExactlyWhenADisplacementExceedsHalfTheSkin) {
  const Domain<2> box = periodic_box<2>();
  Particles<2> p = random_particles<2>(500, box, 13);
  const double support = 0.08, skin = 0.02;
  VerletList<2> vl(box, support, skin);
  EXPECT_TRUE(vl.update(p)); // first call builds
  EXPECT_FALSE(vl.update(p));
  const std::int64_t id = p.id[7];
  auto at = [&] { return std::find(p.id.begin(), p.id.end(), id) - p.id.begin(); };
  p.r[at()][0] += 0.49 * skin;
  EXPECT_FALSE(vl.update(p));
  p.r[at()][0] += 0.02 * skin; // 0.51 skin from the build
  EXPECT_TRUE(vl.update(p));
  EXPECT_EQ(vl.builds(), 2);
  p.r[at()][1] += 0.3 * skin;
  EXPECT_FALSE(vl.update(p));
  p.r[at()][1] += 0.3 * skin;
  EXPECT_TRUE(vl.update(p));
  // Across a periodic boundary the displacement is the minimum image: wrapping is no move.
  p.r[at()][0] += 1.0;
  EXPECT_FALSE(vl.update(p));
}

// Right after a build the Verlet list (cutoff support + skin) and the cell list (cutoff support)
// give the same pairs with bitwise the same geometry; the rows of the Verlet list and its pairs
// are the same bits on 1 and on 2 threads.
TEST(VerletList, SamePairsAsTheCellListAndTheSameRowsOnAnyThreadCount) {
  const Domain<3> box = periodic_box<3>();
  Particles<3> p = random_particles<3>(3000, box, 14);
  const double support = 0.12;
  WendlandC2<3> kernel(support / 2);
  VerletList<3> vl(box, support, 0.3 * support);
  vl.update(p);
  CellList<3> cells(box, support);
  Particles<3> q = p;
  cells.build(q);
  NeighborList<3> a, b;
  a.build(vl, p.r, kernel);
  b.build(cells, q.r, kernel);
  ASSERT_EQ(a.num_pairs(), b.num_pairs());
  // Match the rows by particle id (the two sorts differ in cell size, so in order).
  std::vector<std::size_t> row_of_id(p.size());
  for (std::size_t i = 0; i < q.size(); ++i)
    row_of_id[q.id[i]] = i;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::size_t iq = row_of_id[p.id[i]];
    std::map<std::int64_t, std::uint32_t> kb;
    for (auto k = b.offset[iq]; k < b.offset[iq + 1]; ++k)
      kb[q.id[b.j[k]]] = k;
    ASSERT_EQ(a.offset[i + 1] - a.offset[i], kb.size());
    for (auto k = a.offset[i]; k < a.offset[i + 1]; ++k) {
      const auto m = kb.at(p.id[a.j[k]]);
      EXPECT_EQ(a.r_ij[k], b.r_ij[m]);
      EXPECT_EQ(a.r[k], b.r[m]);
      EXPECT_EQ(a.W[k], b.W[m]);
      EXPECT_EQ(a.dW[k], b.dW[m]);
    }
  }
  const int threads = omp_get_max_threads();
  for (int t : {1, 2}) {
    omp_set_num_threads(t);
    VerletList<3> v2(box, support, 0.3 * support);
    Particles<3> p2 = p;
    v2.rebuild(p2);
    NeighborList<3> c;
    c.build(v2, p2.r, kernel);
    EXPECT_EQ(v2.rows().offset, vl.rows().offset) << t << " threads";
    EXPECT_EQ(v2.rows().j, vl.rows().j) << t << " threads";
    EXPECT_EQ(c.j, a.j);
    EXPECT_EQ(c.r, a.r);
  }
  omp_set_num_threads(threads);
}

// A resumed run restores the list from the reference positions a checkpoint saved: the same
// candidate rows, the same pairs of the current positions, the same build count, and the same
// rebuild decisions afterwards.
TEST(VerletList, RestoredFromItsReferencePositionsGivesTheSameRows) {
  const Domain<2> box = periodic_box<2>();
  Particles<2> p = random_particles<2>(2000, box, 15);
  const double support = 0.06, skin = 0.02;
  WendlandC2<2> kernel(support / 2);
  VerletList<2> vl(box, support, skin);
  UniformRandom rn(16);
  vl.update(p);
  random_move(p, 0.3 * skin, rn);
  ASSERT_FALSE(vl.update(p)); // a checkpoint between builds
  VerletList<2> resumed(box, support, skin);
  resumed.restore(p, vl.reference(), vl.builds());
  EXPECT_EQ(resumed.rows().offset, vl.rows().offset);
  EXPECT_EQ(resumed.rows().j, vl.rows().j);
  NeighborList<2> a, b;
  a.build(vl, p.r, kernel);
  b.build(resumed, p.r, kernel);
  EXPECT_EQ(a.j, b.j);
  EXPECT_EQ(a.r, b.r);
  EXPECT_EQ(a.dW, b.dW);
  Particles<2> q = p;
  random_move(p, 0.3 * skin, rn);
  q.r = p.r;
  EXPECT_EQ(vl.update(p), resumed.update(q)); // 0.6 skin from the build: both rebuild
  EXPECT_EQ(p.id, q.id);
  EXPECT_EQ(vl.builds(), resumed.builds());
  // Positions that are not in cell order are not a build's reference positions.
  std::vector<Vec2> shuffled = vl.reference();
  std::reverse(shuffled.begin(), shuffled.end());
  VerletList<2> wrong(box, support, skin);
  EXPECT_THROW(wrong.restore(p, shuffled, 1), std::logic_error);
}

namespace {

// Two resolution levels (boundaries/refinement.hpp): h = h_f in the left half of the box and in
// every 7th particle of the right half, 2 h_f elsewhere. After every update() of the variable-h
// Verlet list, moving the particles 0.3 skin per step, the pairs are exactly the brute-force pairs
// within s0 (h_i + h_j) / 2 (minimum image), each once; and the fine particles far from coarse
// ones have the candidates of the fine cutoff: at most half of what the one list sized for the
// coarse support gives them.
template <int D>
void verlet_two_levels(const Domain<D>& box, std::size_t n, double nbrs, std::uint64_t seed) {
  Particles<D> p = random_particles<D>(n, box, seed);
  const int hf = p.add_scalar("h");
  const double ball = D == 2 ? M_PI : 4.0 * M_PI / 3.0;
  const double volume = (box.hi - box.lo).prod();
  const double s_f = std::pow(nbrs * volume / (n * ball), 1.0 / D), h_f = s_f / 2;
  const double skin = 0.25 * s_f;
  const double mid = 0.5 * (box.lo[0] + box.hi[0]);
  for (std::size_t i = 0; i < p.size(); ++i)
    p.scalar(hf)[i] = p.r[i][0] < mid || i % 7 == 0 ? h_f : 2 * h_f;
  WendlandC2<D> kernel(h_f);
  const double s0 = kernel.support() / h_f;
  VerletList<D> vl(box, s0, h_f, 2 * h_f, skin, hf);
  NeighborList<D> nl;
  UniformRandom rn(seed + 1);
  for (int s = 0; s < 8; ++s) {
    if (s > 0)
      random_move(p, 0.3 * skin, rn);
    vl.update(p);
    const auto& h = p.scalar(hf);
    nl.build(vl, p.r, kernel, h);
    expect_pairs(
        nl, p, box, [&](std::size_t i, std::size_t j) { return s0 * 0.5 * (h[i] + h[j]); },
        [](std::size_t) {});
    if (::testing::Test::HasFailure())
      FAIL() << "step " << s;
  }
  // Candidates of the fine particles more than 2 coarse cutoffs from any coarse one (the left
  // half's middle), against the list of one support for all (cells and cutoff of the coarse pair).
  VerletList<D> one(box, s0 * 2 * h_f, skin);
  Particles<D> q = p;
  one.update(q);
  auto fine_candidates = [&](const VerletList<D>& l, const Particles<D>& x) {
    // Coarse particles started at x >= mid (or on a periodic image beyond hi) and moved at most
    // 2.1 skin: the fine ones in (lo + far, mid - far) have none within `far`.
    const double far = 2 * (s0 * 2 * h_f + skin), a = box.lo[0] + far, b = mid - far;
    std::size_t c = 0, fine = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (x.r[i][0] > a && x.r[i][0] < b)
        c += l.rows().offset[i + 1] - l.rows().offset[i], ++fine;
    EXPECT_GT(fine, 20u);
    return static_cast<double>(c);
  };
  const double c_two = fine_candidates(vl, p), c_one = fine_candidates(one, q);
  std::printf("fine particles' candidates: two levels %.0f, one support %.0f (ratio %.2f)\n", c_two,
              c_one, c_two / c_one);
  EXPECT_LT(c_two, 0.5 * c_one);
}

} // namespace

TEST(VerletList, TwoLevelsGiveExactlyThePairsOfTheirOwnSupport2DPeriodic) {
  verlet_two_levels<2>(periodic_box<2>(), 3000, 20.0, 21);
}
TEST(VerletList, TwoLevelsGiveExactlyThePairsOfTheirOwnSupport2DOpen) {
  verlet_two_levels<2>(Domain<2>{}, 3000, 20.0, 22);
}
TEST(VerletList, TwoLevelsGiveExactlyThePairsOfTheirOwnSupport3DPeriodic) {
  Domain<3> box = periodic_box<3>();
  box.hi[0] = 3.0; // room for fine particles far from the coarse half
  verlet_two_levels<3>(box, 5000, 15.0, 23);
}

// A periodic axis must hold 2K + 1 cells of the fine cutoff, K the coarse pair's reach in cells.
TEST(VerletList, TwoLevelsRejectAPeriodicAxisTooShortForTheCoarseReach) {
  Domain<2> box = periodic_box<2>();
  Particles<2> p = random_particles<2>(200, box, 24);
  const int hf = p.add_scalar("h", 0.09);
  p.scalar(hf)[0] = 0.27; // 3 h_f: the coarse pair reaches 3 cells of 0.2 + 0.04 (4 per axis)
  VerletList<2> vl(box, 2.0, 0.1, 0.3, 0.04, hf);
  EXPECT_THROW(vl.update(p), std::invalid_argument);
  p.scalar(hf)[0] = 0.31; // beyond the h_max the list was made for
  VerletList<2> small(box, 2.0, 0.1, 0.3, 0.04, hf);
  EXPECT_THROW(small.update(p), std::logic_error);
}
