// Linear solvers for the pressure Poisson equation of the ISPH projection (seed 001, eq. 13 with
// the Laplacian of eq. 14), assembled every step as a sparse matrix in compressed rows.
//
//   "umfpack"  : sparse LU of SuiteSparse/UMFPACK (Davis 2004, ACM TOMS 30) through Eigen's
//                UmfPackLU; direct, exact to round-off, the matrix is non-symmetric (the wall rows
//                are extrapolations, see isph.hpp), so CHOLMOD does not apply.
//   "bicgstab_ilut"   : Eigen BiCGSTAB (van der Vorst 1992) preconditioned by incomplete LU with
//                       threshold (Saad 1994, IncompleteLUT), warm-started from the previous
//                       step's pressure;
//   "bicgstab_ilu0"   : the same with ILU(0), incomplete LU on A's own sparsity (Saad 2003,
//                       Algorithm 10.4; written here, Eigen has none);
//   "bicgstab_jacobi" : the same with the diagonal (Jacobi) preconditioner. The particle order
//                       changes at every neighbour search, so no factorisation can be reused
//                       across steps; see docs/isph.md for the measurements that chose the
//                       default.
//
// The caller fills the CSR arrays (rows()); solve() returns the iterations (1 for the direct
// solver) and keeps the last solve time. Non-template: SuiteSparse headers stay in one .cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sph {

enum class PpeSolverKind { Umfpack, BicgstabIlut, BicgstabIlu0, BicgstabJacobi };

inline const std::vector<std::string>& ppe_solver_names() {
  static const std::vector<std::string> names{"umfpack", "bicgstab_ilut", "bicgstab_ilu0",
                                              "bicgstab_jacobi"};
  return names;
}
PpeSolverKind parse_ppe_solver(const std::string& name);

class PpeSolver {
public:
  PpeSolver(PpeSolverKind kind, double tol, int max_iter);
  ~PpeSolver();
  PpeSolver(const PpeSolver&) = delete;
  PpeSolver& operator=(const PpeSolver&) = delete;

  // The matrix in compressed rows, filled by the caller before solve(): offset (n + 1),
  // col and val (nnz). Sized once, reused every step (capacity grows only when nnz grows).
  std::vector<std::int32_t> offset, col;
  std::vector<double> val;

  // Solves A x = b; x holds the initial guess on entry (used by the iterative solver).
  // Returns the number of iterations; throws std::runtime_error when the solve fails.
  int solve(const std::vector<double>& b, std::vector<double>& x);

  double last_error() const { return last_error_; } // relative residual of the last solve

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  template <class Solver>
  int iterate(Solver& solver, Impl& s, const std::vector<double>& x0, int n);
  PpeSolverKind kind_;
  double tol_;
  int max_iter_;
  double last_error_ = 0.0;
};

} // namespace sph
