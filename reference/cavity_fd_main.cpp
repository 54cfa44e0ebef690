// cavity_fd RE N1 N2 ...: the finite-difference cavity (cavity_fd.hpp) at Reynolds number RE on
// grids of N1, N2, ... cells (each a multiple of 128, ascending), printed as CSV at the 17 points
// of Ghia, Ghia & Shin's (1982) Tables I and II: u(0.5, y) and v(x, 0.5) per grid, and the
// Richardson extrapolation (4 f_N - f_N/2) / 3 of the two finest grids.
#include "cavity_fd.hpp"
#include "data/ghia1982.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: cavity_fd RE N1 [N2 ...]  (N a multiple of 128, ascending)\n");
    return 2;
  }
  const double Re = std::atof(argv[1]);
  std::vector<sph::CavityFdSolution> s;
  for (int a = 2; a < argc; ++a) {
    const int N = std::atoi(argv[a]);
    if (N <= 0 || N % 128 != 0 || (!s.empty() && N <= s.back().N)) {
      std::fprintf(stderr, "cavity_fd: N = %s: a multiple of 128, ascending, expected\n", argv[a]);
      return 2;
    }
    const auto t0 = std::chrono::steady_clock::now();
    s.push_back(sph::cavity_fd_solve(Re, N));
    std::fprintf(stderr, "N = %d: %d Newton iterations, residual %.1e, %.1f s\n", N,
                 s.back().newton_iterations, s.back().residual,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::printf("profile,coord");
  for (const auto& g : s)
    std::printf(",N%d", g.N);
  const bool extrapolate = s.size() >= 2 && s.back().N == 2 * s[s.size() - 2].N;
  if (extrapolate)
    std::printf(",richardson");
  std::printf("\n");
  // Ghia et al.'s point coordinates, as they print them (the same for Re = 100 and 1000).
  using sph::data::ghia_re1000_x, sph::data::ghia_re1000_y;
  for (const bool u : {true, false})
    for (int k = 0; k < sph::data::ghia_points; ++k) {
      const double c = u ? ghia_re1000_y[k] : ghia_re1000_x[k];
      auto at = [&](const sph::CavityFdSolution& g) { return u ? g.u_at_y(c) : g.v_at_x(c); };
      std::printf("%s,%.4f", u ? "u_at_y" : "v_at_x", c);
      for (const auto& g : s)
        std::printf(",%.6f", at(g));
      if (extrapolate)
        std::printf(",%.6f", (4.0 * at(s.back()) - at(s[s.size() - 2])) / 3.0);
      std::printf("\n");
    }
  return 0;
}
