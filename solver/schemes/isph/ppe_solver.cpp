// PPE linear solvers: UMFPACK sparse LU and BiCGSTAB + ILUT (see ppe_solver.hpp).
#include "schemes/isph/ppe_solver.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <Eigen/UmfPackSupport>

#include <cmath>
#include <stdexcept>
#include <type_traits>

namespace sph {

PpeSolverKind parse_ppe_solver(const std::string& name) {
  if (name == "umfpack")
    return PpeSolverKind::Umfpack;
  if (name == "bicgstab_ilut")
    return PpeSolverKind::BicgstabIlut;
  if (name == "bicgstab_ilu0")
    return PpeSolverKind::BicgstabIlu0;
  if (name == "bicgstab_jacobi")
    return PpeSolverKind::BicgstabJacobi;
  throw std::invalid_argument("unknown PPE solver '" + name + "'");
}

namespace {

// ILU(0): incomplete LU with the sparsity of A (Saad, Iterative Methods for Sparse Linear
// Systems, 2nd ed. 2003, Algorithm 10.4, IKJ variant), as an Eigen preconditioner. Rows of A
// must have sorted column indices and a non-zero diagonal. The particle order (sorted by cell)
// keeps the fill pattern local, so ILU(0) is cheap (O(nnz x row length)) and effective.
class Ilu0 {
public:
  using RowMat = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
  Ilu0() = default;
  template <class M>
  explicit Ilu0(const M& a) {
    compute(a);
  }
  template <class M>
  Ilu0& analyzePattern(const M&) {
    return *this;
  }
  template <class M>
  Ilu0& factorize(const M& a) {
    return compute(a);
  }
  template <class M>
  Ilu0& compute(const M& a) {
    lu_ = a;
    const int n = static_cast<int>(lu_.rows());
    const int* off = lu_.outerIndexPtr();
    const int* col = lu_.innerIndexPtr();
    double* val = lu_.valuePtr();
    diag_.resize(n);
    marker_.assign(n, -1);
    for (int i = 0; i < n; ++i) {
      for (int q = off[i]; q < off[i + 1]; ++q)
        marker_[col[q]] = q;
      for (int q = off[i]; q < off[i + 1] && col[q] < i; ++q) {
        const int k = col[q];
        val[q] /= val[diag_[k]];
        const double lik = val[q];
        for (int r = diag_[k] + 1; r < off[k + 1]; ++r) {
          const int m = marker_[col[r]];
          if (m >= 0)
            val[m] -= lik * val[r];
        }
      }
      diag_[i] = marker_[i];
      for (int q = off[i]; q < off[i + 1]; ++q)
        marker_[col[q]] = -1;
      if (diag_[i] < 0) {
        info_ = Eigen::NumericalIssue, bad_row_ = i;
        return *this;
      }
      // Pivot guard: a vanishing or sign-flipped pivot is replaced by A's own diagonal (the
      // preconditioner only has to be close to A^-1, BiCGSTAB keeps the solution exact).
      const double aii = a.coeff(i, i);
      if (!(std::abs(val[diag_[i]]) > 1e-8 * std::abs(aii)) || val[diag_[i]] * aii < 0.0)
        val[diag_[i]] = aii, ++guarded_;
      if (aii == 0.0) {
        info_ = Eigen::NumericalIssue, bad_row_ = i;
        return *this;
      }
    }
    info_ = Eigen::Success;
    return *this;
  }
  template <class Rhs>
  Eigen::VectorXd solve(const Rhs& b) const {
    const int n = static_cast<int>(lu_.rows());
    const int* off = lu_.outerIndexPtr();
    const int* col = lu_.innerIndexPtr();
    const double* val = lu_.valuePtr();
    Eigen::VectorXd x = b;
    for (int i = 0; i < n; ++i) {
      double s = x[i];
      for (int q = off[i]; q < diag_[i]; ++q)
        s -= val[q] * x[col[q]];
      x[i] = s;
    }
    for (int i = n - 1; i >= 0; --i) {
      double s = x[i];
      for (int q = diag_[i] + 1; q < off[i + 1]; ++q)
        s -= val[q] * x[col[q]];
      x[i] = s / val[diag_[i]];
    }
    return x;
  }
  Eigen::ComputationInfo info() const { return info_; }
  long guarded() const { return guarded_; }
  int bad_row() const { return bad_row_; }

private:
  long guarded_ = 0;
  int bad_row_ = -1;
  RowMat lu_;
  std::vector<int> diag_, marker_;
  Eigen::ComputationInfo info_ = Eigen::Success;
};

} // namespace

struct PpeSolver::Impl {
  using RowMat = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
  using ColMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  RowMat a;
  ColMat a_col;
  Eigen::UmfPackLU<ColMat> lu;
  Eigen::BiCGSTAB<RowMat, Eigen::IncompleteLUT<double>> bicg;
  Eigen::BiCGSTAB<RowMat, Eigen::DiagonalPreconditioner<double>> jacobi;
  Eigen::BiCGSTAB<RowMat, Ilu0> ilu0;
  Eigen::VectorXd b, x, a1;
};

PpeSolver::PpeSolver(PpeSolverKind kind, double tol, int max_iter)
    : impl_(std::make_unique<Impl>()), kind_(kind), tol_(tol), max_iter_(max_iter) {}
PpeSolver::~PpeSolver() = default;

template <class Solver>
int PpeSolver::iterate(Solver& solver, Impl& s, const std::vector<double>& x0, int n) {
  solver.setTolerance(tol_);
  solver.setMaxIterations(max_iter_);
  solver.compute(s.a);
  if (solver.info() != Eigen::Success) {
    std::string where;
    if constexpr (std::is_same_v<std::decay_t<decltype(solver.preconditioner())>, Ilu0>)
      where = " (zero diagonal in row " + std::to_string(solver.preconditioner().bad_row()) + ")";
    throw std::runtime_error("PPE: preconditioner failed" + where);
  }
  // Constant-mode correction of the warm start: the PPE is regularised pure-Neumann, so the
  // constant vector is its slowest mode; shift x0 by the delta minimising |b - A (x0 + delta 1)|
  // (a one-vector coarse correction) before iterating.
  s.x = Eigen::Map<const Eigen::VectorXd>(x0.data(), n);
  s.a1 = s.a * Eigen::VectorXd::Ones(n);
  const double a1a1 = s.a1.squaredNorm();
  if (a1a1 > 0.0)
    s.x.array() += s.a1.dot(s.b - s.a * s.x) / a1a1;
  s.x = solver.solveWithGuess(s.b, s.x);
  last_error_ = solver.error();
  if (solver.info() == Eigen::NumericalIssue)
    throw std::runtime_error("PPE: BiCGSTAB breakdown");
  return static_cast<int>(solver.iterations());
}

int PpeSolver::solve(const std::vector<double>& b, std::vector<double>& x) {
  const int n = static_cast<int>(offset.size()) - 1;
  const int nnz = offset[n];
  Impl& s = *impl_;
  // Copy the caller's CSR into Eigen's row-major storage (reuses capacity).
  s.a.resize(n, n);
  s.a.resizeNonZeros(nnz);
  std::copy(offset.begin(), offset.end(), s.a.outerIndexPtr());
  std::copy(col.begin(), col.begin() + nnz, s.a.innerIndexPtr());
  std::copy(val.begin(), val.begin() + nnz, s.a.valuePtr());
  s.b = Eigen::Map<const Eigen::VectorXd>(b.data(), n);
  int iters = 1;
  if (kind_ == PpeSolverKind::Umfpack) {
    s.a_col = s.a;
    s.lu.compute(s.a_col);
    if (s.lu.info() != Eigen::Success)
      throw std::runtime_error("PPE: UMFPACK factorisation failed");
    s.x = s.lu.solve(s.b);
    last_error_ = (s.a * s.x - s.b).norm() / std::max(s.b.norm(), 1e-300);
  } else if (kind_ == PpeSolverKind::BicgstabIlut) {
    iters = iterate(s.bicg, s, x, n);
  } else if (kind_ == PpeSolverKind::BicgstabIlu0) {
    iters = iterate(s.ilu0, s, x, n);
  } else {
    iters = iterate(s.jacobi, s, x, n);
  }
  x.resize(n);
  Eigen::Map<Eigen::VectorXd>(x.data(), n) = s.x;
  return iters;
}

} // namespace sph
