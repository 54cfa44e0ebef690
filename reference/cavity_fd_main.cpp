// cavity_fd RE N1 N2 ...: the finite-difference cavity (cavity_fd.hpp) at Reynolds number RE on
// grids of N1, N2, ... cells (each a multiple of 128, ascending), printed as CSV at the 17 points
// of Ghia, Ghia & Shin's (1982) Tables I and II: u(0.5, y) and v(x, 0.5) per grid, and the
// Richardson extrapolation (4 f_N - f_N/2) / 3 of the two finest grids.
#include "cavity_fd.hpp"

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {
// Ghia et al.'s point coordinates (the same for u and v tables), as they print them.
constexpr std::array<double, 17> ghia_y{1.0000, 0.9766, 0.9688, 0.9609, 0.9531, 0.8516,
                                        0.7344, 0.6172, 0.5000, 0.4531, 0.2813, 0.1719,
                                        0.1016, 0.0703, 0.0625, 0.0547, 0.0000};
constexpr std::array<double, 17> ghia_x{1.0000, 0.9688, 0.9609, 0.9531, 0.9453, 0.9063,
                                        0.8594, 0.8047, 0.5000, 0.2344, 0.2266, 0.1563,
                                        0.0938, 0.0781, 0.0703, 0.0625, 0.0000};
} // namespace

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
  for (int pass = 0; pass < 2; ++pass)
    for (int k = 0; k < 17; ++k) {
      const double c = pass == 0 ? ghia_y[k] : ghia_x[k];
      std::printf("%s,%.4f", pass == 0 ? "u_at_y" : "v_at_x", c);
      for (const auto& g : s)
        std::printf(",%.6f", pass == 0 ? g.u_at_y(c) : g.v_at_x(c));
      if (extrapolate) {
        const auto &f = s.back(), &c2 = s[s.size() - 2];
        const double a = pass == 0 ? f.u_at_y(c) : f.v_at_x(c);
        const double b = pass == 0 ? c2.u_at_y(c) : c2.v_at_x(c);
        std::printf(",%.6f", (4.0 * a - b) / 3.0);
      }
      std::printf("\n");
    }
  return 0;
}
