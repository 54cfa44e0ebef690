// The one driver that owns the particle and pair loops.
//
// An operator is a small struct with three named phases, as PySPH's equations
// (pysph/sph/basic_equations.py, SummationDensity) are written:
//
//   struct MyOp {
//     struct Acc { ... };                         // per-particle accumulator (registers)
//     Acc  init(std::size_t i) const;             // before the pairs of particle i
//     void pair(std::size_t i, const Pair<D>& p, Acc& a) const;  // one neighbour j != i
//     void finish(std::size_t i, Acc& a);         // write particle i's outputs
//   };
//
// interact() runs init, every pair, finish for each particle: gather style, each particle writes
// only its own outputs, so the particle loop is OpenMP-parallel without atomics. Two drivers give
// the pairs: a cached NeighborList, or the cell list directly with the kernel evaluated on the fly.
// `select(i)` limits the particle loop (e.g. to fluid particles); pairs always include all kinds.
#pragma once

#include "core/cell_list.hpp"
#include "core/neighbor_list.hpp"

#include <cmath>

namespace sph {

struct AllParticles {
  bool operator()(std::size_t) const { return true; }
};

// init, the pairs and finish of particle i alone (the body of interact's particle loop; also for
// a caller that runs an operator on a row right after producing it, while it is in cache).
template <int D, class Op>
void interact_row(const NeighborList<D>& nl, Op& op, std::size_t i) {
  auto acc = op.init(i);
  for (std::uint32_t k = nl.offset[i]; k < nl.offset[i + 1]; ++k)
    op.pair(i, nl.pair(k), acc);
  op.finish(i, acc);
}

template <int D, class Op, class Select = AllParticles>
void interact(const NeighborList<D>& nl, Op& op, Select select = {}) {
  const std::size_t N = nl.num_particles();
#pragma omp parallel for schedule(dynamic, 64)
  for (std::size_t i = 0; i < N; ++i) {
    if (!select(i))
      continue;
    interact_row(nl, op, i);
  }
}

// The same loop for operators on per-pair data cached by the caller (coefficients computed once
// per neighbour configuration): op.pair(i, j, k, acc) gets the pair's index k into the list's
// arrays instead of a Pair, so the loop loads only what the operator reads.
template <int D, class Op, class Select = AllParticles>
void interact_indexed(const NeighborList<D>& nl, Op& op, Select select = {}) {
  const std::size_t N = nl.num_particles();
#pragma omp parallel for schedule(dynamic, 64)
  for (std::size_t i = 0; i < N; ++i) {
    if (!select(i))
      continue;
    auto acc = op.init(i);
    const std::uint32_t end = nl.offset[i + 1];
    for (std::uint32_t k = nl.offset[i]; k < end; ++k)
      op.pair(i, nl.j[k], k, acc);
    op.finish(i, acc);
  }
}

template <int D, class Kernel, class Op, class Select = AllParticles>
void interact(const CellList<D>& cells, const std::vector<Vec<D>>& x, const Kernel& kernel, Op& op,
              Select select = {}) {
  const std::size_t N = x.size();
#pragma omp parallel for schedule(dynamic, 64)
  for (std::size_t i = 0; i < N; ++i) {
    if (!select(i))
      continue;
    auto acc = op.init(i);
    cells.for_each_neighbor(i, x, [&](std::uint32_t j, const Vec<D>& rij, double r2) {
      const double r = std::sqrt(r2);
      op.pair(i, Pair<D>{j, rij, r, kernel.W(r), kernel.dW(r)}, acc);
    });
    op.finish(i, acc);
  }
}

} // namespace sph
