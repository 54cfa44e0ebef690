// ppe_bench: the ISPH pressure Poisson solve with BiCGSTAB + ILU(0) against the AMG-preconditioned
// Krylov solvers (HYPRE BoomerAMG) on the lid-driven cavity's own systems (docs/isph.md).
//
// For each dx (default 1/50, 1/100, 1/200, 1/400: 3136, 11 236, 42 436, 164 836 unknowns) the
// cavity (Re = 1000, VISC-04, the scheme's defaults, U0 dt / dx = 0.1) is advanced from rest for
// --warm steps with bicgstab_amg; from that state (particles, pressure as the warm start) each
// variant then runs --steps ISPH steps, the variants alternated A B A B for --rounds rounds, each
// from a copy of the same state. The PPE system of every step is the real one (assembled by
// Isph::assemble on the current configuration). Printed per variant and round: PPE iterations per
// solve, AMG set-up time per step (inside the solve time), solve time per step (set-up included),
// and the whole ISPH step, each as wall time and as CPU time (the process's own: on this shared
// machine wall times vary 2x with the other users' load); then the medians over rounds and the
// ratios first variant / variant (solve_r, step_r: wall; solvc_r, stepc_r: CPU). Run it with one
// thread for the CPU ratios to mean what the wall ratios would on an idle machine.
//
// Usage: ppe_bench [--dx 0.02,0.01,...] [--warm 20] [--steps 5] [--rounds 2] [--threads 1]
//                  [--variants bicgstab_ilu0,bicgstab_amg,gmres_amg,gmres_amg:1]
//                  [--tol 1e-6] [--coarsen 10] [--interp 6] [--strong 0.25] [--agg 0]
//                  [--relax K (down and up)] [--relax-down 3] [--relax-up 4]
//                  [--relax-coarse 9] [--pmax 4] [--sweeps 1] [--verbose]
// A variant is solver[:k], k the AMG set-up interval (a new hierarchy every k solves; without
// :k the solver's adaptive default). Tiny size (a second; the test bench_ppe_bench):
//   ppe_bench --dx 0.05 --warm 2 --steps 2 --rounds 2 --variants bicgstab_ilu0,bicgstab_amg
#include "cases/cavity.hpp"
#include "core/kernels/cubic_spline.hpp"
#include "schemes/isph/isph.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <omp.h>
#include <sstream>
#include <string>
#include <vector>

using namespace sph;

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string t;
  while (std::getline(ss, t, ','))
    if (!t.empty())
      out.push_back(t);
  return out;
}

struct Variant {
  std::string name;
  PpeSolverKind kind;
  int every = 0; // AMG set-up interval, 0: adaptive (the solver's default)
};

struct Sample {
  double iters = 0, setup_s = 0, solve_s = 0, step_s = 0, setups = 0;
  double setup_cpu = 0, solve_cpu = 0, step_cpu = 0; // process / thread CPU time
};

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

} // namespace

int main(int argc, char** argv) {
  std::vector<double> dxs{0.02, 0.01, 0.005, 0.0025};
  int warm = 20, steps = 5, rounds = 2, threads = 1;
  bool verbose = false;
  double tol = 1e-6;
  std::vector<std::string> vnames{"bicgstab_ilu0", "bicgstab_amg", "gmres_amg", "gmres_amg:1"};
  AmgSettings& as = amg_tuning().amg;
  for (int a = 1; a < argc; ++a) {
    const std::string k = argv[a];
    auto next = [&]() -> std::string {
      if (a + 1 >= argc) {
        std::fprintf(stderr, "missing value after %s\n", k.c_str());
        std::exit(2);
      }
      return argv[++a];
    };
    if (k == "--dx") {
      dxs.clear();
      for (const auto& t : split(next()))
        dxs.push_back(std::stod(t));
    } else if (k == "--warm")
      warm = std::stoi(next());
    else if (k == "--steps")
      steps = std::stoi(next());
    else if (k == "--rounds")
      rounds = std::stoi(next());
    else if (k == "--threads")
      threads = std::stoi(next());
    else if (k == "--verbose")
      verbose = true;
    else if (k == "--tol")
      tol = std::stod(next());
    else if (k == "--variants")
      vnames = split(next());
    else if (k == "--coarsen")
      as.coarsen_type = std::stoi(next());
    else if (k == "--interp")
      as.interp_type = std::stoi(next());
    else if (k == "--strong")
      as.strong_threshold = std::stod(next());
    else if (k == "--agg")
      as.agg_num_levels = std::stoi(next());
    else if (k == "--relax") // down and up
      as.relax_down = as.relax_up = std::stoi(next());
    else if (k == "--relax-down")
      as.relax_down = std::stoi(next());
    else if (k == "--relax-up")
      as.relax_up = std::stoi(next());
    else if (k == "--relax-coarse")
      as.relax_coarse = std::stoi(next());
    else if (k == "--pmax")
      as.p_max_elmts = std::stoi(next());
    else if (k == "--sweeps")
      as.num_sweeps = std::stoi(next());
    else {
      std::fprintf(stderr, "unknown option %s (see the header of bench/ppe_bench.cpp)\n",
                   k.c_str());
      return 2;
    }
  }
  omp_set_num_threads(threads);
  std::vector<Variant> vars;
  for (const auto& v : vnames) {
    Variant x;
    const auto c = v.find(':');
    x.name = v;
    x.kind = parse_ppe_solver(v.substr(0, c));
    if (c != std::string::npos)
      x.every = std::stoi(v.substr(c + 1));
    vars.push_back(x);
  }
  std::printf("# ppe_bench: lid-driven cavity Re = 1000, VISC-04, tol %.0e, %d thread(s), warm-up "
              "%d steps, %d steps per sample, %d rounds (variants alternated)\n",
              tol, threads, warm, steps, rounds);
  std::printf("# BoomerAMG: coarsen %d, interp %d, strong %.2f, agg levels %d, relax down %d up %d "
              "coarsest %d, pmax %d, sweeps %d\n",
              as.coarsen_type, as.interp_type, as.strong_threshold, as.agg_num_levels,
              as.relax_down, as.relax_up, as.relax_coarse, as.p_max_elmts, as.num_sweeps);
  std::printf("# per step (one solve per step), wall ms and CPU ms; solve includes setup\n");
  std::printf("%-8s %-16s %5s %8s %6s %9s %9s %9s %9s %9s %9s %6s %5s\n", "N", "variant", "round",
              "it/solve", "setups", "setup", "solve", "step", "setup_cpu", "solve_cpu", "step_cpu",
              "levels", "opcx");
  std::fflush(stdout);

  for (double dx : dxs) {
    CavityGeometry g;
    g.dx = dx;
    Particles<2> p0;
    const int vw = build_cavity(p0, g);
    CubicSpline<2> W(1.2 * dx);
    const double nu = 1e-3, dt = 0.1 * dx;
    IsphOptions opt;
    opt.ppe_tol = tol;
    {
      IsphOptions ow = opt;
      ow.solver = PpeSolverKind::BicgstabAmg;
      Isph<2, CubicSpline<2>> s(p0, Domain<2>{}, W, ow, vw, nu, dt, dx);
      for (int k = 0; k < warm; ++k)
        s.step();
    }
    const std::size_t N = p0.size();
    std::vector<std::vector<Sample>> res(vars.size());
    for (int r = 0; r < rounds; ++r) {
      for (std::size_t v = 0; v < vars.size(); ++v) {
        Particles<2> p = p0;
        IsphOptions o = opt;
        o.solver = vars[v].kind;
        amg_tuning().setup_every = vars[v].every;
        Isph<2, CubicSpline<2>> s(p, Domain<2>{}, W, o, vw, nu, dt, dx);
        double cpu = 0.0;
        for (int k = 0; k < steps; ++k) {
          const double c0 = process_cpu_seconds();
          s.step();
          cpu += process_cpu_seconds() - c0;
          if (verbose)
            std::printf("#   step %d: %d iterations, residual %.2e, setups %ld\n", k,
                        s.last_iterations(), s.ppe_residual(), s.ppe().setups());
        }
        Sample x;
        x.iters = static_cast<double>(s.iterations_total()) / steps;
        x.setups = static_cast<double>(s.ppe().setups());
        x.setup_s = s.ppe().setup_seconds() / steps;
        x.solve_s = s.time_solve() / steps;
        x.step_s = s.time_step() / steps;
        x.setup_cpu = s.ppe().setup_cpu_seconds() / steps;
        x.solve_cpu = s.ppe().cpu_seconds() / steps;
        x.step_cpu = cpu / steps;
        res[v].push_back(x);
        std::printf("%-8zu %-16s %5d %8.2f %6.0f %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %6d %5.2f\n",
                    N, vars[v].name.c_str(), r, x.iters, x.setups, 1e3 * x.setup_s, 1e3 * x.solve_s,
                    1e3 * x.step_s, 1e3 * x.setup_cpu, 1e3 * x.solve_cpu, 1e3 * x.step_cpu,
                    s.ppe().amg_levels(), s.ppe().amg_operator_complexity());
        std::fflush(stdout);
      }
    }
    auto med = [&](std::size_t v, double Sample::*f) {
      std::vector<double> a;
      for (const auto& x : res[v])
        a.push_back(x.*f);
      return median(a);
    };
    std::printf("# N = %zu, medians over rounds; ratio = %s / variant\n", N, vars[0].name.c_str());
    std::printf("# %-16s %8s %9s %9s %9s %9s %9s %9s %7s %7s %7s %7s\n", "variant", "it/solve",
                "setup", "solve", "step", "setup_cpu", "solve_cpu", "step_cpu", "solve_r", "step_r",
                "solvc_r", "stepc_r");
    for (std::size_t v = 0; v < vars.size(); ++v)
      std::printf("# %-16s %8.2f %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %7.2f %7.2f %7.2f %7.2f\n",
                  vars[v].name.c_str(), med(v, &Sample::iters), 1e3 * med(v, &Sample::setup_s),
                  1e3 * med(v, &Sample::solve_s), 1e3 * med(v, &Sample::step_s),
                  1e3 * med(v, &Sample::setup_cpu), 1e3 * med(v, &Sample::solve_cpu),
                  1e3 * med(v, &Sample::step_cpu),
                  med(0, &Sample::solve_s) / med(v, &Sample::solve_s),
                  med(0, &Sample::step_s) / med(v, &Sample::step_s),
                  med(0, &Sample::solve_cpu) / med(v, &Sample::solve_cpu),
                  med(0, &Sample::step_cpu) / med(v, &Sample::step_cpu));
    std::fflush(stdout);
  }
  return 0;
}
