// PPE linear solvers: UMFPACK sparse LU, BiCGSTAB + ILUT / ILU(0) / Jacobi / BoomerAMG, GMRES +
// BoomerAMG (see ppe_solver.hpp).
#include "schemes/isph/ppe_solver.hpp"

#include "schemes/isph/ppe_hypre.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <Eigen/UmfPackSupport>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
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
  if (name == "bicgstab_amg")
    return PpeSolverKind::BicgstabAmg;
  if (name == "gmres_amg")
    return PpeSolverKind::GmresAmg;
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

// One BoomerAMG V-cycle as an Eigen preconditioner. The hierarchy is set up by PpeSolver (compute()
// is a no-op); perm, when set, maps the current row i to the row perm[i] of the set-up matrix.
class AmgPrecond {
public:
  AmgPrecond() = default;
  template <class M>
  explicit AmgPrecond(const M&) {}
  template <class M>
  AmgPrecond& analyzePattern(const M&) {
    return *this;
  }
  template <class M>
  AmgPrecond& factorize(const M&) {
    return *this;
  }
  template <class M>
  AmgPrecond& compute(const M&) {
    return *this;
  }
  void attach(const HypreAmg* amg, const std::vector<int>* perm) { amg_ = amg, perm_ = perm; }
  void apply(const double* in, double* out) const {
    if (!perm_) {
      amg_->apply(in, out);
      return;
    }
    const int n = amg_->rows();
    const std::vector<int>& p = *perm_;
    tin_.resize(n), tout_.resize(n);
    for (int i = 0; i < n; ++i)
      tin_[p[i]] = in[i];
    amg_->apply(tin_.data(), tout_.data());
    for (int i = 0; i < n; ++i)
      out[i] = tout_[p[i]];
  }
  template <class Rhs>
  Eigen::VectorXd solve(const Rhs& b) const {
    in_ = b;
    Eigen::VectorXd out(in_.size());
    apply(in_.data(), out.data());
    return out;
  }
  Eigen::ComputationInfo info() const { return amg_ ? Eigen::Success : Eigen::InvalidInput; }

private:
  const HypreAmg* amg_ = nullptr;
  const std::vector<int>* perm_ = nullptr;
  mutable Eigen::VectorXd in_;
  mutable std::vector<double> tin_, tout_;
};

} // namespace

namespace {

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Constant-mode correction of the warm start: the PPE is regularised pure-Neumann, so the
// constant vector is its slowest mode; shift x0 by the delta minimising |b - A (x0 + delta 1)|
// (a one-vector coarse correction) before iterating.
template <class M>
void warm_start(const M& a, const Eigen::VectorXd& b, const std::vector<double>& x0, int n,
                Eigen::VectorXd& a1, Eigen::VectorXd& x) {
  x = Eigen::Map<const Eigen::VectorXd>(x0.data(), n);
  a1 = a * Eigen::VectorXd::Ones(n);
  const double a1a1 = a1.squaredNorm();
  if (a1a1 > 0.0)
    x.array() += a1.dot(b - a * x) / a1a1;
}

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
  Eigen::BiCGSTAB<RowMat, AmgPrecond> bicg_amg;
  AmgPrecond amg_precond; // for GMRES
  std::unique_ptr<HypreAmg> amg;
  // AMG set-up reuse: row of each particle id in the set-up matrix, the current permutation.
  std::vector<int> setup_row, perm;
  int solves_since_setup = 0;
  int iters_after_setup = 0; // iterations of the first solve on a new hierarchy
  int excess = 0;            // iterations above that count since the set-up
  bool permuted = false;
  Eigen::VectorXd b, x, a1;
  // GMRES work space: Krylov basis, preconditioned basis, Hessenberg, rotations.
  std::vector<Eigen::VectorXd> v, z;
  Eigen::MatrixXd h;
  Eigen::VectorXd cs, sn, g, w, r;
};

AmgTuning& amg_tuning() {
  static AmgTuning t;
  return t;
}

PpeSolver::PpeSolver(PpeSolverKind kind, double tol, int max_iter)
    : impl_(std::make_unique<Impl>()), kind_(kind), tol_(tol), max_iter_(max_iter),
      amg_settings_(amg_tuning().amg), amg_setup_every_(amg_tuning().setup_every) {}
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
  warm_start(s.a, s.b, x0, n, s.a1, s.x);
  s.x = solver.solveWithGuess(s.b, s.x);
  last_error_ = solver.error();
  if (solver.info() == Eigen::NumericalIssue)
    throw std::runtime_error("PPE: BiCGSTAB breakdown");
  return static_cast<int>(solver.iterations());
}

void PpeSolver::prepare_amg(Impl& s, int n, const std::vector<std::int64_t>* ids) {
  if (!s.amg)
    s.amg = std::make_unique<HypreAmg>(amg_settings_);
  // Set-up cost in iterations of this Krylov method (see ppe_solver.hpp).
  const int setup_cost = kind_ == PpeSolverKind::GmresAmg ? 8 : 4;
  const bool due = amg_setup_every_ > 0 ? s.solves_since_setup >= amg_setup_every_
                                        : s.excess >= setup_cost || s.solves_since_setup >= 50;
  bool setup = s.amg->rows() != n || !ids || static_cast<int>(ids->size()) != n || due;
  s.permuted = false;
  if (!setup) {
    // Current row i holds particle ids[i]; perm[i] is that particle's row at set-up.
    s.perm.resize(n);
    bool identity = true;
    for (int i = 0; i < n && !setup; ++i) {
      const std::int64_t id = (*ids)[i];
      const int r = id >= 0 && id < static_cast<std::int64_t>(s.setup_row.size())
                        ? s.setup_row[static_cast<std::size_t>(id)]
                        : -1;
      if (r < 0)
        setup = true; // a particle the set-up did not have
      s.perm[i] = r, identity = identity && r == i;
    }
    s.permuted = !setup && !identity;
  }
  if (setup) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu_seconds();
    s.amg->setup(s.a);
    last_setup_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    setup_s_ += last_setup_s_, ++setups_;
    setup_cpu_s_ += thread_cpu_seconds() - c0;
    s.solves_since_setup = 0, s.excess = 0;
    s.setup_row.clear();
    if (ids) {
      std::int64_t idmax = -1;
      for (std::int64_t id : *ids)
        idmax = std::max(idmax, id);
      s.setup_row.assign(static_cast<std::size_t>(idmax + 1), -1);
      for (int i = 0; i < n; ++i)
        if ((*ids)[i] >= 0)
          s.setup_row[static_cast<std::size_t>((*ids)[i])] = i;
    }
  }
  ++s.solves_since_setup;
  const std::vector<int>* perm = s.permuted ? &s.perm : nullptr;
  s.bicg_amg.preconditioner().attach(s.amg.get(), perm);
  s.amg_precond.attach(s.amg.get(), perm);
}

// Restarted GMRES(m), right-preconditioned (Saad 2003, Algorithm 9.5 with Givens rotations): the
// Arnoldi residual |g_{j+1}| is the residual of b - A x itself, so the stopping rule
// |b - A x| <= tol |b| is BiCGSTAB's. One V-cycle per iteration (BiCGSTAB: two).
int PpeSolver::gmres(Impl& s, const std::vector<double>& x0, int n) {
  constexpr int m = 30;
  warm_start(s.a, s.b, x0, n, s.a1, s.x);
  const double bnorm = s.b.norm();
  if (bnorm == 0.0) {
    s.x.setZero();
    last_error_ = 0.0;
    return 0;
  }
  s.r = s.b - s.a * s.x;
  double beta = s.r.norm();
  int iters = 0;
  s.h.setZero(m + 1, m);
  s.cs.resize(m), s.sn.resize(m), s.g.resize(m + 1);
  while (beta > tol_ * bnorm && iters < max_iter_) {
    if (s.v.size() < 1)
      s.v.emplace_back();
    s.v[0] = s.r / beta;
    s.g.setZero();
    s.g[0] = beta;
    int k = 0;
    for (int j = 0; j < m && iters < max_iter_; ++j) {
      if (static_cast<int>(s.z.size()) <= j)
        s.z.emplace_back();
      if (static_cast<int>(s.v.size()) <= j + 1)
        s.v.emplace_back();
      s.z[j].resize(n);
      s.amg_precond.apply(s.v[j].data(), s.z[j].data());
      s.w = s.a * s.z[j];
      for (int i = 0; i <= j; ++i) { // modified Gram-Schmidt
        s.h(i, j) = s.w.dot(s.v[i]);
        s.w -= s.h(i, j) * s.v[i];
      }
      const double hnext = s.w.norm();
      s.h(j + 1, j) = hnext;
      if (hnext > 0.0)
        s.v[j + 1] = s.w / hnext;
      for (int i = 0; i < j; ++i) { // previous rotations on the new column
        const double t = s.cs[i] * s.h(i, j) + s.sn[i] * s.h(i + 1, j);
        s.h(i + 1, j) = -s.sn[i] * s.h(i, j) + s.cs[i] * s.h(i + 1, j);
        s.h(i, j) = t;
      }
      const double den = std::hypot(s.h(j, j), s.h(j + 1, j));
      if (den == 0.0)
        throw std::runtime_error("PPE: GMRES breakdown");
      s.cs[j] = s.h(j, j) / den, s.sn[j] = s.h(j + 1, j) / den;
      s.h(j, j) = den, s.h(j + 1, j) = 0.0;
      s.g[j + 1] = -s.sn[j] * s.g[j], s.g[j] *= s.cs[j];
      ++iters, k = j + 1;
      if (std::abs(s.g[j + 1]) <= tol_ * bnorm || hnext == 0.0) // converged, or exact
        break;
    }
    // x += Z y, H(0:k, 0:k) y = g(0:k) (upper triangular after the rotations).
    Eigen::VectorXd y = s.h.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(s.g.head(k));
    for (int i = 0; i < k; ++i)
      s.x += y[i] * s.z[i];
    s.r = s.b - s.a * s.x;
    beta = s.r.norm();
  }
  last_error_ = beta / bnorm;
  return iters;
}

std::vector<double> PpeSolver::last_rhs() const {
  return std::vector<double>(impl_->b.data(), impl_->b.data() + impl_->b.size());
}

int PpeSolver::amg_levels() const {
  return impl_->amg ? impl_->amg->levels() : 0;
}
double PpeSolver::amg_operator_complexity() const {
  return impl_->amg ? impl_->amg->operator_complexity() : 0.0;
}

int PpeSolver::solve(const std::vector<double>& b, std::vector<double>& x,
                     const std::vector<std::int64_t>* ids) {
  const double c0 = thread_cpu_seconds();
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
  } else if (kind_ == PpeSolverKind::BicgstabAmg || kind_ == PpeSolverKind::GmresAmg) {
    prepare_amg(s, n, ids);
    iters = kind_ == PpeSolverKind::GmresAmg ? gmres(s, x, n) : iterate(s.bicg_amg, s, x, n);
    if (s.solves_since_setup == 1)
      s.iters_after_setup = iters;
    else
      s.excess += std::max(0, iters - s.iters_after_setup);
  } else {
    iters = iterate(s.jacobi, s, x, n);
  }
  x.resize(n);
  Eigen::Map<Eigen::VectorXd>(x.data(), n) = s.x;
  cpu_s_ += thread_cpu_seconds() - c0;
  return iters;
}

} // namespace sph
