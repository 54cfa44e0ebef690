// Newton solve of the streamfunction-vorticity cavity (the equations and their discretisation:
// cavity_fd.hpp). Unknowns interleaved per node, x = [psi_0, omega_0, psi_1, omega_1, ...]; the
// interior equations multiplied by h^2:
//   R_psi   = psi_E + psi_W + psi_N + psi_S - 4 psi_P + h^2 omega_P
//   R_omega = (psi_N - psi_S)(omega_E - omega_W) / 4 - (psi_E - psi_W)(omega_N - omega_S) / 4
//             - (omega_E + omega_W + omega_N + omega_S - 4 omega_P) / Re
// walls: R_psi = psi_P; R_omega = omega_P + 2 (psi_1 + h U_w) / h^2 (Thom), corners omega_P.
// The Jacobian is assembled exactly and factorised by Eigen's SparseLU at every iteration.
#include "cavity_fd.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sph {

namespace {

struct Grid {
  int N;
  int n1() const { return N + 1; }
  int node(int i, int j) const { return i + n1() * j; }
  int psi(int i, int j) const { return 2 * node(i, j); }
  int omega(int i, int j) const { return 2 * node(i, j) + 1; }
};

// Residual R(x) and, if J is given, its Jacobian.
void equations(const Grid& g, double Re, const Eigen::VectorXd& x, Eigen::VectorXd& R,
               Eigen::SparseMatrix<double>* J) {
  const int N = g.N;
  const double h = 1.0 / N, U = 1.0;
  std::vector<Eigen::Triplet<double>> t;
  if (J)
    t.reserve(static_cast<std::size_t>(g.n1()) * g.n1() * 16);
  R.setZero(x.size());
  auto P = [&](int i, int j) { return x[g.psi(i, j)]; };
  auto W = [&](int i, int j) { return x[g.omega(i, j)]; };
  for (int j = 0; j <= N; ++j)
    for (int i = 0; i <= N; ++i) {
      const int rp = g.psi(i, j), rw = g.omega(i, j);
      const bool wall = i == 0 || j == 0 || i == N || j == N;
      if (wall) {
        R[rp] = P(i, j);
        R[rw] = W(i, j);
        if (J)
          t.emplace_back(rp, rp, 1.0), t.emplace_back(rw, rw, 1.0);
        const bool corner = (i == 0 || i == N) && (j == 0 || j == N);
        if (corner)
          continue;
        // Thom: the first interior node along the wall normal, and the wall's tangential speed.
        int ii = i, jj = j;
        double Uw = 0.0;
        if (j == 0)
          jj = 1;
        else if (j == N)
          jj = N - 1, Uw = U;
        else if (i == 0)
          ii = 1;
        else
          ii = N - 1;
        R[rw] += 2.0 * (P(ii, jj) + h * Uw) / (h * h);
        if (J)
          t.emplace_back(rw, g.psi(ii, jj), 2.0 / (h * h));
        continue;
      }
      const double pE = P(i + 1, j), pW = P(i - 1, j), pN = P(i, j + 1), pS = P(i, j - 1);
      const double wE = W(i + 1, j), wW = W(i - 1, j), wN = W(i, j + 1), wS = W(i, j - 1);
      R[rp] = pE + pW + pN + pS - 4.0 * P(i, j) + h * h * W(i, j);
      R[rw] = 0.25 * (pN - pS) * (wE - wW) - 0.25 * (pE - pW) * (wN - wS) -
              (wE + wW + wN + wS - 4.0 * W(i, j)) / Re;
      if (!J)
        continue;
      t.emplace_back(rp, g.psi(i + 1, j), 1.0), t.emplace_back(rp, g.psi(i - 1, j), 1.0);
      t.emplace_back(rp, g.psi(i, j + 1), 1.0), t.emplace_back(rp, g.psi(i, j - 1), 1.0);
      t.emplace_back(rp, g.psi(i, j), -4.0), t.emplace_back(rp, g.omega(i, j), h * h);
      t.emplace_back(rw, g.psi(i, j + 1), 0.25 * (wE - wW));
      t.emplace_back(rw, g.psi(i, j - 1), -0.25 * (wE - wW));
      t.emplace_back(rw, g.psi(i + 1, j), -0.25 * (wN - wS));
      t.emplace_back(rw, g.psi(i - 1, j), 0.25 * (wN - wS));
      t.emplace_back(rw, g.omega(i + 1, j), 0.25 * (pN - pS) - 1.0 / Re);
      t.emplace_back(rw, g.omega(i - 1, j), -0.25 * (pN - pS) - 1.0 / Re);
      t.emplace_back(rw, g.omega(i, j + 1), -0.25 * (pE - pW) - 1.0 / Re);
      t.emplace_back(rw, g.omega(i, j - 1), 0.25 * (pE - pW) - 1.0 / Re);
      t.emplace_back(rw, g.omega(i, j), 4.0 / Re);
    }
  if (J) {
    J->resize(x.size(), x.size());
    J->setFromTriplets(t.begin(), t.end());
  }
}

} // namespace

CavityFdSolution cavity_fd_solve(double Re, int N, double tol, int max_iterations) {
  if (N < 4 || N % 2 != 0)
    throw std::invalid_argument("cavity_fd_solve: N must be even and at least 4, got " +
                                std::to_string(N));
  if (!(Re > 0.0))
    throw std::invalid_argument("cavity_fd_solve: Re must be positive");
  const Grid g{N};
  const int n = 2 * g.n1() * g.n1();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n), R;
  Eigen::SparseMatrix<double> J;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
  CavityFdSolution s;
  s.N = N, s.Re = Re;
  // Newton from rest converges up to about Re = 100; above, continuation in Re: each solution
  // (Re doubled from 100) starts the next.
  bool analysed = false;
  for (double Re_k = std::min(Re, 100.0);; Re_k = std::min(Re, 2.0 * Re_k)) {
    for (int it = 0;; ++it) {
      equations(g, Re_k, x, R, &J);
      s.residual = R.lpNorm<Eigen::Infinity>();
      // The Thom rows carry 1 / h^2: their residual is compared at the interior rows' scale.
      if (it > 0 && s.residual / (N * N) < tol)
        break;
      if (it == max_iterations)
        throw std::runtime_error("cavity_fd_solve: Newton did not converge in " +
                                 std::to_string(max_iterations) +
                                 " iterations at Re = " + std::to_string(Re_k) + " (residual " +
                                 std::to_string(s.residual) + ")");
      if (!analysed)
        lu.analyzePattern(J), analysed = true;
      lu.factorize(J);
      if (lu.info() != Eigen::Success)
        throw std::runtime_error("cavity_fd_solve: the Jacobian could not be factorised");
      x -= lu.solve(R);
      ++s.newton_iterations;
    }
    if (Re_k == Re)
      break;
  }
  s.psi.resize(g.n1() * g.n1());
  for (int k = 0; k < g.n1() * g.n1(); ++k)
    s.psi[k] = x[2 * k];
  return s;
}

double CavityFdSolution::u_centre(int j) const {
  if (j <= 0)
    return 0.0;
  if (j >= N)
    return 1.0;
  const int i = N / 2, n1 = N + 1;
  return (psi[i + n1 * (j + 1)] - psi[i + n1 * (j - 1)]) * N / 2.0;
}

double CavityFdSolution::v_centre(int i) const {
  if (i <= 0 || i >= N)
    return 0.0;
  const int j = N / 2, n1 = N + 1;
  return -(psi[i + 1 + n1 * j] - psi[i - 1 + n1 * j]) * N / 2.0;
}

namespace {
int node_of(double c, int N) {
  // Within 6e-5 of a node: Ghia et al. print their grid's coordinates to four decimals.
  const long r = std::lround(c * N);
  if (std::abs(c - static_cast<double>(r) / N) > 6e-5 || r < 0 || r > N)
    throw std::invalid_argument("cavity_fd: " + std::to_string(c) + " is not a node of the " +
                                std::to_string(N) + "-cell grid");
  return static_cast<int>(r);
}
} // namespace

double CavityFdSolution::u_at_y(double y) const {
  return u_centre(node_of(y, N));
}
double CavityFdSolution::v_at_x(double x) const {
  return v_centre(node_of(x, N));
}

} // namespace sph
