// sph_bench: throughput of the solver core, the numbers ../README.md reports.
//
// On a slightly disordered lattice in a periodic box (every coordinate shifted by up to 0.1 dx,
// Wendland C2, h = 1.3 dx: 20 neighbours in 2D, 79 in 3D) it measures:
//   - neighbour search, in ns per particle:
//       cell list build: counting sort by cell and reorder of every particle field;
//       neighbour list from the cell list: candidates within the support, then the pair geometry
//         (r_ij, r, W, dW) of the pairs within it (NeighborList::build(CellList, ...));
//       Verlet list build: sort, then the candidates within cutoff = support + skin
//         (VerletList::rebuild; what LAMMPS's "Neigh" time counts per build);
//       pair geometry from the Verlet list: r_ij, r, W, dW of its candidates within the support,
//         every step (NeighborList::build(VerletList, ...));
//   - pair loops, in pair evaluations per second per core (one evaluation = one ordered pair
//     i, j != i within the support, gather style), through both drivers (on the fly from the cell
//     list, and from the cached neighbour list):
//       density:  rho_i = sum_j m_j W_ij                                (SummationDensity)
//       pressure: a_i = -sum_j m_j (p_i / rho_i^2 + p_j / rho_j^2) grad_i W_ij
// Anchor (../shared/notes/performance.md): 2.5-3e7 pair evaluations per second per core;
// bench/lammps_ab.sh runs LAMMPS beside it.
// Usage: sph_bench [--n N] [--dim 2|3] [--threads T] [--skin F] [--quick] [--csv]
//   default: N = 10k, 40k, 160k, both dimensions, 1 thread and all; skin = F x support (0.25,
//   the wcsph_tvf default); --quick: N = 10k only. Tiny size (seconds; the test bench_sph_bench):
//   sph_bench --n 1000 --threads 1 --csv.
#include "core/cell_list.hpp"
#include "core/kernels/wendland_c2.hpp"
#include "core/lattice.hpp"
#include "core/neighbor_list.hpp"
#include "core/verlet_list.hpp"
#include "operators/summation_density.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <omp.h>
#include <string>
#include <vector>

using namespace sph;

namespace {

template <int D, class Kernel>
struct PressureGradient {
  const Particles<D>& p;
  std::vector<Vec<D>>& a;
  struct Acc {
    Vec<D> s = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& acc) const {
    const double pi = p.p[i] / (p.rho[i] * p.rho[i]);
    const double pj = p.p[q.j] / (p.rho[q.j] * p.rho[q.j]);
    acc.s -= p.m[q.j] * (pi + pj) * q.grad();
  }
  void finish(std::size_t i, const Acc& acc) { a[i] = acc.s; }
};

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Seconds per call of f, repeated until at least `min_time` has passed.
template <class F>
double time_it(F&& f, double min_time = 0.3) {
  f(); // warm-up
  int reps = 0;
  const double t0 = now();
  double t;
  do {
    f();
    ++reps;
    t = now() - t0;
  } while (t < min_time);
  return t / reps;
}

bool csv = false;

void report(int D, std::size_t N, double neighbours, int threads, const char* what, double value,
            const char* unit) {
  if (csv)
    std::printf("%d,%zu,%.1f,%d,%s,%.4g,%s\n", D, N, neighbours, threads, what, value, unit);
  else
    std::printf("  %dD N=%-7zu nbrs=%5.1f threads=%d  %-34s %10.4g %s\n", D, N, neighbours, threads,
                what, value, unit);
  std::fflush(stdout);
}

template <int D>
void bench(std::size_t N_target, int threads, double skin_fraction) {
  omp_set_num_threads(threads);
  const int n = static_cast<int>(std::lround(std::pow(static_cast<double>(N_target), 1.0 / D)));
  const double dx = 1.0 / n;
  WendlandC2<D> kernel(1.3 * dx);
  Domain<D> box;
  box.periodic.fill(true);
  Particles<D> p;
  UniformRandom rn(1);
  std::array<int, D> lo{}, hi;
  hi.fill(n);
  for_each_lattice_point<D>(lo, hi, dx, [&](Vec<D> x, const std::array<int, D>&) {
    for (int a = 0; a < D; ++a)
      x[a] += (rn() - 0.5) * 0.2 * dx;
    const auto i = p.add(x, std::pow(dx, D), 1.0);
    p.p[i] = 1.0 + 0.1 * rn();
  });
  // Shuffle the storage order so the first cell-list build does real work.
  std::vector<std::uint32_t> perm(p.size());
  for (std::size_t i = 0; i < perm.size(); ++i)
    perm[i] = static_cast<std::uint32_t>(i);
  for (std::size_t i = perm.size() - 1; i > 0; --i)
    std::swap(perm[i], perm[static_cast<std::size_t>(rn() * (i + 1))]);
  p.reorder(perm);

  const std::size_t N = p.size();
  CellList<D> cells(box, kernel.support());
  cells.build(p);
  NeighborList<D> nl;
  nl.build(cells, p.r, kernel);
  const double nbrs = static_cast<double>(nl.num_pairs()) / N;
  const double pairs = static_cast<double>(nl.num_pairs());

  const double t_cells = time_it([&] { cells.build(p); });
  report(D, N, nbrs, threads, "cell list build", 1e9 * t_cells / N, "ns/particle");
  const double t_nl = time_it([&] { nl.build(cells, p.r, kernel); });
  report(D, N, nbrs, threads, "neighbour list build", 1e9 * t_nl / N, "ns/particle");

  const double skin =
      VerletList<D>::largest_skin(box, kernel.support(), skin_fraction * kernel.support());
  VerletList<D> vl(box, kernel.support(), skin);
  vl.rebuild(p);
  report(D, N, nbrs, threads, "verlet candidates", static_cast<double>(vl.rows().size()) / N,
         "per particle");
  const double t_vl = time_it([&] { vl.rebuild(p); });
  report(D, N, nbrs, threads, "verlet list build", 1e9 * t_vl / N, "ns/particle");
  const double t_geo = time_it([&] { nl.build(vl, p.r, kernel); });
  report(D, N, nbrs, threads, "pair geometry (verlet list)", 1e9 * t_geo / N, "ns/particle");

  // The loops on cells of edge = the support (the Verlet build sorted by its larger cells).
  cells.build(p);
  nl.build(cells, p.r, kernel);
  SummationDensity<D, WendlandC2<D>> density{p, kernel};
  const double t_rho_cells = time_it([&] { interact(cells, p.r, kernel, density); });
  report(D, N, nbrs, threads, "density (cell list)", pairs / t_rho_cells / threads, "pairs/s/core");
  const double t_rho_nl = time_it([&] { interact(nl, density); });
  report(D, N, nbrs, threads, "density (neighbour list)", pairs / t_rho_nl / threads,
         "pairs/s/core");

  std::vector<Vec<D>> acc(N);
  PressureGradient<D, WendlandC2<D>> pg{p, acc};
  const double t_pg_cells = time_it([&] { interact(cells, p.r, kernel, pg); });
  report(D, N, nbrs, threads, "pressure grad (cell list)", pairs / t_pg_cells / threads,
         "pairs/s/core");
  const double t_pg_nl = time_it([&] { interact(nl, pg); });
  report(D, N, nbrs, threads, "pressure grad (nbr list)", pairs / t_pg_nl / threads,
         "pairs/s/core");
}

int usage() {
  std::fprintf(stderr,
               "usage: sph_bench [--n N] [--dim 2|3] [--threads T] [--skin F] [--quick] [--csv]\n");
  return 2;
}

} // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::vector<std::size_t> sizes{10000, 40000, 160000};
  std::vector<int> dims{2, 3}, thread_counts;
  double skin = 0.25;
  for (int k = 1; k < argc; ++k) {
    const bool has_value = k + 1 < argc;
    if (!std::strcmp(argv[k], "--quick"))
      quick = true;
    else if (!std::strcmp(argv[k], "--csv"))
      csv = true;
    else if (!std::strcmp(argv[k], "--n") && has_value)
      sizes = {static_cast<std::size_t>(std::atol(argv[++k]))};
    else if (!std::strcmp(argv[k], "--dim") && has_value)
      dims = {std::atoi(argv[++k])};
    else if (!std::strcmp(argv[k], "--threads") && has_value)
      thread_counts = {std::atoi(argv[++k])};
    else if (!std::strcmp(argv[k], "--skin") && has_value)
      skin = std::atof(argv[++k]);
    else
      return usage();
  }
  for (int d : dims)
    if (d != 2 && d != 3)
      return usage();
  if (sizes[0] < 100)
    return usage();
  const int all = omp_get_num_procs();
  if (thread_counts.empty()) {
    thread_counts = {1};
    if (all > 1)
      thread_counts.push_back(all);
  }
  if (quick)
    sizes.resize(1);
  if (csv)
    std::printf("dim,particles,neighbours,threads,measure,value,unit\n");
  for (std::size_t N : sizes)
    for (int t : thread_counts)
      for (int d : dims)
        d == 2 ? bench<2>(N, t, skin) : bench<3>(N, t, skin);
  return 0;
}
