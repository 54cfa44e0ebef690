// Scheme "alsph" (seed 004), each term alone on a field whose answer is known (issue 15, section
// 1). Written against today's alsph::ops structs and alsph::Scheme::step (schemes/alsph/alsph.hpp);
// each test gives a term its inputs and compares its output, so it ports to the Scheme interface
// of issue 14 by replacing the call.
//  - eq. (8), the penalty term r_AL <grad div u> and the viscous term, on a linear divergence;
//  - eq. (10), the pressure update, on a linear u* and a quadratic p (kernel-corrected operators
//    exact there on the perfect lattice);
//  - eq. (11), the velocity correction, on a linear p on a disordered lattice;
//  - eq. (20), the body pressure, on a pressure linear along the normal;
//  - r_AL = C_BV u_max^2 dt of one step.
#include "core/kernels/quintic_spline.hpp"
#include "operators/correction_matrix.hpp"
#include "padded_lattice.hpp"
#include "schemes/alsph/alsph.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sph;
using sph::testing::PaddedLattice;

namespace {

using Lat = PaddedLattice<QuinticSpline<2>>;

// Gamma on every particle and the pair coefficients the ops of eqs. 8-11 read (eta = 0).
alsph::ops::PairCoefficients<2> coefficients(const Lat& L) {
  std::vector<Mat<2>> gamma(L.p.size());
  std::vector<double> tr(L.p.size());
  CorrectionMatrix<2> cm{L.p.V, gamma, tr};
  interact(L.nl, cm);
  alsph::ops::PairCoefficients<2> c;
  c.compute(L.nl, L.p.V, gamma, 0.0);
  return c;
}

} // namespace

// Eq. (8): u* = u^n + dt (r_AL <grad div u> + nu <lap u> + g). With <div u> = c . x + d given, the
// corrected gradient gives <grad div u> = c exactly (any lattice): u* = u^n + dt (r_AL c + nu lap
// + g) to round-off; a body particle gets u* = 0 and the pseudo-acceleration a_s = r_AL c + nu lap.
TEST(AlsphTerms, PredictPenaltyAndViscousTerms) {
  Lat L(16, 1.0, 0.5, 3);
  const auto coef = coefficients(L);
  const std::size_t N = L.p.size();
  const Vec2 c(0.8, -1.5), g(0.0, -0.3);
  std::vector<double> div(N);
  std::vector<Vec2> lap(N), un(N), us(N, Vec2::Zero()), as(N, Vec2::Zero());
  for (std::size_t i = 0; i < N; ++i) {
    div[i] = 0.4 + c.dot(L.p.r[i]);
    lap[i] = Vec2(0.1 * static_cast<double>(i % 7), -0.2);
    un[i] = Vec2(0.5, 0.25);
  }
  std::size_t body = 0;
  while (!L.fluid(body))
    ++body;
  L.p.kind[body] = Kind::Body;
  const double r_al = 0.4, nu = 0.01, dt = 1e-3;
  alsph::ops::Predict<2> op{coef, div, lap, un, L.p.kind, r_al, nu, dt, g, us, as};
  interact_indexed(L.nl, op, [&](std::size_t i) { return L.p.kind[i] != Kind::Buffer; });
  for (std::size_t i = 0; i < N; ++i) {
    if (L.p.kind[i] == Kind::Fluid)
      ASSERT_LT((us[i] - (un[i] + dt * (r_al * c + nu * lap[i] + g))).norm(), 1e-12) << i;
  }
  EXPECT_LT(us[body].norm(), 1e-15);
  EXPECT_LT((as[body] - (r_al * c + nu * lap[body])).norm(), 1e-10);
}

// Eq. (10): p^{m+1} = p^m - r_AL rho (<div u*> - dt / rho <lap p^m>). On the perfect lattice the
// kernel-corrected divergence is exact for u* = A x + b and the corrected Laplacian (eta = 0) for
// p = 1/2 x^T H x (test_operators: VISC-04 is exact for quadratics there), so
// p_new = p - r_AL rho (tr A - dt / rho tr H) to round-off (1e-9 relative).
TEST(AlsphTerms, PressureUpdateOnLinearVelocityAndQuadraticPressure) {
  Lat L(16, 1.0);
  const auto coef = coefficients(L);
  const std::size_t N = L.p.size();
  Mat<2> A, H;
  A << 0.3, -1.2, 0.7, 0.5;
  H << 2.0, 0.5, 0.5, -6.0;
  std::vector<Vec2> us(N);
  std::vector<double> p(N), pn(N), ds(N);
  for (std::size_t i = 0; i < N; ++i) {
    const Vec2 x = L.p.r[i];
    us[i] = A * x + Vec2(1.0, 2.0);
    p[i] = 0.5 * x.dot(H * x) + 3.0;
  }
  const double r_al = 0.4, rho = 2.0, dt = 1e-2;
  alsph::ops::PressureUpdate<2> op{coef, us, p, r_al, rho, dt, pn, ds};
  interact_indexed(L.nl, op, L.sampled());
  for (std::size_t i = 0; i < N; ++i)
    if (L.fluid(i)) {
      ASSERT_NEAR(ds[i], A.trace(), 1e-10) << i;
      const double expect = p[i] - r_al * rho * (A.trace() - dt / rho * H.trace());
      ASSERT_NEAR(pn[i], expect, 1e-9 * std::abs(expect)) << i;
    }
}

// Eq. (11): u = u* - dt / rho <grad p>, exact for a linear p on a disordered lattice.
TEST(AlsphTerms, CorrectionOnLinearPressure) {
  Lat L(16, 1.0, 0.6, 9);
  const auto coef = coefficients(L);
  const std::size_t N = L.p.size();
  const Vec2 G(2.0, -3.0);
  std::vector<double> p(N);
  std::vector<Vec2> us(N, Vec2(0.2, 0.1)), gp(N), u(N);
  for (std::size_t i = 0; i < N; ++i)
    p[i] = 1.0 + G.dot(L.p.r[i]);
  alsph::ops::Correct<2> op{coef, p, us, 0.01 / 2.0, gp, u};
  interact_indexed(L.nl, op, L.sampled());
  for (std::size_t i = 0; i < N; ++i)
    if (L.fluid(i)) {
      ASSERT_LT((gp[i] - G).norm(), 1e-10) << i;
      ASSERT_LT((u[i] - (Vec2(0.2, 0.1) - 0.005 * G)).norm(), 1e-12) << i;
    }
}

// Eq. (20): p_s = sum_j W_sj (p_j + dp/dn (r_s - r_j) . n) / sum_j W_sj, dp/dn = rho a_s . n. For
// a pressure linear along n, p = p0 + G n . x with rho a_s . n = G, every term is p(r_s): exact.
TEST(AlsphTerms, BodyPressureExtrapolatesAlongTheNormal) {
  Lat L(16, 1.0, 0.5, 4);
  const std::size_t N = L.p.size();
  const Vec2 n = Vec2(0.6, 0.8);
  const double G = 3.0, rho = 2.0;
  std::size_t s = 0;
  while ((L.p.r[s] - Vec2(0.5, 0.5)).norm() > 0.1 || !L.fluid(s))
    ++s;
  L.p.kind[s] = Kind::Body;
  std::vector<Vec2> a_s(N, Vec2::Zero()), normal(N, Vec2::Zero());
  a_s[s] = (G / rho) * n + Vec2(-0.8, 0.6); // the tangential part must not matter
  normal[s] = n;
  for (std::size_t i = 0; i < N; ++i)
    L.p.p[i] = 1.5 + G * n.dot(L.p.r[i]);
  const double expect = L.p.p[s];
  L.p.p[s] = -100.0;
  alsph::ops::BodyPressure<2> op{L.p.kind, a_s, normal, rho, L.p.p};
  interact(L.nl, op, [&](std::size_t i) { return i == s; });
  EXPECT_NEAR(L.p.p[s], expect, 1e-12);
}

// r_AL = C_BV u_max^2 dt (after eq. 8) of a step on a periodic lattice moving at |u| = 2 (a
// uniform translation: no divergence, so the step converges at once and keeps the velocity).
TEST(AlsphTerms, PenaltyCoefficientOfAStep) {
  const int n = 16;
  const double dx = 1.0 / n;
  Particles<2> p;
  for_each_lattice_point<2>({0, 0}, {n, n}, dx, [&](const Vec2& x, const std::array<int, 2>&) {
    p.add(x, dx * dx, 1.0);
  });
  for (auto& v : p.v)
    v = Vec2(1.2, 1.6);
  QuinticSpline<2> W(dx);
  Domain<2> box;
  box.periodic = {true, true};
  CellList<2> cells(box, W.support());
  cells.build(p);
  NeighborList<2> nl;
  nl.build(cells, p.r, W);
  alsph::Settings s;
  s.c_bv = 100.0, s.dt = 1e-3, s.shifting = false;
  alsph::Scheme<2, QuinticSpline<2>> sc(W, s);
  MirrorGhosts<2> ghosts;
  std::vector<Vec2> normal(p.size(), Vec2::Zero());
  const auto st = sc.step(p, nl, ghosts, normal, [](auto&, auto&) {});
  EXPECT_NEAR(st.r_al, 100.0 * 4.0 * 1e-3, 1e-13);
  EXPECT_NEAR(st.u_max, 2.0, 1e-14);
  for (const auto& v : p.v)
    ASSERT_LT((v - Vec2(1.2, 1.6)).norm(), 1e-10);
}
