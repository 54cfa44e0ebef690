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
//   "bicgstab_amg"    : the same BiCGSTAB (same stopping rule, |b - A x| <= tol |b|, same warm
//                       start) preconditioned by one V-cycle of HYPRE's BoomerAMG
//                       (schemes/isph/ppe_hypre.hpp);
//   "gmres_amg"       : restarted GMRES(30) (Saad & Schultz 1986), right-preconditioned by the
//                       same V-cycle, so that its residual is the true one and the stopping rule
//                       is the same as BiCGSTAB's.
//   The AMG hierarchy is reused across steps: given the particle identity of each row (solve()'s
//   ids), the V-cycle of the set-up matrix is applied through the permutation from the current
//   particle order to the set-up one. It is then a preconditioner for a nearby matrix; the Krylov
//   iterations use the current one, so the solution and the tolerance are unchanged, only the
//   iteration count grows with the age of the hierarchy. A new hierarchy is set up (default,
//   amg_setup_every() = 0) when the iterations spent above the first solve's count since the
//   last set-up reach the cost of a set-up, measured as 8 GMRES or 4 BiCGSTAB iterations (one or
//   two V-cycles each; a set-up costs about 9 V-cycles at 42k unknowns, docs/isph.md), at the
//   latest after 50 solves: for a linear growth of the count this is the optimal interval
//   sqrt(2 set-up / growth rate). A fixed interval k (set_amg_setup_every(k)) is for the bench.
//   Without ids, or when the size changes, the hierarchy is set up at every solve.
//
// The caller fills the CSR arrays (rows()); solve() returns the iterations (1 for the direct
// solver) and keeps the last solve time. Non-template: SuiteSparse headers stay in one .cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sph {

enum class PpeSolverKind {
  Umfpack,
  BicgstabIlut,
  BicgstabIlu0,
  BicgstabJacobi,
  BicgstabAmg,
  GmresAmg
};

inline const std::vector<std::string>& ppe_solver_names() {
  static const std::vector<std::string> names{"umfpack",         "bicgstab_ilut", "bicgstab_ilu0",
                                              "bicgstab_jacobi", "bicgstab_amg",  "gmres_amg"};
  return names;
}
PpeSolverKind parse_ppe_solver(const std::string& name);

// BoomerAMG parameters of the *_amg solvers (HYPRE reference manual, HYPRE_BoomerAMGSet*). The
// defaults are the ones chosen with bench/ppe_bench on the cavity PPE (docs/isph.md).
struct AmgSettings {
  int coarsen_type = 10; // 10 HMIS, 8 PMIS, 6 Falgout
  int interp_type = 6;   // 6 extended+i, 0 classical
  double strong_threshold = 0.25;
  int agg_num_levels = 0; // levels of aggressive coarsening
  int relax_down = 3;     // 3 / 4 hybrid Gauss-Seidel forward / backward, 6 symmetric, 8 l1-GS,
  int relax_up = 4;       // 18 l1-Jacobi
  int relax_coarse = 9;   // 9 Gaussian elimination on the coarsest level
  int p_max_elmts = 4;    // interpolation truncation: entries per row
  int num_sweeps = 1;
};

// The AMG knobs every PpeSolver copies at construction: the defaults above, changed only by
// bench/ppe_bench to tune them (not a job parameter, so job keys do not depend on them).
struct AmgTuning {
  AmgSettings amg;
  int setup_every = 0; // 0: adaptive; k > 0: a new hierarchy every k solves
};
AmgTuning& amg_tuning();

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
  // ids (optional): the particle identity of each row, unique, for the AMG set-up reuse; without
  // it the AMG hierarchy is set up at every solve.
  int solve(const std::vector<double>& b, std::vector<double>& x,
            const std::vector<std::int64_t>* ids = nullptr);

  double last_error() const { return last_error_; } // relative residual of the last solve
  std::vector<double> last_rhs() const;             // b of the last solve (for tests)

  // AMG only: a new hierarchy every k solves (1: every solve), or 0: adaptive (the default, see
  // above).
  void set_amg_setup_every(int k) { amg_setup_every_ = k < 0 ? 0 : k; }
  int amg_setup_every() const { return amg_setup_every_; }
  long setups() const { return setups_; }           // AMG set-ups so far
  double setup_seconds() const { return setup_s_; } // their total wall time (inside solve())
  double last_setup_seconds() const { return last_setup_s_; }
  // CPU time of this thread inside solve() and inside the AMG set-ups (totals): on a loaded
  // machine these count only our own work (the solvers run on the calling thread).
  double cpu_seconds() const { return cpu_s_; }
  double setup_cpu_seconds() const { return setup_cpu_s_; }
  int amg_levels() const;
  double amg_operator_complexity() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  template <class Solver>
  int iterate(Solver& solver, Impl& s, const std::vector<double>& x0, int n);
  void prepare_amg(Impl& s, int n, const std::vector<std::int64_t>* ids);
  int gmres(Impl& s, const std::vector<double>& x0, int n);
  PpeSolverKind kind_;
  double tol_;
  int max_iter_;
  double last_error_ = 0.0;
  AmgSettings amg_settings_;
  int amg_setup_every_ = 0;
  long setups_ = 0;
  double setup_s_ = 0.0, last_setup_s_ = 0.0, cpu_s_ = 0.0, setup_cpu_s_ = 0.0;
};

} // namespace sph
