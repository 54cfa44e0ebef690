// Contact SPH (seed 003), terms alone with known answers (issue 15, section 1). Written against
// today's contact::Scheme (schemes/contact/contact.hpp: init, step, stable_dt, eta_num) and the
// pair functions of riemann.hpp; each test sets a state and compares a number, so it ports to the
// Scheme interface of issue 14 by replacing the calls.
//  - the time-step criteria (acoustic cfl D / (c0 + |U|), viscous 0.125 D^2 rho / (eta + zeta
//    eta_num)) by hand;
//  - the equation of state (4) after a step of a uniform compressed state;
//  - eq. (37), the numerical viscosity, at its two branches;
//  - the zeta correction of the contact viscosity: eta_ij - zeta eta_num for equal fluids;
//  - the acoustic Riemann problem (8)-(9) on a pressure jump and a velocity jump, by hand.
#include "core/kernels/wendland_c2.hpp"
#include "core/lattice.hpp"
#include "schemes/contact/contact.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sph;
using namespace sph::contact;

namespace {

// A periodic 2D box of n^2 particles of one material at density rho = s rho0, velocity U.
struct Uniform {
  Particles<2> p;
  Fields f;
  Domain<2> box;
  Options o;
  static constexpr double D0 = 1e-8, rho0 = 1000.0, c0 = 1483.0, eta = 1e-3;
  Uniform(int n, double s, const Vec2& U) {
    f = Fields::add_to(p);
    for_each_lattice_point<2>({0, 0}, {n, n}, D0, [&](const Vec2& x, const std::array<int, 2>&) {
      const std::size_t i = p.add(x, rho0 * s * D0 * D0, s * rho0);
      p.v[i] = U;
      p.scalar(f.rho0)[i] = rho0;
      p.scalar(f.c0)[i] = c0;
      p.scalar(f.eta)[i] = eta;
      p.scalar(f.e)[i] = 1e3;
    });
    box.hi.setConstant(n * D0);
    box.periodic.fill(true);
  }
};

} // namespace

// D = (m / rho)^(1/2) = D0 here. Acoustic: 0.3 D0 / (c0 + |U|); viscous: 0.125 D0^2 rho / (eta +
// zeta eta_num). With |U| = 50, eta = 10 mPa s and eta_num = 2 mPa s given: acoustic 1.957e-12 s,
// viscous 1.25e-12 s (zeta = 0) and 1.04e-12 s (zeta = 1), so the viscous limit is the one that
// acts. Exact (1e-12 relative).
TEST(ContactTerms, TimeStepCriteria) {
  Uniform u(12, 1.0, Vec2(30.0, 40.0));
  const double eta = 1e-2;
  for (std::size_t i = 0; i < u.p.size(); ++i)
    u.p.scalar(u.f.eta)[i] = eta;
  u.o.eta_num = 2e-3;
  const double ac = 0.3 * Uniform::D0 / (Uniform::c0 + 50.0);
  const double vi = 0.125 * Uniform::D0 * Uniform::D0 * Uniform::rho0;
  for (double zeta : {0.0, 1.0}) {
    u.o.zeta = zeta;
    Scheme<2, WendlandC2<2>> s(u.p, u.f, u.box, u.o);
    s.init();
    const double expect = std::min(ac, vi / (eta + zeta * 2e-3));
    EXPECT_LT(expect, ac); // the viscous limit acts
    EXPECT_NEAR(s.stable_dt(), expect, 1e-12 * expect) << zeta;
  }
  // Inviscid: the acoustic limit alone.
  for (std::size_t i = 0; i < u.p.size(); ++i)
    u.p.scalar(u.f.eta)[i] = 0.0;
  u.o.zeta = 0.0;
  Scheme<2, WendlandC2<2>> s(u.p, u.f, u.box, u.o);
  s.init();
  EXPECT_NEAR(s.stable_dt(), ac, 1e-12 * ac);
}

// Eq. (4), P = c0^2 (rho - rho0), on a uniform state compressed by 0.1 %: the state is steady
// (every pair term cancels), so after a step P = c0^2 0.001 rho0 = 2199.3 Pa on every particle.
TEST(ContactTerms, EquationOfStateOnUniformCompressedState) {
  Uniform u(12, 1.001, Vec2(5.0, -3.0));
  Scheme<2, WendlandC2<2>> s(u.p, u.f, u.box, u.o);
  s.init();
  s.step(0.5 * s.stable_dt());
  const double P = Uniform::c0 * Uniform::c0 * 0.001 * Uniform::rho0;
  for (std::size_t i = 0; i < u.p.size(); ++i) {
    ASSERT_NEAR(u.p.p[i], P, 1e-8 * P) << i;
    ASSERT_LT((u.p.v[i] - Vec2(5.0, -3.0)).norm(), 1e-9) << i;
  }
}

// Eq. (37): eta_num = D0 Z (0.47142 alpha - 0.14629) for alpha <= 0.55, D0 Z (0.18093 alpha +
// 0.01347) above, by hand at alpha = 0.5 and 1.
TEST(ContactTerms, NumericalViscosityEq37) {
  const double D0 = 1e-8, Z = 1.5e6;
  EXPECT_NEAR(eta_num_eq37(D0, Z, 0.5), D0 * Z * 0.08942, 1e-12 * D0 * Z);
  EXPECT_NEAR(eta_num_eq37(D0, Z, 1.0), D0 * Z * 0.1944, 1e-12 * D0 * Z);
}

// The contact viscosity with the correction (eq. 26): for two equal fluids eta_ij = eta and the
// numerical side gives zeta eta_num, so the pair stress uses eta - zeta eta_num (the scheme
// subtracts contact_viscosity of the `num` sides from that of the `phys` sides).
TEST(ContactTerms, ZetaCorrectionOfTheContactViscosity) {
  const double eta = 5e-3, eta_num = 1.34e-3, rho = 1000.0;
  for (double zeta : {0.0, 0.5, 1.0}) {
    const auto phys = viscous_side(eta, rho), num = viscous_side(zeta * eta_num, rho);
    EXPECT_NEAR(contact_viscosity(phys, phys) - contact_viscosity(num, num), eta - zeta * eta_num,
                1e-15)
        << zeta;
  }
}

// Eqs. (8)-(9) by hand: equal impedances Z, states at rest with P_i = 3, P_j = 1: P* = 2, U* =
// (P_i - P_j) / (2 Z) along e (from i to j: the contact moves away from the high pressure);
// equal pressures 0 with an approaching pair (U_i^R = 1, U_j^R = -1): P* = Z, U* = 0.
TEST(ContactTerms, AcousticRiemannOnJumps) {
  const double Z = 4.0;
  auto a = acoustic_riemann(3.0, 0.0, Z, 1.0, 0.0, Z);
  EXPECT_NEAR(a.P, 2.0, 1e-15);
  EXPECT_NEAR(a.U, 2.0 / (2 * Z), 1e-15);
  auto b = acoustic_riemann(0.0, 1.0, Z, 0.0, -1.0, Z);
  EXPECT_NEAR(b.P, Z, 1e-15);
  EXPECT_NEAR(b.U, 0.0, 1e-15);
  // Unequal impedances, velocity jump: P* = Zi Zj (uRi - uRj) / (Zi + Zj).
  auto c = acoustic_riemann(0.0, 2.0, 1.0, 0.0, 0.0, 3.0);
  EXPECT_NEAR(c.P, 1.0 * 3.0 * 2.0 / 4.0, 1e-15);
  EXPECT_NEAR(c.U, 2.0 * 1.0 / 4.0, 1e-15);
}
