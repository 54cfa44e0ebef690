// A grid reference for the lid-driven square cavity: the steady incompressible Navier-Stokes
// equations in streamfunction-vorticity form on a uniform (N + 1) x (N + 1) node grid, solved by
// Newton's method, so that the SPH cavities can be compared with a solution whose own error is
// known and shrinks with N (Ghia, Ghia & Shin's tables are one such solution at N = 128).
//
// Unit square, lid y = 1 moving at u = U (= 1), Reynolds number Re = U L / nu, u = psi_y,
// v = -psi_x, omega = v_x - u_y:
//   laplace(psi) = -omega,                      u omega_x + v omega_y = laplace(omega) / Re,
// second-order central differences at the interior nodes (h = 1 / N), psi = 0 on the walls and
// the wall vorticity of Thom's formula (from psi's Taylor series normal to the wall, psi_n = the
// wall's tangential velocity): omega_w = -2 (psi_1 + h U_w) / h^2, psi_1 the first interior
// node (U_w = U at the lid, 0 elsewhere; the corners do not enter the interior stencils). This is
// the discretisation of Ghia et al. (1982) J. Comput. Phys. 48, 387 (second-order central
// differences, a 129 x 129 grid), which their multigrid method solves by a different iteration.
//
// Centreline velocities at the nodes: u(0.5, y_j) = (psi_{N/2, j+1} - psi_{N/2, j-1}) / (2 h),
// v(x_i, 0.5) = -(psi_{i+1, N/2} - psi_{i-1, N/2}) / (2 h) (N even); second order, so values of
// two grids Richardson-extrapolate as (4 f_h - f_2h) / 3.
#pragma once

#include <vector>

namespace sph {

struct CavityFdSolution {
  int N = 0;
  double Re = 0;
  std::vector<double> psi;   // node (i, j) at i + (N + 1) j (the vorticity is not kept)
  int newton_iterations = 0; // over all continuation stages
  double residual = 0;       // max-norm of the scaled discrete equations at the end

  // u on the vertical centreline x = 0.5 at y = j / N, v on the horizontal one at x = i / N.
  double u_centre(int j) const;
  double v_centre(int i) const;
  // The same at a coordinate within 6e-5 of a node of this grid (throws otherwise).
  double u_at_y(double y) const;
  double v_at_x(double x) const;
};

// Solves the discrete equations to a scaled residual below tol: Newton from rest (its first step
// is the Stokes solution) at min(Re, 100), then continuation with Re doubled up to Re, each
// solution the next one's start. N even, N >= 4; Re > 0. newton_iterations counts all stages.
CavityFdSolution cavity_fd_solve(double Re, int N, double tol = 1e-11, int max_iterations = 30);

} // namespace sph
