// Scheme "wcsph_tvf" on a short analytic flow (issue 15, section 1): the viscous decay of a small
// Taylor-Green vortex. Written against today's wcsph_tvf::Scheme (init(), advance(Dt)); it sets
// particles, steps, and measures the velocity amplitude, so it ports to the Scheme interface of
// issue 14 by replacing those calls. (The study's own Taylor-Green, at U = 1 and Re = 100, is
// checked by tests/studies/tvf.sh with value bands.) And that study's vortex with B and the
// limited shift, through the case: its decay follows the viscous force's lattice eigenvalue.
#include "case_helpers.hpp"
#include "core/kernels/wendland_c2.hpp"
#include "schemes/wcsph_tvf/wcsph_tvf.hpp"
#include "tgv_helpers.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sph;
using namespace sph::testing;

// U = 0.001 (Re = 0.02, Mach U / c0 = 1e-4: linear and nearly incompressible). The viscous force
// F^nu is computed once per advection step and applied over the step's acoustic sub-steps, so each
// step is u <- u (1 + nu Dt lambda), lambda the eigenvalue of the pair form
// a_i = nu sum_j -2 V_j dW / (r + eps h) (v_j - v_i) for the mode on the perfect lattice (computed
// from the kernel; lambda = -2 k^2 0.948, the uncorrected form's quadrature factor 0.964 times its
// truncation error). What the prediction leaves out is nonlinear in U: the pressure the mode's
// O(U^2) compression creates (acoustic, not projected), the Riemann dissipation (limited: beta ~
// 3 u_ij / c0, quadratic in U) and the TVF shift (zero on the perfect lattice); measured, they
// change the rate by 5e-4 at U = 0.01 and 3.5e-5 at U = 0.001 (6e-5 with c0 = 40). Tolerance 5e-4
// of the rate. A factor error in the viscous force (2 mu -> mu halves the rate) fails.
TEST(AnalyticWcsphTvf, TaylorGreenViscousDecayRate) {
  const int n = 24, steps = 20;
  const double U = 0.001, dx = 1.0 / n, nu = 0.05;
  Particles<2> p;
  tgv_lattice(p, n, U);
  wcsph_tvf::Fields f = wcsph_tvf::Fields::add_to(p);
  Domain<2> box;
  box.periodic = {true, true};
  wcsph_tvf::Options o;
  o.dx = dx, o.h = 1.3 * dx, o.mu = nu, o.c0 = 10.0;
  wcsph_tvf::Scheme<2, WendlandC2<2>> sc(p, f, box, o);
  sc.init();
  const WendlandC2<2> W(o.h);
  const double eps_h = o.viscous_eps * o.h;
  const double lambda = tgv_eigenvalue(
      dx, W.support(), [&](double r) { return -2 * dx * dx * W.dW(r) / (r + eps_h); });
  const double k2 = 2 * tgv_k * tgv_k;
  const double Dt = sc.advection_dt();
  EXPECT_NEAR(Dt, 0.25 * o.h, 1e-15); // U_ref = 1 sets the step
  const double A0 = tgv_amplitude(p);
  for (int k = 0; k < steps; ++k)
    sc.advance(Dt);
  const double rate = std::log(tgv_amplitude(p) / A0) / (steps * Dt);
  const double pred = std::log(1 + nu * Dt * lambda) / Dt;
  std::printf("rate %.6f  predicted %.6f  continuum %.6f\n", rate, pred, -nu * k2);
  EXPECT_NEAR(rate / pred, 1.0, 5e-4);
}

// The study's Taylor-Green (Re = 100, U = 1, c0 = 10 U) with the kernel-gradient correction B and
// the limited shift, from the perturbed lattice, through the case: its kinetic energy decays
// slower than the analytic solution's (docs/tvf.md: E_k 23 % above it at t = 5, 100 x 100), and
// the deficit is the viscous force's lattice quadrature, which the shift's near-lattice order
// brings back. Its fingerprint: switching eps h off in (r_ij + eps h) must speed the decay by the
// ratio of the two lattice eigenvalues for the mode, lambda(0) / lambda(0.01) = 1.0105 at
// n = 40 (measured 1.0103; at n = 60 1.0114), and not by any other amount: a viscous force that did
// not act as nu times its lattice eigenvalue on these particles (a disordered set, a wrong eps
// scaling) would give another ratio. Tolerance 0.002, a fifth of the effect. A few seconds.
TEST(AnalyticWcsphTvf, TaylorGreenWithBAndTheLimitedShiftDecaysAtTheLatticeRateOfItsViscousForce) {
  const int n = 40;
  auto rate = [&](double eps) {
    Params prm = case_defaults("taylor_green", "wcsph_tvf");
    prm["n_side"] = std::int64_t{n};
    prm["t_end"] = 1.0;
    prm["perturb"] = 0.3;
    prm["riemann_dissipation"] = std::string("none");
    prm["tvf"] = std::string("limited");
    prm["kernel_correction"] = true;
    prm["viscous_eps"] = eps;
    const RunResult r = find_case("taylor_green")->run(prm, RunContext{});
    EXPECT_EQ(r.status, RunStatus::Done) << r.message;
    return metric(r, "ke_rate");
  };
  const double dx = 1.0 / n, h = 1.3 * dx;
  const WendlandC2<2> W(h);
  auto lambda = [&](double eps) {
    return tgv_eigenvalue(dx, W.support(),
                          [&](double r) { return -2 * dx * dx * W.dW(r) / (r + eps * h); });
  };
  const double predicted = lambda(0.0) / lambda(0.01);
  EXPECT_NEAR(predicted, 1.0105, 5e-4); // the lattice sums themselves
  const double measured = rate(0.0) / rate(0.01);
  std::printf("ke_rate(eps 0) / ke_rate(eps 0.01) %.5f, lattice eigenvalues %.5f\n", measured,
              predicted);
  EXPECT_NEAR(measured, predicted, 0.002);
}
