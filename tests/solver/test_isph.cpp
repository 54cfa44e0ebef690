// Tests of the ISPH scheme (schemes/isph), the cavity cases and their diagnostics.
#include "case_helpers.hpp"
#include "cases/case.hpp"
#include "cases/cavity.hpp"
#include "core/kernels/cubic_spline.hpp"
#include "core/kernels/kernel.hpp"
#include "diagnostics/cavity_profiles.hpp"
#include "schemes/isph/isph.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

using namespace sph;
using sph::testing::metric;

namespace {

Params defaults(const std::string& case_name) {
  return sph::testing::case_defaults(case_name, "isph");
}

} // namespace

TEST(Cavity, GeometryHasLayersLidAndCylinder) {
  Particles<2> p;
  CavityGeometry g;
  g.dx = 0.1, g.layers = 3;
  const int f = build_cavity(p, g);
  std::size_t nf = 0, nw = 0, nlid = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    nf += p.kind[i] == Kind::Fluid, nw += p.kind[i] == Kind::Wall;
    if (p.vector(f)[i].x() == 1.0) {
      ++nlid;
      EXPECT_GT(p.r[i].y(), 1.0);
    }
  }
  EXPECT_EQ(nf, 100u);
  EXPECT_EQ(nw, 16u * 16u - 100u);
  EXPECT_EQ(nlid, 3u * 16u);
  // lid_corners = "resting": only the 3 x 10 lid particles above 0 < x < 1 move.
  Particles<2> r;
  g.lid_corners_move = false;
  const int fr = build_cavity(r, g);
  std::size_t nlid_r = 0;
  for (std::size_t i = 0; i < r.size(); ++i)
    if (r.vector(fr)[i].x() == 1.0) {
      ++nlid_r;
      EXPECT_GT(r.r[i].y(), 1.0);
      EXPECT_GT(r.r[i].x(), 0.0);
      EXPECT_LT(r.r[i].x(), 1.0);
    }
  EXPECT_EQ(nlid_r, 3u * 10u);
  g.lid_corners_move = true;
  Particles<2> q;
  g.cylinder_d = 0.5;
  build_cavity(q, g);
  for (std::size_t i = 0; i < q.size(); ++i)
    if (q.kind[i] == Kind::Fluid)
      EXPECT_GE((q.r[i] - Vec2(0.5, 0.5)).norm(), 0.25);
  Particles<2> bad;
  g.dx = 0.03;
  EXPECT_THROW(build_cavity(bad, g), std::invalid_argument);
}

TEST(Profiles, ShepardReproducesConstantAndLinearFieldsOnLattice) {
  Particles<2> p;
  CavityGeometry g;
  g.dx = 0.05;
  build_cavity(p, g);
  for (std::size_t i = 0; i < p.size(); ++i)
    p.v[i] = Vec2(0.3, 2.0 * p.r[i].x() - 1.0);
  CubicSpline<2> W(1.2 * g.dx);
  // Lattice-symmetric points (cell corners and centres) with full support: exact for linear.
  std::vector<Vec2> pts{{0.5, 0.5}, {0.25, 0.75}, {0.525, 0.325}};
  auto u = shepard_sample<2>(p, W, pts, [](std::size_t) { return true; });
  for (std::size_t k = 0; k < pts.size(); ++k) {
    EXPECT_NEAR(u[k].x(), 0.3, 1e-14);
    EXPECT_NEAR(u[k].y(), 2.0 * pts[k].x() - 1.0, 1e-13);
  }
}

// A fluid at rest with walls at rest stays at rest, with uniform pressure.
TEST(Isph, RestStaysAtRest) {
  Particles<2> p;
  CavityGeometry g;
  g.dx = 0.05, g.U0 = 0.0;
  const int f = build_cavity(p, g);
  CubicSpline<2> W(1.2 * g.dx);
  IsphOptions opt;
  Isph<2, CubicSpline<2>> s(p, Domain<2>{}, W, opt, f, 1e-3, 1e-3, g.dx);
  for (int k = 0; k < 3; ++k)
    s.step();
  // The pressure level is arbitrary (regularised pure-Neumann problem): check its variation.
  double vmax = 0, pmin = 1e300, pmax = -1e300;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == Kind::Fluid)
      vmax = std::max(vmax, p.v[i].norm()), pmax = std::max(pmax, p.p[i]),
      pmin = std::min(pmin, p.p[i]);
  EXPECT_LT(vmax, 1e-12);
  EXPECT_LT(pmax - pmin, 1e-9);
}

// The wall-clearance safety net (step 8 of Isph::step): a fluid particle put 0.3 dx from a wall
// particle and moving towards it ends the step exactly wall_clearance dx = 0.5 dx from it, without
// the velocity component towards it, and the step counts one correction
// (`wall_clearance_corrections`, a metric of every ISPH job); with wall_clearance = 0 nothing
// moves it and nothing is counted (the step itself moves it by about u dt = 2e-4 dx).
TEST(Isph, WallClearanceMovesAndCountsTheParticle) {
  for (double clearance : {0.5, 0.0}) {
    SCOPED_TRACE("wall_clearance " + std::to_string(clearance));
    Particles<2> p;
    CavityGeometry g;
    g.dx = 0.05, g.U0 = 0.0;
    const int f = build_cavity(p, g);
    const Vec2 wall(0.025, -0.025); // the wall particle below the first fluid particle
    std::int64_t moved = -1;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid && (p.r[i] - Vec2(0.025, 0.025)).norm() < 1e-12) {
        p.r[i] = wall + Vec2(0.0, 0.3 * g.dx);
        p.v[i] = Vec2(0.0, -0.1);
        moved = p.id[i];
      }
    ASSERT_GE(moved, 0);
    CubicSpline<2> W(1.2 * g.dx);
    IsphOptions opt;
    opt.shifting = false;
    opt.alpha_ppe = 0.0;
    opt.wall_clearance = clearance;
    Isph<2, CubicSpline<2>> s(p, Domain<2>{}, W, opt, f, 1e-3, 1e-4, g.dx);
    s.step();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.id[i] == moved) {
        const Vec2 d = p.r[i] - wall;
        if (clearance > 0.0) {
          EXPECT_NEAR(d.norm(), 0.5 * g.dx, 1e-12);
          EXPECT_GE(p.v[i].dot(d / d.norm()), -1e-12);
        } else {
          EXPECT_NEAR(d.norm(), 0.3 * g.dx, 1e-3 * g.dx);
        }
      }
    EXPECT_EQ(s.clearance_corrections(), clearance > 0.0 ? 1 : 0);
    // When and where it fired first (step 0, the particle's corrected position), in one step.
    EXPECT_EQ(s.clearance_steps(), clearance > 0.0 ? 1 : 0);
    EXPECT_EQ(s.clearance_first_step(), clearance > 0.0 ? 0 : -1);
    if (clearance > 0.0)
      EXPECT_NEAR((s.clearance_first_r() - (wall + Vec2(0.0, 0.5 * g.dx))).norm(), 0.0,
                  1e-3 * g.dx);
  }
}

// The gap between two neighbouring wall particles (dx apart): a fluid particle 0.1 dx above the
// bottom row's line, midway between two of its particles, moving into the wall, is 0.51 dx from
// both, so wall_clearance = 0.5 alone does not stop it (it ends the step inside the wall band,
// y < 0, uncorrected). With wall_clearance_gaps it is kept 0.5 dx from the gap's midpoint: back on
// the fluid side (y = 0), its velocity into the wall removed, one correction counted.
TEST(Isph, WallClearanceGapsCloseTheGapBetweenWallParticles) {
  for (bool gaps : {false, true}) {
    SCOPED_TRACE(gaps ? "wall_clearance_gaps" : "particles only");
    Particles<2> p;
    CavityGeometry g;
    g.dx = 0.05, g.U0 = 0.0;
    const int f = build_cavity(p, g);
    const Vec2 gap(0.05, -0.025); // midpoint of the wall particles (0.025, -0.025), (0.075, -0.025)
    std::int64_t moved = -1;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid && (p.r[i] - Vec2(0.025, 0.025)).norm() < 1e-12) {
        p.r[i] = gap + Vec2(0.0, 0.1 * g.dx);
        p.v[i] = Vec2(0.0, -0.1);
        moved = p.id[i];
      }
    ASSERT_GE(moved, 0);
    CubicSpline<2> W(1.2 * g.dx);
    IsphOptions opt;
    opt.shifting = false;
    opt.alpha_ppe = 0.0;
    opt.wall_clearance_gaps = gaps;
    Isph<2, CubicSpline<2>> s(p, Domain<2>{}, W, opt, f, 1e-3, 1e-4, g.dx);
    s.step();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.id[i] == moved) {
        if (gaps) {
          const Vec2 d = p.r[i] - gap;
          EXPECT_NEAR(d.norm(), 0.5 * g.dx, 1e-12);
          EXPECT_GT(p.r[i].y(), -1e-3 * g.dx);
          EXPECT_GE(p.v[i].dot(d / d.norm()), -1e-12);
        } else {
          EXPECT_LT(p.r[i].y(), 0.0);
          EXPECT_NEAR(p.r[i].y(), gap.y() + 0.1 * g.dx, 1e-3 * g.dx);
        }
      }
    EXPECT_EQ(s.clearance_corrections(), gaps ? 1 : 0);
  }
}

// The projection removes a pure gradient field: u* = grad phi, phi = eps cos(pi x) cos(pi y), has
// zero normal velocity on the walls, so the exact projection is u = 0 and P = rho phi / dt. The
// discrete projection must remove most of it; UMFPACK and BiCGSTAB (ILUT, ILU(0), Jacobi) must give
// the same pressure.
TEST(Isph, ProjectionRemovesGradientFieldAndSolversAgree) {
  std::vector<double> pressure[4];
  int run = 0;
  const double pi = std::acos(-1.0), eps = 0.01;
  for (auto kind : {PpeSolverKind::Umfpack, PpeSolverKind::BicgstabIlut,
                    PpeSolverKind::BicgstabIlu0, PpeSolverKind::BicgstabJacobi}) {
    Particles<2> p;
    CavityGeometry g;
    g.dx = 0.025, g.U0 = 0.0;
    const int f = build_cavity(p, g);
    double u0max = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid) {
        const double x = p.r[i].x(), y = p.r[i].y();
        p.v[i] = -eps * pi *
                 Vec2(std::sin(pi * x) * std::cos(pi * y), std::cos(pi * x) * std::sin(pi * y));
        u0max = std::max(u0max, p.v[i].norm());
      }
    CubicSpline<2> W(1.2 * g.dx);
    IsphOptions opt;
    opt.solver = kind;
    opt.ppe_tol = 1e-12;
    opt.shifting = false;
    opt.alpha_ppe = 0.0;
    Isph<2, CubicSpline<2>> s(p, Domain<2>{}, W, opt, f, 1e-9, 1e-3, g.dx);
    s.set_measure_divergence(true);
    s.step();
    double umax = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid)
        umax = std::max(umax, p.v[i].norm());
    // div u* = -2 pi^2 eps cos cos, up to 0.197. Away from the walls (> 2h) the projection removes
    // more than 95 % of it; the wall particles' extrapolated pressure is only first-order at the
    // corners, where it removes about 80 % (measured 0.041 at dx = 0.025).
    const double div0 = 2 * pi * pi * eps;
    double div_int = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec2 x = p.r[i];
      if (p.kind[i] == Kind::Fluid && x.minCoeff() > 2.4 * g.dx && x.maxCoeff() < 1 - 2.4 * g.dx)
        div_int = std::max(div_int, std::abs(s.divergence()[i]));
    }
    EXPECT_LT(div_int, 0.05 * div0) << run;
    EXPECT_LT(s.div_max(), 0.25 * div0) << run << " at " << s.div_argmax().transpose();
    EXPECT_LT(umax, 0.1 * u0max) << run;
    EXPECT_LT(s.ppe_residual(), 1e-10);
    std::vector<double> pr(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      pr[p.id[i]] = p.p[i];
    pressure[run++] = pr;
  }
  // The regularised level (see isph.hpp) is the same for every solver; compare pressures.
  for (int k : {1, 2, 3}) {
    double dmax = 0, pmax = 0;
    for (std::size_t i = 0; i < pressure[0].size(); ++i)
      dmax = std::max(dmax, std::abs(pressure[0][i] - pressure[k][i])),
      pmax = std::max(pmax, std::abs(pressure[0][i]));
    EXPECT_GT(pmax, 0.0);
    EXPECT_LT(dmax, 1e-6 * pmax) << k;
  }
}

// The AMG-preconditioned solvers on a real cavity PPE system (lid-driven, Re = 100, dx = 0.02,
// after 10 steps from rest): the system of the 11th step, captured from the scheme, solved by
// BiCGSTAB + ILU(0), BiCGSTAB + BoomerAMG and GMRES + BoomerAMG from the same warm start. At the
// default tolerance every solution's true residual meets it, so |A (x_amg - x_ilu0)| <= 2 tol |b|
// (the two agree to the tolerance in the norm the tolerance is stated in); at tol 1e-10 the
// pressures agree pointwise to 1e-6 of their range. Iterations at the default tolerance <= 10.
TEST(Isph, AmgSolversMatchIlu0OnCavityPpe) {
  Particles<2> p;
  CavityGeometry g;
  g.dx = 0.02;
  const int f = build_cavity(p, g);
  CubicSpline<2> W(1.2 * g.dx);
  IsphOptions opt;
  Isph<2, CubicSpline<2>> s(p, Domain<2>{}, W, opt, f, 1e-2, 2e-3, g.dx);
  for (int k = 0; k < 10; ++k)
    s.step();
  const std::vector<double> x0 = p.p; // the warm start of the next solve
  s.step();
  const PpeSolver& sys = s.ppe();
  const std::vector<double> b = sys.last_rhs();
  const int n = static_cast<int>(b.size());
  ASSERT_EQ(n, static_cast<int>(p.size()));
  auto residual = [&](const std::vector<double>& x, const std::vector<double>& rhs) {
    double r2 = 0.0;
    for (int i = 0; i < n; ++i) {
      double a = -rhs[i];
      for (int q = sys.offset[i]; q < sys.offset[i + 1]; ++q)
        a += sys.val[q] * x[sys.col[q]];
      r2 += a * a;
    }
    return std::sqrt(r2);
  };
  double bn = 0.0;
  for (double v : b)
    bn += v * v;
  bn = std::sqrt(bn);
  ASSERT_GT(bn, 0.0);
  for (double tol : {1e-6, 1e-10}) {
    std::vector<std::vector<double>> x;
    for (auto kind :
         {PpeSolverKind::BicgstabIlu0, PpeSolverKind::BicgstabAmg, PpeSolverKind::GmresAmg}) {
      PpeSolver ppe(kind, tol, 1000);
      ppe.offset = sys.offset, ppe.col = sys.col, ppe.val = sys.val;
      std::vector<double> xi = x0;
      const int it = ppe.solve(b, xi);
      EXPECT_LE(ppe.last_error(), tol) << static_cast<int>(kind);
      // Eigen's BiCGSTAB stops on its recursive residual: the true one within 10 %.
      EXPECT_LE(residual(xi, b), 1.1 * tol * bn) << static_cast<int>(kind) << " tol " << tol;
      if (kind != PpeSolverKind::BicgstabIlu0 && tol > 1e-7) // issue 21's target
        EXPECT_LE(it, 10) << static_cast<int>(kind) << " tol " << tol;
      x.push_back(xi);
    }
    const std::vector<double> zero(n, 0.0);
    for (int k : {1, 2}) {
      std::vector<double> d(n);
      for (int i = 0; i < n; ++i)
        d[i] = x[k][i] - x[0][i];
      EXPECT_LE(residual(d, zero), 2.2 * tol * bn) << k << " tol " << tol;
      if (tol < 1e-9) {
        const auto [lo, hi] = std::minmax_element(x[0].begin(), x[0].end());
        double dmax = 0.0;
        for (double v : d)
          dmax = std::max(dmax, std::abs(v));
        EXPECT_GT(*hi - *lo, 0.0);
        EXPECT_LT(dmax, 1e-6 * (*hi - *lo)) << k;
      }
    }
  }
}

// The same short cavity job with bicgstab_amg (hierarchy reused across steps) and gmres_amg gives
// the flow metrics of bicgstab_ilu0 within a bound set by the solver tolerance. Each solve leaves
// a residual r with |r| <= tol |b|; b is div u* / dt (plus the small density term), so the
// divergence the projection leaves differs between two solvers by at most 2 tol |div u*| per
// step, and the velocity by dt |grad delta P| <= about 2 tol U0 (the lowest Neumann mode,
// |grad A^-1| ~ 1 / pi on the unit square, div u* of order U0 / dx over the lid band, times dx).
// Over n steps, without amplification at Re = 100: |delta u| <= 2 n tol U0; the bound used is
// 10 n tol U0 (a factor 5 for the pointwise Shepard samples against the norm). Measured: about
// 8e-9 for 20 steps at tol 1e-6 (bound 2e-4): the bound is a worst case.
TEST(LidDrivenCavity, AmgSolversGiveIlu0Metrics) {
  Params prm = defaults("lid_driven_cavity");
  prm["dx"] = 0.05, prm["t_end"] = 0.1, prm["dt"] = 0.005, prm["Re"] = 100.0;
  const double tol = get_real(prm, "ppe_tol"), n = 20.0, U0 = 1.0;
  const double bound = 10.0 * n * tol * U0;
  std::map<std::string, double> ref;
  for (const char* solver : {"bicgstab_ilu0", "bicgstab_amg", "gmres_amg"}) {
    prm["ppe_solver"] = std::string(solver);
    RunResult r = find_case("lid_driven_cavity")->run(prm, RunContext{});
    ASSERT_EQ(r.status, RunStatus::Done) << solver << ": " << r.message;
    EXPECT_EQ(metric(r, "steps"), n);
    int compared = 0;
    double dmax = 0.0;
    for (const auto& [k, v] : r.metrics) {
      // Velocities and their errors; not the positions of the extrema (ux_min_y, uy_max_x, ...).
      const bool flow = k.rfind("ux_", 0) == 0 || k.rfind("uy_", 0) == 0;
      const bool position = k.size() > 2 && (k.ends_with("_x") || k.ends_with("_y"));
      if (!flow || position)
        continue;
      if (ref.empty() || !ref.count(k)) {
        if (std::string(solver) == "bicgstab_ilu0")
          ref[k] = v;
        continue;
      }
      ++compared;
      dmax = std::max(dmax, std::abs(v - ref[k]));
      EXPECT_NEAR(v, ref[k], bound) << solver << " " << k;
    }
    if (std::string(solver) != "bicgstab_ilu0") {
      EXPECT_GT(compared, 30) << solver;
      EXPECT_LE(metric(r, "ppe_iters_mean"), 10.0) << solver;
      std::printf("%s: %d flow metrics, max |difference| to bicgstab_ilu0 %.2e (bound %.1e)\n",
                  solver, compared, dmax, bound);
    }
    EXPECT_GT(metric(r, "ppe_solve_s_per_step"), 0.0);
  }
}

// A short cavity run through the case interface records every profile metric.
TEST(LidDrivenCavity, ShortRunRecordsProfileMetrics) {
  Params prm = defaults("lid_driven_cavity");
  prm["dx"] = 0.1, prm["t_end"] = 0.2, prm["dt"] = 0.005, prm["Re"] = 100.0;
  RunResult r = find_case("lid_driven_cavity")->run(prm, RunContext{});
  ASSERT_EQ(r.status, RunStatus::Done) << r.message;
  EXPECT_GT(metric(r, "ux_at_y_0.9766"), 0.0);
  EXPECT_TRUE(std::isfinite(metric(r, "uy_at_x_0.0625")));
  EXPECT_LT(metric(r, "ux_min"), 0.0);
  // Value bands (issue 15): what this deterministic run measured (dx = 0.1, Re = 100, t = 0.2),
  // 3 % for floating-point differences between builds; a defect in the viscous term, the wall
  // velocity or the projection moves these early-time extrema by more (VISC-02 alone differs
  // from VISC-04 by 8 % in the quick tier).
  EXPECT_NEAR(metric(r, "ux_min"), -0.040423, 0.03 * 0.040423);
  EXPECT_NEAR(metric(r, "uy_max"), 0.020724, 0.03 * 0.020724);
  EXPECT_NEAR(metric(r, "uy_min"), -0.023332, 0.03 * 0.023332);
  EXPECT_NEAR(metric(r, "ke"), 0.0027047, 0.03 * 0.0027047);
  EXPECT_EQ(metric(r, "steps"), 40.0);
  EXPECT_GT(metric(r, "ppe_share"), 0.0);
  int n_ux = 0;
  for (const auto& [k, v] : r.metrics)
    n_ux += k.rfind("ux_at_y_", 0) == 0;
  EXPECT_EQ(n_ux, 17);
  // Re = 100 has Ghia's column: the errors are recorded (|ux_min - (-0.21090)| by definition).
  EXPECT_NEAR(metric(r, "ux_min_err"), std::abs(metric(r, "ux_min") + 0.21090), 1e-12);
  EXPECT_GT(metric(r, "ux_rms_err"), 0.0);
  EXPECT_GT(metric(r, "cpu_time_per_step_s"), 0.0);
  EXPECT_GE(metric(r, "div_max"), metric(r, "div_rms"));
}

// Ghia's columns: Re = 100 and 1000 only, and their minima are the minima of the tables.
TEST(Ghia, TablesAndMinima) {
  for (double Re : {100.0, 1000.0}) {
    const auto t = data::ghia_table(Re);
    ASSERT_TRUE(t.u && t.v);
    EXPECT_EQ(*std::min_element(t.u->begin(), t.u->end()), t.u_min);
    EXPECT_EQ((*t.u)[0], 1.0);
    EXPECT_EQ((*t.v)[0], 0.0);
  }
  EXPECT_EQ(data::ghia_table(400.0).u, nullptr);
}
