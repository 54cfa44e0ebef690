// Tests of scheme "contact" (seed 003, Parshikov et al.), the shear-layer fit and case.
#include "case_helpers.hpp"
#include "cases/case.hpp"
#include "core/kernels/cubic_spline.hpp"
#include "core/kernels/wendland_c2.hpp"
#include "core/lattice.hpp"
#include "diagnostics/erf_fit.hpp"
#include "diagnostics/gravity_current.hpp"
#include "schemes/contact/contact.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

using namespace sph;
using sph::testing::metric;
using namespace sph::contact;

// Eqs. (8)-(9): equal states exchange nothing; a symmetric collision stops at the contact with
// P* = Z u (the acoustic impedance times the approach speed).
TEST(ContactRiemann, EqualStatesGiveTheirOwnState) {
  const auto s = acoustic_riemann(3.0e5, 12.0, 2.2e7, 3.0e5, 12.0, 2.2e7);
  EXPECT_DOUBLE_EQ(s.P, 3.0e5);
  EXPECT_DOUBLE_EQ(s.U, 12.0);
}

TEST(ContactRiemann, SymmetricCollision) {
  const double Z = 11350.0 * 1931.7, u = 40.0;
  const auto s = acoustic_riemann(0.0, u, Z, 0.0, -u, Z);
  EXPECT_NEAR(s.P, Z * u, 1e-9 * Z * u);
  EXPECT_NEAR(s.U, 0.0, 1e-12);
  // Separation gives tension of the same size.
  EXPECT_NEAR(acoustic_riemann(0.0, -u, Z, 0.0, u, Z).P, -Z * u, 1e-9 * Z * u);
  // A rigid (infinite-impedance) partner: the contact does not move, P* = P_i + Z_i u_i.
  const auto w = acoustic_riemann(1.0e5, u, Z, 0.0, 0.0, 1e12 * Z);
  EXPECT_NEAR(w.U, 0.0, 1e-9 * u);
  EXPECT_NEAR(w.P, 1.0e5 + Z * u, 1e-6 * Z * u);
}

TEST(ContactRiemann, ViscousContact) {
  // Eqs. (27), (30)-(32): two equal fluids have eta_ij = eta and U* = mean; an inviscid partner
  // transmits no shear.
  const auto a = viscous_side(2.3e-3, 11350.0);
  EXPECT_NEAR(contact_viscosity(a, a), 2.3e-3, 1e-15);
  EXPECT_DOUBLE_EQ(contact_weight(a, a, 1.0, 2.0), 0.5);
  EXPECT_EQ(contact_viscosity(a, viscous_side(0.0, 1000.0)), 0.0);
  // Against the paper's form eta_i eta_j (1 + s) / (eta_i + eta_j s), s = sqrt(nu_i / nu_j).
  const double ei = 0.08, ri = 910.0, ej = 1.48, rj = 1250.0;
  const double s = std::sqrt((ei / ri) / (ej / rj));
  const auto I = viscous_side(ei, ri), J = viscous_side(ej, rj);
  EXPECT_NEAR(contact_viscosity(I, J), ei * ej * (1 + s) / (ei + ej * s), 1e-14);
  EXPECT_NEAR(contact_weight(I, J, 1, 1), ei / (ei + ej * s), 1e-14);
}

namespace {

// A periodic box of n^D particles of two materials with perturbed density and velocity.
template <int D, class K>
struct Box {
  Particles<D> p;
  Fields f;
  Domain<D> box;
  Options o;
  double D0 = 1e-8;

  explicit Box(int n, double zeta, bool uniform) {
    f = Fields::add_to(p);
    std::array<int, D> lo{}, hi{};
    hi.fill(n);
    UniformRandom rn(7);
    for_each_lattice_point<D>(lo, hi, D0, [&](Vec<D> x, const std::array<int, D>& idx) {
      const bool heavy = !uniform && idx[0] < n / 2;
      const double rho0 = heavy ? 11350.0 : 1000.0, c0 = heavy ? 1931.7 : 1483.0;
      const double eta = heavy ? 2.3e-3 : 1.0e-3;
      const double rho = uniform ? rho0 : rho0 * (1.0 + 0.01 * (rn() - 0.5));
      const std::size_t i = p.add(x, rho0 * std::pow(D0, D), rho);
      for (int a = 0; a < D; ++a)
        p.v[i][a] = uniform ? 30.0 * (a + 1) : 50.0 * (rn() - 0.5);
      p.scalar(f.rho0)[i] = rho0;
      p.scalar(f.c0)[i] = c0;
      p.scalar(f.eta)[i] = eta;
      p.scalar(f.e)[i] = 1.0e3;
    });
    box.lo.setZero();
    box.hi.setConstant(n * D0);
    box.periodic.fill(true);
    o.zeta = zeta;
  }
  Vec<D> momentum() const {
    Vec<D> P = Vec<D>::Zero();
    for (std::size_t i = 0; i < p.size(); ++i)
      P += p.m[i] * p.v[i];
    return P;
  }
  double energy() const {
    double E = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
      E += p.m[i] * (p.scalar(f.e)[i] + 0.5 * p.v[i].squaredNorm());
    return E;
  }
};

template <int D, class K>
void check_conservation(int n, int steps) {
  Box<D, K> b(n, 0.7, false);
  Scheme<D, K> s(b.p, b.f, b.box, b.o);
  s.init();
  double mass = 0.0, pscale = 0.0;
  for (std::size_t i = 0; i < b.p.size(); ++i)
    mass += b.p.m[i], pscale += b.p.m[i] * b.p.v[i].norm();
  const Vec<D> P0 = b.momentum();
  const double E0 = b.energy();
  double max_dv = 0.0;
  const Vec<D> v_first = b.p.v[0];
  for (int k = 0; k < steps; ++k)
    s.step(s.stable_dt());
  for (std::size_t i = 0; i < b.p.size(); ++i)
    max_dv = std::max(max_dv, (b.p.v[i] - v_first).norm());
  double mass1 = 0.0;
  for (std::size_t i = 0; i < b.p.size(); ++i)
    mass1 += b.p.m[i];
  EXPECT_NEAR(mass1 / mass, 1.0, 1e-14); // m is constant; only the summation order changes
  EXPECT_LT((b.momentum() - P0).norm() / pscale, 1e-14);
  EXPECT_LT(std::abs(b.energy() - E0) / E0, 1e-14);
  EXPECT_GT(max_dv, 1.0); // the state did evolve
}

} // namespace

TEST(ContactScheme, ConservesMomentumAndEnergy2D) {
  check_conservation<2, WendlandC2<2>>(12, 30);
  check_conservation<2, CubicSpline<2>>(12, 30);
}

TEST(ContactScheme, ConservesMomentumAndEnergy3D) {
  check_conservation<3, WendlandC2<3>>(8, 10);
}

// The per-particle factor on zeta (field "zeta_factor", the falling ball's ball particles): a
// factor of 1 everywhere changes nothing, a factor of 0 everywhere is zeta = 0, to the bit; a
// factor of 0 on half the particles lies between (the two-material box, zeta = 0.7, 3 steps).
TEST(ContactScheme, ZetaFactorScalesTheCorrectionPerParticle) {
  auto run = [](double zeta, int factor_mode) {
    Box<2, WendlandC2<2>> b(12, zeta, false);
    if (factor_mode >= 0) {
      const int zf = b.p.add_scalar("zeta_factor");
      for (std::size_t i = 0; i < b.p.size(); ++i)
        b.p.scalar(zf)[i] = factor_mode == 2 ? (b.p.r[i][0] < 6e-8 ? 0.0 : 1.0) : factor_mode;
      b.f = Fields::find_in(b.p);
    }
    Scheme<2, WendlandC2<2>> s(b.p, b.f, b.box, b.o);
    s.init();
    for (int k = 0; k < 3; ++k)
      s.step(2e-13);
    std::vector<double> out;
    for (std::size_t i = 0; i < b.p.size(); ++i)
      out.push_back(b.p.v[i][0]), out.push_back(b.p.v[i][1]);
    return out;
  };
  const auto plain = run(0.7, -1), ones = run(0.7, 1), zeros = run(0.7, 0), off = run(0.0, -1);
  const auto half = run(0.7, 2);
  EXPECT_EQ(plain, ones);
  EXPECT_EQ(zeros, off);
  double d_on = 0.0, d_half_on = 0.0, d_half_off = 0.0;
  for (std::size_t k = 0; k < plain.size(); ++k) {
    d_on += std::abs(plain[k] - off[k]);
    d_half_on += std::abs(half[k] - plain[k]);
    d_half_off += std::abs(half[k] - off[k]);
  }
  EXPECT_GT(d_on, 0.0);
  EXPECT_GT(d_half_on, 0.1 * d_on);
  EXPECT_GT(d_half_off, 0.1 * d_on);
}

// Equal states on a uniform periodic lattice: no flux, nothing changes but the positions.
TEST(ContactScheme, UniformStateIsSteady) {
  Box<3, WendlandC2<3>> b(8, 1.0, true);
  Scheme<3, WendlandC2<3>> s(b.p, b.f, b.box, b.o);
  s.init();
  const Vec<3> v0 = b.p.v[0];
  for (int k = 0; k < 5; ++k)
    s.step(s.stable_dt());
  for (std::size_t i = 0; i < b.p.size(); ++i) {
    EXPECT_LT((b.p.v[i] - v0).norm(), 1e-9 * v0.norm());
    EXPECT_NEAR(b.p.rho[i], 1000.0, 1e-9);
  }
}

// The fit recovers nu exactly from the model's own profile: one fluid with wall images (also
// once the layer has reached the walls), and two fluids.
TEST(ErfFit, RecoversKnownViscosity) {
  const double L = 400e-9, t = 4e-9;
  for (double nu : {1.7e-6, 2.0e-7, 3.0e-5}) {
    ShearLayer s{500.0, L, 3};
    std::vector<double> x, u;
    for (int k = 0; k < 80; ++k) {
      x.push_back(-L + (k + 0.5) * 10e-9);
      u.push_back(shear_layer_u(s, x.back(), t, nu));
    }
    const ErfFit f = fit_shear_layer(s, x, u, t);
    EXPECT_TRUE(f.converged);
    EXPECT_NEAR(f.nu / nu, 1.0, 1e-9) << nu;
    EXPECT_LT(f.rms, 1e-10);
  }
  ShearLayer s2{1.0, 0.0, 0};
  std::vector<double> x, u;
  const double nul = 0.08 / 910.0, nur = 1.48 / 1250.0, t2 = 2e-6;
  for (int k = 0; k < 60; ++k) {
    x.push_back(-300e-6 + (k + 0.5) * 10e-6);
    u.push_back(shear_layer_u2(s2, x.back(), t2, nul, 910.0, nur, 1250.0));
  }
  const ErfFit f = fit_shear_layer2(s2, x, u, t2, 910.0, 1250.0);
  EXPECT_NEAR(f.nu_left / nul, 1.0, 1e-8);
  EXPECT_NEAR(f.nu_right / nur, 1.0, 1e-8);
}

TEST(ErfFit, ImagesMakeSlipWalls) {
  // du/dx = 0 at the walls and the mean velocity (momentum) is zero for all times.
  ShearLayer s{1.0, 1.0, 4};
  const double nu = 0.3, t = 1.0, h = 1e-6;
  EXPECT_NEAR((shear_layer_u(s, 1.0 + h, t, nu) - shear_layer_u(s, 1.0 - h, t, nu)) / (2 * h), 0.0,
              1e-6);
  EXPECT_NEAR(shear_layer_u(s, 0.3, t, nu), -shear_layer_u(s, -0.3, t, nu), 1e-15);
}

namespace {
Params shear_params() {
  const CaseInfo* c = find_case("shear_layer");
  Params prm;
  for (const auto& s : c->params)
    prm[s.name] = s.default_value;
  for (const auto& s : find_scheme("contact")->params)
    prm[s.name] = s.default_value;
  return prm;
}
} // namespace

// A short 2D shear layer of a liquid whose physical viscosity (5 mPa s) is about 4 times the
// scheme's numerical one (eq. 37: 1.34 mPa s at D0 = 10 nm, Z = 1.5e6): with zeta = 1 the fitted
// viscosity must be the physical one. Tolerance 12%: the pair stresses (30)-(32) sum to
// eta (1 + 1/(3(d+2))) times the Laplacian for a shear flow, +8.3% in 2D (docs/contact.md), and
// eq. (37), fitted by the paper to its 3D runs, leaves about +-0.1 eta_num = +-3% of eta
// uncorrected in 2D; measured: +6.6%. Without the correction (zeta = 0) the same run gives +34%,
// so the bound separates the two.
TEST(ShearLayerCase, CorrectionRecoversPhysicalViscosity) {
  Params prm = shear_params();
  prm["dim"] = std::int64_t{2};
  prm["material"] = std::string("custom");
  prm["rho0"] = 1000.0, prm["c0"] = 1500.0, prm["eta"] = 5e-3;
  prm["U0"] = 100.0, prm["D0"] = 1e-8, prm["t_end"] = 3.2e-10;
  prm["nx"] = std::int64_t{40}, prm["ny"] = std::int64_t{8};
  RunContext ctx;
  prm["zeta"] = 1.0;
  const RunResult on = find_case("shear_layer")->run(prm, ctx);
  ASSERT_EQ(on.status, RunStatus::Done) << on.message;
  EXPECT_NEAR(metric(on, "eta_fit") / 5e-3, 1.0, 0.12);
  EXPECT_LT(metric(on, "eta_fit_spread"), 0.05);
  prm["zeta"] = 0.0;
  const RunResult off = find_case("shear_layer")->run(prm, ctx);
  ASSERT_EQ(off.status, RunStatus::Done) << off.message;
  EXPECT_GT(metric(off, "eta_fit") / 5e-3, 1.2);
  EXPECT_LT(metric(on, "profile_err"), metric(off, "profile_err"));
}

TEST(ShearLayerCase, RejectsBadEtaNum) {
  Params prm = shear_params();
  prm["eta_num"] = std::string("lots");
  EXPECT_THROW(find_case("shear_layer")->run(prm, RunContext{}), std::invalid_argument);
}

TEST(ShearLayerCase, ImpedanceIsACheckedLabel) {
  Params prm = shear_params();
  prm["material"] = std::string("lead");
  prm["impedance"] = 2.0e7; // lead: rho0 c0 = 2.1925e7
  EXPECT_THROW(find_case("shear_layer")->run(prm, RunContext{}), std::invalid_argument);
}

namespace sph {
double cylinder_array_a0(double d_over_S);
}

// Seed 003 eq. (39) as printed against the paper's own Table 2 column C_D,M at Re = 0.005:
// d/S = 0.3 gives 8000 (we get 7968); d/S = 0.5 gives 20200 where the printed series gives 21130
// (+4.6%; Sangani & Acrivos's K(c = 0.196) = 50.4 gives 20160: docs/contact.md).
TEST(CylinderArray, Eq39AgainstTable2) {
  const double pi = 3.141592653589793;
  EXPECT_NEAR(16 * pi * cylinder_array_a0(0.3) / 0.005, 8000.0, 0.005 * 8000.0);
  EXPECT_NEAR(16 * pi * cylinder_array_a0(0.5) / 0.005, 21130.0, 10.0);
  // Dilute limit: a0 -> 1 / (1 - 2 ln(2 omega)) (Hasimoto), within 1% at d/S = 0.05.
  const double w = pi * 0.05 / 2;
  EXPECT_NEAR(cylinder_array_a0(0.05) * (1 - 2 * std::log(2 * w)), 1.0, 0.01);
}

namespace {

// Fluid on a lattice above a solid floor (y < 0), periodic in x, hydrostatic in the body force
// g = (0, -gy): P = rho0 gy (H - y) and rho = rho0 + P / c0^2.
struct Floor {
  Particles<2> p;
  Fields f;
  Domain<2> box;
  Options o;
  double D0 = 1e-3, rho0 = 1000.0, c0 = 200.0, gy = 10.0, H = 0.0;
  int n_fluid = 0;
  Floor(int nx, int ny, int n_solid) {
    f = Fields::add_to(p);
    H = ny * D0;
    for_each_lattice_point<2>({0, -n_solid}, {nx, ny}, D0, [&](Vec<2> x, const auto& idx) {
      const bool solid = idx[1] < 0;
      const double P = solid ? 0.0 : rho0 * gy * (H - x[1]);
      const double rho = rho0 + P / (c0 * c0);
      const std::size_t i =
          p.add(x, rho0 * D0 * D0, solid ? rho0 : rho, solid ? Kind::Wall : Kind::Fluid);
      p.scalar(f.rho0)[i] = rho0;
      p.scalar(f.c0)[i] = c0;
      p.scalar(f.eta)[i] = 1e-3;
      n_fluid += !solid;
    });
    box.lo = Vec<2>(0.0, -n_solid * D0);
    box.hi = Vec<2>(nx * D0, H);
    box.periodic = {true, false};
    o.g = {0.0, -gy, 0.0};
  }
};

} // namespace

// The solid's pressure is the fluid's carried by the body force: a hydrostatic column on a solid
// floor is at rest, also next to the floor (with P_solid = 0 the first rows would be pushed down
// by about gy). Tolerance: 3% of gy (the lattice's gradient error at h = D0); checked to fail
// with the body-force term of P_j removed.
TEST(ContactSolid, HydrostaticColumnOnAFloorIsAtRest) {
  Floor fl(8, 12, 3);
  Scheme<2, WendlandC2<2>> s(fl.p, fl.f, fl.box, fl.o);
  s.init();
  s.step(1e-9); // one tiny step: the rates are those of the initial state
  double worst = 0.0;
  for (std::size_t i = 0; i < fl.p.size(); ++i)
    if (fl.p.kind[i] == Kind::Fluid && fl.p.r[i][1] < fl.H - 3.0 * fl.D0) // away from the top
      worst = std::max(worst, s.work().dvdt[i].norm());
  EXPECT_LT(worst, 0.03 * fl.gy) << worst;
}

// The per-particle body force (field "g_factor", the falling ball's reduced gravity): particle i
// feels g g_factor_i. (1) Uniform periodic lattice, factors 0, 0.25, 1: the rates of the initial
// state are g_i and the energy rates g_i . U_i exactly (the pair terms of equal states cancel; the
// tiny step's velocity differences, g dt = 1e-8 m/s, move them by far less than the 1e-6
// tolerance). (2) The floor's hydrostatic column with g doubled and g_factor 0.5 everywhere is the
// plain column, to the bit: the solid's pressure P_i - rho_i g_i . r_ij takes the particle's own
// g_i.
TEST(ContactScheme, GFactorScalesTheBodyForcePerParticle) {
  Box<2, WendlandC2<2>> b(12, 0.0, true);
  const int gf = b.p.add_scalar("g_factor");
  const double factors[3] = {0.0, 0.25, 1.0}, g = 1e10;
  for (std::size_t i = 0; i < b.p.size(); ++i)
    b.p.scalar(gf)[i] = factors[i % 3];
  b.f = Fields::find_in(b.p);
  b.o.g = {0.0, -g, 0.0};
  Scheme<2, WendlandC2<2>> s(b.p, b.f, b.box, b.o);
  s.init();
  s.step(1e-18);
  for (std::size_t i = 0; i < b.p.size(); ++i) {
    const double fi = b.p.scalar(gf)[i]; // particles are reordered: read the factor back
    EXPECT_NEAR(s.work().dvdt[i][1], -g * fi, 1e-6 * g) << i;
    EXPECT_NEAR(s.work().dvdt[i][0], 0.0, 1e-6 * g) << i;
    // eq. (36): the body force's power g_i . U_i (U = (30, 60) m/s on this lattice)
    EXPECT_NEAR(s.work().dEdt[i], -g * fi * b.p.v[i][1], 1e-6 * g * 60.0) << i;
  }

  auto rates = [](bool halved) {
    Floor fl(8, 12, 3);
    if (halved) {
      const int k = fl.p.add_scalar("g_factor");
      for (std::size_t i = 0; i < fl.p.size(); ++i)
        fl.p.scalar(k)[i] = 0.5;
      fl.f = Fields::find_in(fl.p);
      fl.o.g = {0.0, -2.0 * fl.gy, 0.0};
    }
    Scheme<2, WendlandC2<2>> sf(fl.p, fl.f, fl.box, fl.o);
    sf.init();
    sf.step(1e-9);
    std::vector<double> out;
    for (std::size_t i = 0; i < fl.p.size(); ++i) // the rates of the fluid (solids have none)
      if (fl.p.kind[i] == Kind::Fluid)
        out.push_back(sf.work().dvdt[i][0]), out.push_back(sf.work().dvdt[i][1]);
    return out;
  };
  EXPECT_EQ(rates(true), rates(false));
}

// Momentum balance with solids: fluid-fluid pairs cancel, so the fluid's total momentum rate is
// the body force on the fluid plus the force of the solids (solid_force()), to round-off.
TEST(ContactSolid, MomentumBalanceWithSolids) {
  Floor fl(8, 12, 3);
  UniformRandom rn(3);
  for (std::size_t i = 0; i < fl.p.size(); ++i)
    if (fl.p.kind[i] == Kind::Fluid)
      fl.p.v[i] = Vec<2>(rn() - 0.3, 0.2 * (rn() - 0.5));
  Scheme<2, WendlandC2<2>> s(fl.p, fl.f, fl.box, fl.o);
  s.init();
  s.step(1e-6);
  Vec<2> rate = Vec<2>::Zero(), Mg = Vec<2>::Zero();
  for (std::size_t i = 0; i < fl.p.size(); ++i)
    if (fl.p.kind[i] == Kind::Fluid)
      rate += fl.p.m[i] * s.work().dvdt[i], Mg += fl.p.m[i] * Vec<2>(0.0, -fl.gy);
  const Vec<2> Fs = s.solid_force();
  EXPECT_GT(Fs.norm(), 1e-3 * Mg.norm()); // the solids act
  EXPECT_LT((rate - Mg - Fs).norm(), 1e-12 * (Mg.norm() + Fs.norm()));
  EXPECT_LT(Fs[0], 0.0); // no-slip: the floor drags the fluid moving in +x
}

// The spreading drop's viscometer (diagnostics/gravity_current.hpp): Huppert's (1982) front
// constant of the half-current of constant area, eta_N = (80 / (3 B^3))^(1/5) = 1.411 (his value,
// to the three decimals he gives); and the line fit on points of a line.
TEST(GravityCurrent, HuppertFrontConstant) {
  const double B = gravity_current_shape_integral();
  EXPECT_NEAR(std::pow(80.0 / (3.0 * B * B * B), 0.2), 1.411, 5e-4);
  // B by quadrature of int_{-1}^{1} (1 - s^2)^(1/3) ds (midpoint rule on s = sin(theta), smooth).
  double b = 0.0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double th = -0.5 * std::numbers::pi + (k + 0.5) * std::numbers::pi / n;
    b += std::pow(std::cos(th), 2.0 / 3.0) * std::cos(th) * std::numbers::pi / n;
  }
  EXPECT_NEAR(B, b, 1e-8);
  const LineFit f = fit_line({0.0, 1.0, 2.0, 3.0, 10.0}, {1.0, 3.0, 5.0, 7.0, 100.0}, -1.0, 3.5);
  EXPECT_EQ(f.n, 4);
  EXPECT_NEAR(f.a, 1.0, 1e-12);
  EXPECT_NEAR(f.b, 2.0, 1e-12);
  EXPECT_NEAR(f.r2, 1.0, 1e-12);
}

// Eq. (1) of gravity_current.hpp against an independent solution of the thin-film equation
// h_t = g / (12 nu) (h^4)_xx: explicit finite volumes (flux -(g / (3 nu)) h^3 h_x at the faces,
// h^3 the face mean of the two cells), from a box of area Q = 2 to times where the front has
// spread to about 5 times the box. The viscosity read back from the slope of x_N^5 over the
// second half of the run (front: where h crosses 1e-3 of its maximum, interpolated between cell
// centres) is the one the equation was solved with, to 2 %: measured 2.7, 1.0 and 0.15 % at
// dx = 0.04, 0.02 and 0.01 (first order in dx; 0.02 here, 0.2 s); a wrong constant in eq. 1
// moves it by more (10/9 -> 1: 11 %; Gamma(4/3) -> Gamma(5/3) in B: 3.3 %).
TEST(GravityCurrent, FrontRateMatchesTheThinFilmEquation) {
  const double g = 12.0, nu = 1.0, L = 8.0, dx = 0.02; // g / (12 nu) = 1
  const int n = static_cast<int>(2.0 * L / dx);
  std::vector<double> h(n, 0.0), flux(n + 1, 0.0);
  auto xc = [&](int i) { return -L + (i + 0.5) * dx; };
  for (int i = 0; i < n; ++i)
    if (std::abs(xc(i)) < 1.0)
      h[i] = 1.0;
  double Q = 0.0;
  for (double v : h)
    Q += v * dx;
  std::vector<double> ts, x5;
  double t = 0.0, next = 0.0;
  const double t_end = 100.0;
  while (t < t_end) {
    const double hmax = *std::max_element(h.begin(), h.end());
    const double dt = 0.2 * dx * dx / (g / (3.0 * nu) * hmax * hmax * hmax);
    for (int f = 1; f < n; ++f) {
      const double hf = 0.5 * (h[f - 1] + h[f]);
      flux[f] = -(g / (3.0 * nu)) * hf * hf * hf * (h[f] - h[f - 1]) / dx;
    }
    for (int i = 0; i < n; ++i)
      h[i] -= dt / dx * (flux[i + 1] - flux[i]);
    t += dt;
    if (t >= next) {
      const double thr = 1e-3 * hmax;
      int r = n - 1;
      while (r > 0 && h[r] <= thr)
        --r;
      // the threshold crossing, linear between the centres of cells r and r + 1
      const double xN = xc(r) + dx * (h[r] - thr) / (h[r] - h[r + 1]);
      ts.push_back(t), x5.push_back(std::pow(xN, 5));
      next += 1.0;
    }
  }
  ASSERT_LT(std::pow(x5.back(), 0.2), L - 1.0); // the front stayed inside the domain
  const LineFit f = fit_line(ts, x5, 0.5 * t_end);
  EXPECT_NEAR(gravity_current_viscosity(Q, g, f.b) / nu, 1.0, 0.02)
      << "slope " << f.b << ", r2 " << f.r2;
  EXPECT_GT(f.r2, 0.999);
}
