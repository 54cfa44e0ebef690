// The FDA nozzle's geometry and inflow (solver/core/axisymmetric_duct.hpp, solver/cases/
// fda_nozzle.cpp; Stewart et al. 2012, Cardiovasc. Eng. Technol. 3:139, Fig. 1):
//   1. The body-fitted rings: every slice's lumen volumes add up to pi R(x)^2 dx (pipe, cone,
//      throat), the walls stay outside the lumen and within their thickness of the wall line, and
//      the radius and distance of a sudden step are those of the polyline.
//   2. The case at a coarse spacing through its interface: the fluid in the throat's slices has
//      the throat's volume pi R_t^2 L_t (R_t = 2 mm, L_t = 40 mm) and the whole lumen the
//      benchmark's (pipes, 10 degree cone, throat) within 2 %, and the inlet's rows impose the
//      benchmark's flow rate Q = 5.206e-6 m^3/s (throat Re = 500) within 2 %.
#include "case_helpers.hpp"
#include "core/axisymmetric_duct.hpp"
#include "core/kernels/wendland_c2.hpp"
#include "diagnostics/profiles.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

namespace {

using namespace sph;
using sph::testing::case_defaults;
using sph::testing::metric;

TEST(AxisymmetricDuct, SlicesHoldTheLumensVolumeAndWallsLieOutsideWithinTheirThickness) {
  const double pi = std::numbers::pi, dx = 0.3, thick = 0.9;
  // Pipe R = 3, cone to R = 1 over x in [2, 6), throat to x = 9, step back to R = 3.
  const AxisymmetricDuct d({2.0, 6.0, 9.0, 9.0}, {3.0, 1.0, 1.0, 3.0});
  EXPECT_DOUBLE_EQ(d.radius(0.0), 3.0);
  EXPECT_DOUBLE_EQ(d.radius(4.0), 2.0);
  EXPECT_DOUBLE_EQ(d.radius(8.9), 1.0);
  EXPECT_DOUBLE_EQ(d.radius(9.0), 3.0);                  // the step belongs to the wider side
  EXPECT_NEAR(d.distance_to_wall(8.5, 2.0), 0.5, 1e-12); // nearest: the step's face
  EXPECT_NEAR(d.distance_to_wall(0.0, 2.5), 0.5, 1e-12); // the inlet pipe
  const int n = 40;
  const auto pts = d.particles(0.0, n, dx, thick);
  std::map<int, double> lumen;
  int walls = 0;
  for (const auto& q : pts) {
    const double rho = std::hypot(q.r.y(), q.r.z());
    const int s = static_cast<int>(std::floor(q.r.x() / dx));
    if (q.fluid) {
      EXPECT_LT(rho, d.radius(q.r.x()));
      lumen[s] += q.V;
    } else {
      ++walls;
      EXPECT_GE(rho, d.radius(q.r.x()));
      EXPECT_LT(d.distance_to_wall(q.r.x(), rho), thick);
    }
  }
  EXPECT_GT(walls, 0);
  ASSERT_EQ(static_cast<int>(lumen.size()), n);
  for (const auto& [s, V] : lumen) {
    const double R = d.radius((s + 0.5) * dx);
    EXPECT_NEAR(V, pi * R * R * dx, 1e-12 * pi * R * R * dx) << s;
  }
  // The ring spacing is about dx: a ring's particles are dx apart along it, within 30 %.
  for (const auto& q : d.section(1.0, dx)) {
    const double rho = std::hypot(q.r.y(), q.r.z());
    if (rho > dx) {
      const int n_ring = static_cast<int>(std::lround(2 * pi * rho / dx));
      EXPECT_NEAR(2 * pi * rho / n_ring, dx, 0.3 * dx);
    }
  }
}

// The walls' normals (wall_dissipation = normal): unit vectors into the fluid, radially inward on
// the pipes, perpendicular to the cone's line, along the axis on the step's face, from the corner
// where the face meets the outlet pipe; and at every wall particle unit length, pointing to the
// wall line.
TEST(AxisymmetricDuct, WallNormalsPointIntoTheFluidPerpendicularToTheWallLine) {
  const AxisymmetricDuct d({2.0, 6.0, 9.0, 9.0}, {3.0, 1.0, 1.0, 3.0});
  const double s = std::sqrt(0.5);
  auto expect = [](const Vec3& n, const Vec3& e) { EXPECT_NEAR((n - e).norm(), 0.0, 1e-12) << n; };
  expect(d.wall_normal(Vec3(0.5, 0.0, 3.2)), Vec3(0.0, 0.0, -1.0));      // the inlet pipe
  expect(d.wall_normal(Vec3(7.0, -s * 1.5, s * 1.5)), Vec3(0.0, s, -s)); // the throat
  expect(d.wall_normal(Vec3(8.8, 2.0, 0.0)), Vec3(1.0, 0.0, 0.0));       // the step's face
  expect(d.wall_normal(Vec3(8.7, 0.0, 1.05)), Vec3(0.0, 0.0, -1.0));     // throat, by the face
  expect(d.wall_normal(Vec3(8.8, 0.0, 3.2)), Vec3(s, 0.0, -s)); // from the face's outer corner
  // The cone (R from 3 to 1 over 4, the line's direction (2, -1) / sqrt(5) in (x, rho)): the
  // normal into the fluid (-1, -2) / sqrt(5), inward and facing upstream.
  const Vec3 nc = d.wall_normal(Vec3(4.0, 0.0, 2.0 + 0.5 * std::sqrt(5.0)));
  expect(nc, Vec3(-1.0, 0.0, -2.0) / std::sqrt(5.0));
  for (const auto& q : d.particles(0.0, 40, 0.3, 0.9)) {
    if (q.fluid)
      continue;
    const Vec3 n = d.wall_normal(q.r);
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    const double rho = std::hypot(q.r.y(), q.r.z());
    const double dw = d.distance_to_wall(q.r.x(), rho);
    const Vec3 w = q.r + dw * n; // on the wall line
    EXPECT_NEAR(d.distance_to_wall(w.x(), std::hypot(w.y(), w.z())), 0.0, 1e-9) << q.r;
  }
}

// What the case's centreline metric reads for an exact throat flow (docs/fda_nozzle.md): the
// throat's particles as the case places them (body-fitted rings, walls at rest three layers
// thick), the lumen rings on the ring-averaged fully developed Poiseuille profile of the
// benchmark's flow rate (u = 2 U_t (1 - (rho^2 + dr^2 / 4) / R^2), centre 2 U_t = 0.829 m/s), and
// the case's sampler (Shepard, Wendland C2 at h = 1.3 dx, fluid and walls) on the axis: the kernel
// averages over a section only a few rings wide, so the sample is 26 % low at dx = 1 mm, 12 % at
// 0.667 mm, 4 % at 0.4 mm (the values the docs quote).
TEST(FdaNozzle, CentrelineSamplerOfAnExactPoiseuilleThroatIsLowByTheKernelsAverage) {
  const double R = 0.002, U_t = 0.4143;
  const AxisymmetricDuct throat({0.0, 0.04}, {R, R});
  auto sampled = [&](double dx) {
    const double h = 1.3 * dx, dr = throat.ring_spacing(0.02, dx);
    const WendlandC2<3> W(h);
    Particles<3> p;
    for (const auto& q : throat.particles(0.02 - 10 * dx, 20, dx, std::ceil(2 * h / dx) * dx)) {
      const std::size_t i = p.add(q.r, q.V, 1.0, q.fluid ? Kind::Fluid : Kind::Wall);
      p.V[i] = q.V;
      const double rho2 = q.r.y() * q.r.y() + q.r.z() * q.r.z();
      if (q.fluid)
        p.v[i] = Vec3(2 * U_t * (1 - (rho2 + dr * dr / 4) / (R * R)), 0.0, 0.0);
    }
    return shepard_sample<3>(p, W, {Vec3(0.02, 0.0, 0.0)}, [](std::size_t) { return true; })[0].x();
  };
  const double u1 = sampled(0.001), u2 = sampled(0.002 / 3), u3 = sampled(0.0004);
  EXPECT_NEAR(u1, 0.610, 0.001);
  EXPECT_NEAR(u2, 0.731, 0.001);
  EXPECT_NEAR(u3, 0.794, 0.001);
}

TEST(FdaNozzle, ThroatAndLumenHaveTheBenchmarksVolumeAndTheInletImposesItsFlowRate) {
  Params prm = case_defaults("fda_nozzle", "wcsph_tvf");
  prm["dx"] = 0.001;
  prm["upstream_length"] = 0.004;
  prm["downstream_length"] = 0.006;
  prm["ramp_time"] = 0.002;
  prm["t_end"] = 0.003;
  prm["flux_window"] = 0.0;
  const RunResult r = find_case("fda_nozzle")->run(prm, RunContext{});
  ASSERT_EQ(r.status, RunStatus::Done) << r.message;
  // The benchmark's numbers, not the case's constants: throat 4 mm across and 40 mm long; the
  // lumen from the inlet (4 mm of pipe before the cone) to 6 mm past the expansion: pipes of
  // radius 6 mm, the cone's frustum over 4 mm / tan(10 deg); the flow rate of the PIV files.
  const double pi = std::numbers::pi, L_c = 0.004 / std::tan(10.0 * pi / 180.0);
  const double V_throat = pi * 0.002 * 0.002 * 0.040;
  const double V_lumen = pi * 0.006 * 0.006 * (0.004 + 0.006) + V_throat +
                         pi / 3.0 * L_c * (0.006 * 0.006 + 0.006 * 0.002 + 0.002 * 0.002);
  EXPECT_NEAR(metric(r, "throat_volume") / V_throat, 1.0, 0.02);
  EXPECT_NEAR(metric(r, "fluid_volume") / V_lumen, 1.0, 0.02);
  EXPECT_NEAR(metric(r, "inflow_rate") / 5.20624e-6, 1.0, 0.02);
}

} // namespace
