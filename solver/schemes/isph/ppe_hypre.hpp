// HYPRE BoomerAMG (Henson & Yang 2002, Appl. Numer. Math. 41, 155) as a preconditioner of the
// PPE's Krylov solvers (schemes/isph/ppe_solver.cpp). Private to the PPE solver: the HYPRE and MPI
// headers stay in ppe_hypre.cpp.
//
// Debian's libhypre is built with MPI (Open MPI); it is used sequentially on MPI_COMM_SELF. The
// first HypreAmg initialises MPI if the program has not (an isolated singleton: no orted daemon,
// no process binding; OMPI_MCA_ess_singleton_isolated = 1 unless the environment says otherwise)
// and finalises it at exit.
#pragma once

#include "schemes/isph/ppe_solver.hpp"

#include <Eigen/Sparse>

#include <memory>

namespace sph {

class HypreAmg {
public:
  using RowMat = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
  explicit HypreAmg(const AmgSettings& s = {});
  ~HypreAmg();
  HypreAmg(const HypreAmg&) = delete;
  HypreAmg& operator=(const HypreAmg&) = delete;

  // Copies A (square, CSR) into HYPRE and builds the BoomerAMG hierarchy.
  void setup(const RowMat& a);
  // out = one V-cycle for A out = in from a zero guess, A the matrix of the last setup; in and out
  // have setup's size and may not alias.
  void apply(const double* in, double* out) const;
  int rows() const { return n_; }
  int levels() const; // levels of the last hierarchy
  double operator_complexity() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  AmgSettings settings_;
  int n_ = 0;
};

} // namespace sph
