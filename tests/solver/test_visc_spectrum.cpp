// The spectrum of the viscous Laplacians as matrices (seed 001, Zheng, Ma & Shao 2018, Applied
// Sciences 8, 249, section 3): why VISC-02 makes the explicit viscous step of ISPH (eqs. 7-8,
// u* = u + nu dt lap u) unstable on disordered particles, and which set-up choices do not.
//
// Each operator is linear in u: its matrix L (sampled particles of a padded lattice; the buffer
// particles hold u = 0, so L is the interior block, a principal submatrix of the operator on the
// whole set) is assembled column by column by applying the operator itself to unit vectors. With
// V_j = dx^2 for every particle the pair forms are symmetric, L = L^T. The explicit step multiplies
// the component of u along an eigenvector of eigenvalue lambda by 1 + nu dt lambda, so a positive
// lambda grows like exp(nu lambda t) whatever dt: a growth rate proportional to nu / dx^2, as the
// divergence times of the cavity runs show (t_div nu / dx^2 about 2.4-4 at every dx; docs/isph.md).
//
// VISC-02 (eq. 16 read as sum_j V_j (u_j - u_i) lap W_ij, lap W = W'' + (D - 1) W'/r): for the
// cubic spline lap W < 0 for q = r/h < 0.889, and it is -6 sigma / h^2 at q -> 0, so two particles
// closer than 0.889 h are coupled with a negative (anti-diffusive) weight. On the perfect lattice
// at h = 1.2 dx the negative nearest-neighbour weights (q = 0.833) are balanced by the rest of the
// stencil (largest eigenvalue of the interior block below 0); on a disordered lattice the close
// pairs make the largest eigenvalue positive. The printed weight of eq. (16), W'' - W'/r (visc02p,
// sign and factor made consistent), is positive at every q, so its L is a weighted graph Laplacian:
// non-positive on any arrangement.
#include "core/kernels/kernel.hpp"
#include "operators/viscous_laplacian.hpp"
#include "padded_lattice.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

using namespace sph;
using sph::testing::PaddedLattice;

namespace {

// The interior block of the operator `form` on lattice L, times dx^2 (dimensionless).
template <class K>
Eigen::MatrixXd operator_matrix(PaddedLattice<K>& L, ViscForm form) {
  std::vector<std::size_t> in;
  for (std::size_t i = 0; i < L.p.size(); ++i)
    if (L.fluid(i))
      in.push_back(i);
  const auto n = static_cast<Eigen::Index>(in.size());
  Eigen::MatrixXd M(n, n);
  ViscousLaplacian<2, double, K> lap(form, L.kernel, 0.0);
  lap.prepare(L.nl, L.p.V, L.sampled());
  std::vector<double> u(L.p.size(), 0.0), out;
  for (Eigen::Index c = 0; c < n; ++c) {
    u[in[c]] = 1.0;
    lap.apply(L.nl, L.p.V, u, out, L.sampled());
    for (Eigen::Index r = 0; r < n; ++r)
      M(r, c) = out[in[r]] * L.dx * L.dx;
    u[in[c]] = 0.0;
  }
  return M;
}

struct Spectrum {
  double lmax, lmin;
};

template <class K>
Spectrum spectrum(int n, double h_over_dx, double disorder, std::uint64_t seed, ViscForm form) {
  PaddedLattice<K> L(n, h_over_dx, disorder, seed);
  const Eigen::MatrixXd M = operator_matrix(L, form);
  // Symmetric up to round-off (V_j = dx^2 everywhere, pair weights symmetric in i, j).
  EXPECT_LT((M - M.transpose()).cwiseAbs().maxCoeff(), 1e-12 * M.cwiseAbs().maxCoeff());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (M + M.transpose()),
                                                    Eigen::EigenvaluesOnly);
  const auto& ev = es.eigenvalues();
  return {ev(ev.size() - 1), ev(0)};
}

constexpr int n_side = 16; // 256 sampled particles, 576 with the padding at h = 1.2 dx
constexpr double disorder = 0.5;

} // namespace

// VISC-02 with the cubic spline at h = 1.2 dx: non-positive on the perfect lattice, anti-diffusive
// (largest eigenvalue lambda dx^2 > 0.2) once the particles are disordered by +-0.25 dx.
// A sign error in the pair (u_i - u_j) makes the lattice operator positive (lambda dx^2 ~ +1.6).
TEST(ViscSpectrum, Visc02CubicIsAntiDiffusiveOnDisorderedParticles) {
  const auto lattice = spectrum<CubicSpline<2>>(n_side, 1.2, 0.0, 1, ViscForm::Visc02);
  EXPECT_LT(lattice.lmax, 0.0);
  EXPECT_LT(lattice.lmin, -1.0); // a Laplacian, not the zero matrix
  for (std::uint64_t seed : {1, 2, 3}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto dis = spectrum<CubicSpline<2>>(n_side, 1.2, disorder, seed, ViscForm::Visc02);
    EXPECT_GT(dis.lmax, 0.2);
  }
}

// The printed weight of eq. (16), W'' - W'/r > 0: every pair weight positive, so the operator is
// negative definite on the interior block on the lattice and on the disordered particles alike.
// With the sign of the printed (u_i - u_j) kept the operator would be positive definite.
TEST(ViscSpectrum, Visc02PrintedWeightIsDiffusiveOnAnyArrangement) {
  for (double a : {0.0, disorder, 1.0}) {
    SCOPED_TRACE("disorder " + std::to_string(a));
    const auto s = spectrum<CubicSpline<2>>(n_side, 1.2, a, 1, ViscForm::Visc02Printed);
    EXPECT_LT(s.lmax, 0.0);
    EXPECT_LT(s.lmin, -1.0);
  }
}

// Neither a longer smoothing length nor a smoother kernel makes VISC-02 non-positive on the
// disordered particles (+-0.25 dx): lap W is negative near q = 0 for every bell-shaped kernel (it
// is the kernel's curvature at its peak). The values are printed for docs/isph.md, where they
// stand beside the cavity's divergence times for the same set-ups (studies/isph_stability.toml).
TEST(ViscSpectrum, Visc02StaysAntiDiffusiveForEveryKernelAndSmoothingLength) {
  auto report = [](const char* what, const Spectrum& s) {
    std::printf("VISC-02 %-22s disorder 0.5: lambda_max dx^2 = %+.3f (lambda_min dx^2 = %.2f)\n",
                what, s.lmax, s.lmin);
    EXPECT_GT(s.lmax, 0.05) << what;
  };
  report("cubic, h = 1.2 dx", spectrum<CubicSpline<2>>(n_side, 1.2, disorder, 1, ViscForm::Visc02));
  report("cubic, h = 1.5 dx", spectrum<CubicSpline<2>>(n_side, 1.5, disorder, 1, ViscForm::Visc02));
  report("cubic, h = 2.0 dx", spectrum<CubicSpline<2>>(n_side, 2.0, disorder, 1, ViscForm::Visc02));
  report("wendland_c2, h = 1.2 dx",
         spectrum<WendlandC2<2>>(n_side, 1.2, disorder, 1, ViscForm::Visc02));
  report("quintic, h = 1.0 dx",
         spectrum<QuinticSpline<2>>(n_side, 1.0, disorder, 1, ViscForm::Visc02));
}
