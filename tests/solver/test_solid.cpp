// Tests of the total-Lagrangian elastic solid (schemes/solid/elastic_solid.hpp) and the cantilever
// case (cases/cantilever.cpp); docs/solid.md.
//
// (1) Exact fields on a lattice block (round-off tolerances): the corrected gradient reproduces
//     the identity in the reference configuration and F is exactly the affine map of an affinely
//     deformed block (edges and corners included); the rate dF and the damping stress are exact
//     for an affine velocity; a rigid rotation (with its rigid velocity) gives zero stress, zero
//     energy and zero force, for both laws; P of a uniaxial stretch equals the closed form; a
//     uniformly stretched block has no force in its interior and pulls its edges inwards.
// (2) Conservation on a free block (no clamp) with random velocities: linear and angular momentum
//     to round-off over hundreds of steps; energy without damping to the time-integration error,
//     and decaying with it.
// (3) Value bands of the cantilever against Euler-Bernoulli (static deflection under its own
//     weight, first-mode frequency), measured at H/dx = 4 and 8 (docs/solid.md).
#include "case_helpers.hpp"
#include "cases/case.hpp"
#include "core/kernels/wendland_c2.hpp"
#include "core/lattice.hpp"
#include "schemes/solid/elastic_solid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>

using namespace sph;
using sph::testing::metric;

namespace {

using Kernel = WendlandC2<2>;
using Svk = solid::SaintVenantKirchhoff<2>;
using Nh = solid::NeoHookean<2>;

constexpr double rho0 = 1000.0, E = 1.0e6, nu = 0.3;

// A block of nx x ny Solid particles on the cell-centred lattice of spacing dx, and a scheme on it
// (Wendland C2, h = 1.3 dx), initialised (the reference configuration is the lattice).
template <class Law = Svk>
struct Block {
  Particles<2> p;
  solid::Options o;
  std::unique_ptr<solid::Scheme<2, Kernel, Law>> s;

  Block(int nx, int ny, double dx, double damping = 0.0, double cfl = 0.6) {
    for_each_lattice_point<2>({0, 0}, {nx, ny}, dx, [&](const Vec2& x, const std::array<int, 2>&) {
      p.add(x, rho0 * dx * dx, rho0, Kind::Solid);
    });
    o.rho0 = rho0, o.E = E, o.nu = nu, o.dx = dx, o.h = 1.3 * dx, o.damping = damping;
    o.cfl = cfl;
    s = std::make_unique<solid::Scheme<2, Kernel, Law>>(p, o, Kernel(o.h));
    s->init();
  }
  // Positions A r0 + c and velocities Adot r0 + w, then F, P and the forces of that state.
  void deform(const Mat<2>& A, const Vec2& c, const Mat<2>& Adot, const Vec2& w) {
    const auto& r0 = s->reference_positions();
    for (std::size_t i = 0; i < p.size(); ++i)
      p.r[i] = A * r0[i] + c, p.v[i] = Adot * r0[i] + w;
    s->forces();
  }
  // P_i = A_i B_i^-T (A_i = P_i B_i^T is what the scheme keeps).
  Mat<2> P(std::size_t i) const { return s->stress_term()[i] * s->B()[i].transpose().inverse(); }
};

Mat<2> rotation(double th) {
  Mat<2> R;
  R << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
  return R;
}

double max_abs(const Mat<2>& m) {
  return m.cwiseAbs().maxCoeff();
}

} // namespace

// ---------------------------------------------------------------------------------------------
// (1) Exact fields.

// sum_j V_j (r0_j - r0_i) (x) grad W0_ij B_i = I for every particle: the correction reproduces the
// identity, also at the edges and corners where the uncorrected sum is far from it (checked, so
// the test means something there).
TEST(SolidKinematics, ReferenceDeformationGradientIsTheIdentity) {
  Block<> b(12, 8, 0.01);
  double err = 0.0, uncorrected_edge = 0.0;
  for (std::size_t i = 0; i < b.p.size(); ++i) {
    err = std::max(err, max_abs(b.s->F()[i] - Mat<2>::Identity()));
    uncorrected_edge = std::max(uncorrected_edge, max_abs(b.s->B()[i] - Mat<2>::Identity()));
  }
  EXPECT_LT(err, 1e-12);
  EXPECT_GT(uncorrected_edge, 0.3); // B_i departs from I by O(1) at the free edges
}

// x = A X + c: F_i = A for every particle (edges and corners included), to round-off.
TEST(SolidKinematics, DeformationGradientIsTheAffineMapExactly) {
  Block<> b(12, 8, 0.01);
  Mat<2> A;
  A << 1.08, 0.13, -0.07, 0.94;
  A = rotation(0.7) * A;
  b.deform(A, Vec2(0.3, -0.2), Mat<2>::Zero(), Vec2::Zero());
  double err = 0.0;
  for (std::size_t i = 0; i < b.p.size(); ++i)
    err = std::max(err, max_abs(b.s->F()[i] - A));
  EXPECT_LT(err, 1e-12);
}

// With no elasticity (lambda = G = 0) and the undeformed block moving with v = Adot X + w, the
// stress is the damping stress alone: P = F S = eta (Adot + Adot^T) / 2 exactly (F = I), which
// pins dF = Adot, the strain rate and the viscosity eta = damping rho0 c_p h.
TEST(SolidKinematics, DampingStressIsExactForAnAffineVelocity) {
  Block<> b(12, 8, 0.01, 0.3);
  Mat<2> Ad;
  Ad << 0.5, -1.2, 0.4, -0.3;
  const double eta = 0.3 * rho0 * solid::Elastic{E, nu}.c_p(rho0) * 0.013;
  EXPECT_NEAR(b.s->eta(), eta, 1e-12 * eta);
  // Elasticity switched off through the law's constants (the scheme's own law object).
  const_cast<Svk&>(b.s->law()) = Svk{0.0, 0.0};
  b.deform(Mat<2>::Identity(), Vec2::Zero(), Ad, Vec2(1.0, 2.0));
  const Mat<2> expected = eta * 0.5 * (Ad + Ad.transpose());
  double err = 0.0;
  for (std::size_t i = 0; i < b.p.size(); ++i)
    err = std::max(err, max_abs(b.P(i) - expected));
  EXPECT_LT(err, 1e-10 * max_abs(expected));
}

// A rigid rotation with its rigid velocity: zero strain, zero strain rate, so zero stress, energy
// and force (frame indifference of both laws), to round-off relative to E.
template <class Law>
void rigid_rotation_is_stress_free() {
  Block<Law> b(12, 8, 0.01, 0.5);
  const Mat<2> R = rotation(1.1);
  Mat<2> Omega;
  Omega << 0.0, -3.0, 3.0, 0.0; // angular velocity 3
  b.deform(R, Vec2(0.5, 0.1), Omega * R, Vec2(0.2, 0.0));
  double P = 0.0, a = 0.0, psi = b.s->elastic_energy();
  for (std::size_t i = 0; i < b.p.size(); ++i) {
    P = std::max(P, max_abs(b.P(i)));
    a = std::max(a, b.s->internal_acceleration()[i].norm());
  }
  EXPECT_LT(P, 1e-10 * E);
  EXPECT_LT(std::abs(psi), 1e-12 * E * 0.12 * 0.08);
  EXPECT_LT(a, 1e-10 * E / (rho0 * 0.01)); // force scale of a stress E over one spacing
}
TEST(SolidStress, RigidRotationIsStressFreeSvk) {
  rigid_rotation_is_stress_free<Svk>();
}
TEST(SolidStress, RigidRotationIsStressFreeNeoHookean) {
  rigid_rotation_is_stress_free<Nh>();
}

// F = diag(1 + e, 1) on the block: P of every particle equals the closed form of each law.
//   SVK: E11 = e + e^2/2, S11 = (lambda + 2G) E11, S22 = lambda E11, P = F S.
//   neo-Hookean: J = 1 + e, S11 = G (1 - 1/J^2) + lambda ln J / J^2, S22 = lambda ln J.
TEST(SolidStress, UniaxialStretchMatchesTheClosedForm) {
  const double e = 0.1, lam = solid::Elastic{E, nu}.lambda(), G = solid::Elastic{E, nu}.G();
  const Mat<2> F = Vec2(1.0 + e, 1.0).asDiagonal();
  {
    Block<Svk> b(12, 8, 0.01);
    b.deform(F, Vec2::Zero(), Mat<2>::Zero(), Vec2::Zero());
    const double E11 = e + 0.5 * e * e;
    Mat<2> P = Mat<2>::Zero();
    P(0, 0) = (1.0 + e) * (lam + 2.0 * G) * E11, P(1, 1) = lam * E11;
    for (std::size_t i = 0; i < b.p.size(); ++i)
      ASSERT_LT(max_abs(b.P(i) - P), 1e-10 * E) << "particle " << i;
    // Strain energy lambda/2 E11^2 + G E11^2 per reference volume, times the block's area.
    const double psi = 0.5 * lam * E11 * E11 + G * E11 * E11;
    EXPECT_NEAR(b.s->elastic_energy(), psi * 0.12 * 0.08, 1e-10 * psi);
  }
  {
    Block<Nh> b(12, 8, 0.01);
    b.deform(F, Vec2::Zero(), Mat<2>::Zero(), Vec2::Zero());
    const double J = 1.0 + e, lnJ = std::log(J);
    Mat<2> P = Mat<2>::Zero();
    P(0, 0) = (1.0 + e) * (G * (1.0 - 1.0 / (J * J)) + lam * lnJ / (J * J));
    P(1, 1) = lam * lnJ;
    for (std::size_t i = 0; i < b.p.size(); ++i)
      ASSERT_LT(max_abs(b.P(i) - P), 1e-10 * E) << "particle " << i;
  }
}

// A uniformly stretched block (F = diag(1 + e, 1)): the divergence of a uniform stress is zero, so
// the particles farther than two kernel supports from every edge feel no force (round-off); the
// particles of the edges x = 0 and x = L are pulled inwards (the block wants to contract), with
// the force of the traction P11 over one spacing, i.e. a_x ~ -+ P11 / (rho0 dx) in order of
// magnitude.
TEST(SolidStress, UniformStretchHasNoInteriorForceAndPullsTheEdgesIn) {
  const double dx = 0.01, e = 0.01;
  Block<Svk> b(16, 12, dx);
  b.deform(Vec2(1.0 + e, 1.0).asDiagonal(), Vec2::Zero(), Mat<2>::Zero(), Vec2::Zero());
  const double P11 = b.P(0)(0, 0), scale = P11 / (rho0 * dx), support = 2.6 * dx;
  const auto& r0 = b.s->reference_positions();
  const auto& a = b.s->internal_acceleration();
  double interior = 0.0, left_lo = 1e300, left_hi = -1e300, right_lo = 1e300, right_hi = -1e300;
  for (std::size_t i = 0; i < b.p.size(); ++i) {
    const Vec2 x = r0[i];
    const bool mid_height = x[1] > support && x[1] < 0.12 - support;
    // Interior: every neighbour j is itself a support away from the edges, so that its B_j, and
    // with it its P_j B_j^T, is the interior one (B varies within a support of an edge).
    if (x[0] > 2 * support && x[0] < 0.16 - 2 * support && x[1] > 2 * support &&
        x[1] < 0.12 - 2 * support)
      interior = std::max(interior, a[i].norm());
    if (x[0] < dx && mid_height)
      left_lo = std::min(left_lo, a[i][0]), left_hi = std::max(left_hi, a[i][0]);
    if (x[0] > 0.16 - dx && mid_height)
      right_lo = std::min(right_lo, a[i][0]), right_hi = std::max(right_hi, a[i][0]);
  }
  std::printf("uniform stretch: interior |a| %.2e, left edge a_x in [%.3f, %.3f], right edge "
              "[%.3f, %.3f] (units P11 / (rho0 dx))\n",
              interior / scale, left_lo / scale, left_hi / scale, right_lo / scale,
              right_hi / scale);
  EXPECT_LT(interior, 1e-9 * scale);
  EXPECT_GT(left_lo, 0.1 * scale); // pulled towards +x, into the block
  EXPECT_LT(left_hi, 3.0 * scale);
  EXPECT_LT(right_hi, -0.1 * scale); // pulled towards -x
  EXPECT_GT(right_lo, -3.0 * scale);
}

// ---------------------------------------------------------------------------------------------
// (2) Conservation on a free block.

namespace {

struct Totals {
  Vec2 P = Vec2::Zero();
  double L = 0.0, P_scale = 0.0, L_scale = 0.0, energy = 0.0;
};
template <class S>
Totals totals(const Particles<2>& p, const S& s) {
  Totals t;
  for (std::size_t i = 0; i < p.size(); ++i) {
    t.P += p.m[i] * p.v[i];
    t.L += p.m[i] * (p.r[i][0] * p.v[i][1] - p.r[i][1] * p.v[i][0]);
    t.P_scale += p.m[i] * p.v[i].norm();
    t.L_scale += p.m[i] * p.r[i].norm() * p.v[i].norm();
  }
  t.energy = s.kinetic_energy() + s.elastic_energy();
  return t;
}

// Velocities of the 12 x 8 block (0.12 x 0.08): a drift velocity, a spin of angular velocity w
// about its centre, a smooth deformation mode of amplitude `smooth` and random velocities of
// amplitude `noise` (both in units of sqrt(E / rho0)).
template <class Law = Svk>
void shake(Block<Law>& b, const Vec2& drift, double w, double smooth, double noise) {
  UniformRandom rn(7);
  const Vec2 c(0.06, 0.04);
  const double u = std::sqrt(E / rho0), pi = std::numbers::pi;
  for (std::size_t i = 0; i < b.p.size(); ++i) {
    const Vec2 d = b.p.r[i] - c;
    const double x = b.p.r[i][0] / 0.12, y = b.p.r[i][1] / 0.08;
    b.p.v[i] =
        drift + w * Vec2(-d[1], d[0]) +
        smooth * u *
            Vec2(std::sin(pi * x) * std::cos(pi * y), std::cos(2 * pi * x) * std::sin(pi * y)) +
        noise * u * Vec2(rn() - 0.5, rn() - 0.5);
  }
}

} // namespace

TEST(SolidConservation, FreeBlockConservesLinearAndAngularMomentumToRoundOff) {
  Block<Svk> b(12, 8, 0.01, 0.2);
  shake(b, Vec2(0.3, -0.1), 20.0, 0.01, 0.01);
  b.s->forces(); // accelerations of the shaken state (Verlet's first kick uses them)
  const Totals t0 = totals(b.p, *b.s);
  double dP = 0.0, dL = 0.0, F_max = 0.0;
  for (int n = 0; n < 400; ++n) {
    b.s->step(1e300);
    const Totals t = totals(b.p, *b.s);
    dP = std::max(dP, (t.P - t0.P).norm() / t0.P_scale);
    dL = std::max(dL, std::abs(t.L - t0.L) / t0.L_scale);
    for (std::size_t i = 0; i < b.p.size(); ++i)
      F_max = std::max(F_max, max_abs(b.s->F()[i] - Mat<2>::Identity()));
  }
  EXPECT_GT(F_max, 1e-3); // the block did deform (strains of 0.1 % and more)
  EXPECT_LT(dP, 1e-13);
  EXPECT_LT(dL, 1e-13);
}

// A smooth deformation mode of the free block: without damping the energy (kinetic + elastic)
// stays within the time-integration error of velocity Verlet (second order: halving the step
// divides it by about 4); with damping it decays (a damping
// of the wrong sign makes it grow). Random particle velocities are not used here: much of their
// energy lies in modes that F does not see (hourglass modes, docs/solid.md), which neither store
// elastic energy nor feel the damping.
TEST(SolidConservation, EnergyIsConservedWithoutDampingAndDecaysWithIt) {
  double drift[2] = {0.0, 0.0}, e0_damped = 0.0, e_damped = 0.0;
  for (int k = 0; k < 2; ++k) {
    Block<Svk> b(12, 8, 0.01, 0.0, k == 0 ? 0.6 : 0.3);
    shake(b, Vec2::Zero(), 0.0, 0.01, 0.0);
    b.s->forces();
    const double e0 = totals(b.p, *b.s).energy;
    for (int n = 0; n < 400; ++n) {
      b.s->step(1e300);
      drift[k] = std::max(drift[k], std::abs(totals(b.p, *b.s).energy - e0) / e0);
    }
  }
  {
    Block<Svk> b(12, 8, 0.01, 0.5);
    shake(b, Vec2::Zero(), 0.0, 0.01, 0.0);
    b.s->forces();
    e0_damped = totals(b.p, *b.s).energy;
    for (int n = 0; n < 400; ++n)
      b.s->step(1e300);
    e_damped = totals(b.p, *b.s).energy;
  }
  std::printf("energy: largest |E - E0| / E0 without damping %.3e (cfl 0.6), %.3e (cfl 0.3); "
              "damped E/E0 = %.4f\n",
              drift[0], drift[1], e_damped / e0_damped);
  // Measured 1.90e-2 and 4.11e-3: the error of velocity Verlet, second order in dt (ratio 4.6).
  EXPECT_LT(drift[0], 0.03);
  EXPECT_GT(drift[0] / drift[1], 3.0);
  EXPECT_LT(drift[0] / drift[1], 6.0);
  // Measured 0.123 after 400 steps with damping = 0.5 (the stress-free drift is not damped).
  EXPECT_LT(e_damped, 0.3 * e0_damped);
}

// The same scheme in 3D (one template on the dimension): F is the affine map exactly, a rigid
// rotation is stress-free, and a shaken free block keeps its linear and angular momentum.
TEST(SolidConservation, ThreeDimensionalBlock) {
  using K3 = WendlandC2<3>;
  const double dx = 0.01;
  Particles<3> p;
  for_each_lattice_point<3>({0, 0, 0}, {7, 6, 5}, dx,
                            [&](const Vec3& x, const std::array<int, 3>&) {
                              p.add(x, rho0 * dx * dx * dx, rho0, Kind::Solid);
                            });
  solid::Options o;
  o.rho0 = rho0, o.E = E, o.nu = nu, o.dx = dx, o.h = 1.3 * dx, o.damping = 0.2;
  solid::Scheme<3, K3, solid::SaintVenantKirchhoff<3>> s(p, o, K3(o.h));
  s.init();
  const std::vector<Vec3> r0 = s.reference_positions();
  const Mat<3> R = Eigen::AngleAxisd(0.8, Vec3(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
  Mat<3> A = R;
  A(0, 0) += 0.05, A(1, 2) += -0.08, A(2, 1) += 0.03;
  for (std::size_t i = 0; i < p.size(); ++i)
    p.r[i] = A * r0[i], p.v[i] = Vec3::Zero();
  s.forces();
  double errF = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    errF = std::max(errF, (s.F()[i] - A).cwiseAbs().maxCoeff());
  EXPECT_LT(errF, 1e-12);
  Mat<3> W;
  W << 0.0, -2.0, 1.0, 2.0, 0.0, -3.0, -1.0, 3.0, 0.0; // angular velocity (3, 1, 2)
  for (std::size_t i = 0; i < p.size(); ++i)
    p.r[i] = R * r0[i], p.v[i] = W * R * r0[i];
  s.forces();
  double P = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    P = std::max(P, (s.stress_term()[i] * s.B()[i].transpose().inverse()).cwiseAbs().maxCoeff());
  EXPECT_LT(P, 1e-10 * E);
  // Shaken: spin plus random velocities (0.01 sqrt(E / rho0)) from the lattice.
  UniformRandom rn(3);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.r[i] = r0[i];
    p.v[i] = W * r0[i] + 0.01 * std::sqrt(E / rho0) * Vec3(rn() - 0.5, rn() - 0.5, rn() - 0.5);
  }
  s.forces();
  auto momenta = [&](Vec3& P3, Vec3& L3, double& Ps, double& Ls) {
    P3 = L3 = Vec3::Zero(), Ps = Ls = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      P3 += p.m[i] * p.v[i], L3 += p.m[i] * p.r[i].cross(p.v[i]);
      Ps += p.m[i] * p.v[i].norm(), Ls += p.m[i] * p.r[i].norm() * p.v[i].norm();
    }
  };
  Vec3 P0, L0, P1, L1;
  double Ps, Ls, dP = 0.0, dL = 0.0, ps, ls;
  momenta(P0, L0, Ps, Ls);
  for (int n = 0; n < 100; ++n) {
    s.step(1e300);
    momenta(P1, L1, ps, ls);
    dP = std::max(dP, (P1 - P0).norm() / Ps), dL = std::max(dL, (L1 - L0).norm() / Ls);
  }
  EXPECT_LT(dP, 1e-13);
  EXPECT_LT(dL, 1e-13);
}

// ---------------------------------------------------------------------------------------------
// (3) Value bands of the cantilever case against Euler-Bernoulli.

namespace {

Params cantilever_defaults() {
  return sph::testing::case_defaults("cantilever", "elastic_solid");
}

} // namespace

// L/H = 10 (Euler-Bernoulli's range), H/dx = 8, Wendland C2 with h = 1.3 dx, damping 0.05, own
// weight g = 0.05 (tip deflection 1e-3 L: linear) applied at t = 0, one whole period in
// t_end = 0.6 s. Measured: deflection ratio 1.1738, frequency ratio 0.9204 (the SPH beam is softer
// than the beam theory and converges to it at second order in dx: 1.61 / 1.148 / 1.042 at H/dx =
// 4 / 8 / 16 for L/H = 17.5, docs/solid.md). The run is deterministic (one thread); the bands
// absorb floating-point differences between builds and are far inside what separates two
// resolutions or what a wrong stress term moves (docs/solid.md, mutations).
TEST(Cantilever, DeflectionAndFrequencyAgainstBeamTheory) {
  Params prm = cantilever_defaults();
  prm["L"] = 0.2;
  prm["H_over_dx"] = std::int64_t{8};
  prm["t_end"] = 0.6;
  RunContext ctx;
  const RunResult r = find_case("cantilever")->run(prm, ctx);
  ASSERT_EQ(r.status, RunStatus::Done) << r.message;
  std::printf("cantilever L/H = 10, H/dx = 8: deflection ratio %.5f, frequency ratio %.5f, "
              "energy drift %.2e, internal force %.1e, torque %.1e\n",
              metric(r, "deflection_ratio"), metric(r, "frequency_ratio"),
              metric(r, "energy_drift"), metric(r, "internal_force_rel_max"),
              metric(r, "internal_torque_rel_max"));
  EXPECT_EQ(metric(r, "periods"), 1.0);
  EXPECT_NEAR(metric(r, "deflection_ratio"), 1.1738, 0.02);
  EXPECT_NEAR(metric(r, "frequency_ratio"), 0.9204, 0.01);
  // The damping takes energy out (6.2e-4 of the largest elastic energy), never puts it in.
  EXPECT_LT(metric(r, "energy_drift"), 0.0);
  EXPECT_GT(metric(r, "energy_drift"), -2e-3);
  // Internal forces sum to zero, torques too, clamp included: round-off.
  EXPECT_LT(metric(r, "internal_force_rel_max"), 1e-13);
  EXPECT_LT(metric(r, "internal_torque_rel_max"), 1e-13);
}
