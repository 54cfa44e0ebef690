// Tests of the open-boundary pieces (boundaries/open_boundary.hpp) and of the free_stream_box case
// (issue 19 section 1):
//  - the emitter turns a buffer particle past x_in into fluid and puts its replacement
//    layers * dx upstream on the same row, so the emitted lattice keeps the spacing dx on every
//    row, also with a velocity that varies across the inlet (a parabolic profile, issue 18);
//  - the disposer turns fluid past x_out into outlet buffer and deletes buffer particles past
//    x_out + layers * dx and fluid outside its keep box;
//  - the free-stream surface indicator marks the two outer rows of a slab and no interior row;
//    the near-surface density rule and the velocity correction give their formulas' values;
//  - a uniform free stream through the empty box, from a disturbed start, becomes and stays
//    uniform over 25 flow-throughs, with the particle count steady and the mass fluxes balanced;
//  - two resolution levels (boundaries/refinement.hpp, issue 19 section 2): a coarse lattice
//    moved into the fine region splits into the fine lattice exactly, and merges back into the
//    coarse one exactly when the region moves away; mass and momentum are kept to round-off with
//    random velocities; the hysteresis leaves particles near the interface alone; h follows the
//    mass; the free-stream domain emits each level on its own rows.
#include "boundaries/free_stream_domain.hpp"
#include "boundaries/open_boundary.hpp"
#include "boundaries/refinement.hpp"
#include "cases/case.hpp"
#include "core/kernels/wendland_c2.hpp"
#include "core/lattice.hpp"
#include "schemes/wcsph_tvf/wcsph_tvf.hpp"

#include <gtest/gtest.h>

#include <map>

using namespace sph;
using namespace sph::open_boundary;
using V2 = Vec<2>;

namespace {

// Parabolic inflow across [0, H]: 1.5 U 4 y (H - y) / H^2 (mean U).
V2 parabolic(const V2& r, double) {
  const double H = 1.0;
  return V2(6.0 * r[1] * (H - r[1]) / (H * H), 0.0);
}

} // namespace

TEST(Emitter, EmitsEveryRowOnTheLatticeWithAProfile) {
  Emitter<2>::Config c;
  c.x_in = 0.0, c.layers = 4, c.dx = 0.1, c.hi = {0, 10}, c.u_in = parabolic;
  Emitter<2> e(c);
  Particles<2> p;
  std::int64_t id = 0;
  e.fill(p, 0.0, id);
  ASSERT_EQ(p.size(), 40u);
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(p.kind[i], Kind::Buffer);
    EXPECT_LT(p.r[i][0], 0.0);
    EXPECT_GT(p.r[i][0], -0.4);
  }
  // Drift with the prescribed velocity (as the scheme does) and emit, many times.
  const double dt = 0.013;
  std::size_t emitted = 0;
  for (int s = 0; s < 200; ++s) {
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Buffer)
        p.r[i] += dt * p.v[i];
      else
        p.r[i] += dt * parabolic(p.r[i], 0.0); // the fluid carries on at the same speed
    emitted += e.update(p, s * dt, id);
  }
  // Every row: buffer and fluid together a lattice of spacing dx along x.
  std::map<double, std::vector<double>> rows;
  for (std::size_t i = 0; i < p.size(); ++i) {
    rows[std::round(p.r[i][1] * 1e6)].push_back(p.r[i][0]);
    if (p.kind[i] == Kind::Buffer) {
      EXPECT_LT(p.r[i][0], 0.0);
      EXPECT_GE(p.r[i][0], -0.4);
      EXPECT_EQ(p.v[i], parabolic(p.r[i], 0.0));
    } else {
      EXPECT_GE(p.r[i][0], 0.0);
    }
  }
  ASSERT_EQ(rows.size(), 10u);
  for (auto& [y, xs] : rows) {
    std::sort(xs.begin(), xs.end());
    EXPECT_GE(xs.size(), 4u);
    for (std::size_t k = 1; k < xs.size(); ++k)
      EXPECT_NEAR(xs[k] - xs[k - 1], 0.1, 1e-12) << "row y = " << y * 1e-6;
  }
  EXPECT_EQ(p.size(), 40u + emitted);
  EXPECT_NEAR(e.mass_in(), emitted * 0.01, 1e-12);
  // The middle rows (u = 1.5 U) emitted about 1.5 * 200 * 0.013 / 0.1 = 39 particles each.
  EXPECT_NEAR(static_cast<double>(rows.rbegin()->second.size() + rows.begin()->second.size()),
              2.0 * (4.0 + 6.0 * 0.05 * 0.95 * 200 * dt / 0.1), 2.0);
}

TEST(Disposer, ConvertsDeletesAndCounts) {
  Disposer<2>::Config c;
  c.x_out = 1.0, c.layers = 4, c.dx = 0.1, c.p_out = 0.0;
  c.keep_lo = V2(-1e300, -0.5), c.keep_hi = V2(1e300, 1.5);
  Disposer<2> d(c);
  Particles<2> p;
  zone_field(p);
  p.add(V2(0.5, 0.5), 0.01, 1.0);  // fluid inside: stays
  p.add(V2(1.05, 0.5), 0.01, 1.0); // fluid past x_out: outlet buffer
  p.add(V2(0.5, 1.7), 0.01, 1.0);  // fluid outside the keep box: lost
  const std::size_t b = p.add(V2(1.45, 0.5), 0.01, 1.0, Kind::Buffer); // past x_out + 0.4: deleted
  p.scalar(zone_field(p))[b] = 2.0;
  p.p[1] = 0.3;
  EXPECT_TRUE(d.update(p));
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p.kind[0], Kind::Fluid);
  EXPECT_EQ(p.kind[1], Kind::Buffer);
  EXPECT_EQ(p.p[1], 0.0);
  EXPECT_NEAR(d.mass_out(), 0.01, 1e-15);
  EXPECT_NEAR(d.mass_lost(), 0.01, 1e-15);
  EXPECT_FALSE(d.update(p)); // nothing more to delete
}

namespace {

// A slab of nx x ny fluid particles, periodic in x, free at y = 0 and y = ny dx.
struct Slab {
  static constexpr int nx = 24, ny = 20;
  static constexpr double dx = 0.1, h = 1.3 * dx, rho0 = 1.0;
  Particles<2> p;
  Domain<2> box;
  WendlandC2<2> W{h};
  NeighborList<2> nl;
  Slab() {
    for_each_lattice_point<2>({0, 0}, {nx, ny}, dx, [&](const V2& x, const std::array<int, 2>&) {
      p.add(x, rho0 * dx * dx, rho0);
    });
    box.hi = V2(nx * dx, 10.0), box.periodic = {true, false};
    CellList<2> cells(box, W.support());
    cells.build(p);
    nl.build(cells, p.r, W);
  }
  int row(std::size_t i) const { return static_cast<int>(std::floor(p.r[i][1] / dx)); }
  // The density summation of wcsph_tvf (eq. 8).
  void summation() {
    std::vector<double> sumW(p.size());
    wcsph_tvf::ops::DensitySummation<2> op{p, W.W(0.0), rho0,
                                           wcsph_tvf::lattice_number_density<2>(W, dx), sumW};
    interact(nl, op);
  }
};

FreeStream<2>::Config fs_config() {
  FreeStream<2>::Config c;
  c.rho0 = Slab::rho0, c.h = Slab::h, c.u_inf = [](const V2&, double) { return V2(1.0, 0.0); };
  return c;
}

} // namespace

// The indicator (position divergence below 0.75 D, or a neighbour within h below it) marks the
// two outer rows on each side, nothing inside; the density rule keeps the continuity density
// where the summation's support is cut, the summation elsewhere; the velocity correction pulls
// the stream component of surface particles towards U by the summation's deficit.
TEST(FreeStream, IndicatorDensityAndVelocity) {
  Slab s;
  FreeStream<2> fs(s.p, fs_config());
  for (auto& r : s.p.rho)
    r = 1.01; // what the continuity equation gave
  fs.indicate(s.p, s.nl);
  const auto& ind = s.p.scalar(fs.indicator_field());
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    const int k = s.row(i);
    EXPECT_EQ(ind[i], (k < 2 || k >= Slab::ny - 2) ? 1.0 : 0.0) << "row " << k;
  }
  s.summation();
  const std::vector<double> rho_sum = s.p.rho;
  fs.density(s.p, s.nl);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    const int k = s.row(i), edge = std::min(k, Slab::ny - 1 - k);
    const double rs = rho_sum[i];
    if (edge >= 4) { // no indicated neighbour within the support (2.6 dx): the summation
      EXPECT_NEAR(rs, 1.0, 1e-12);
      EXPECT_EQ(s.p.rho[i], rs);
    } else if (rs < 1.01) { // near the surface with a cut support
      EXPECT_NEAR(s.p.rho[i], rs + (1.01 - rs) / 1.01, 1e-14) << "row " << k;
      EXPECT_NEAR(s.p.V[i], s.p.m[i] / s.p.rho[i], 1e-15);
    }
    if (edge == 0)
      EXPECT_LT(rs, 0.8); // the outer row's summation misses about a third of its support
  }
  for (auto& v : s.p.v)
    v = V2(1.2, 0.3);
  fs.velocity(s.p, 0.0);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    const double expect_x = ind[i] != 0.0 ? 1.0 + 0.2 * std::min(rho_sum[i], 1.0) : 1.2;
    EXPECT_NEAR(s.p.v[i][0], expect_x, 1e-14);
    EXPECT_EQ(s.p.v[i][1], 0.3); // only the stream component is corrected
    if (s.row(i) == 0)
      EXPECT_LT(s.p.v[i][0], 1.16); // pulled most of the way towards U = 1
  }
}

// The spatio-temporal filter: a void opened inside the bulk (particles removed) is not a free
// surface when no particle around it was on the surface the step before.
// The outlet buffer's velocity (BufferVelocity): the stream component of the Shepard average of
// the fluid around each buffer particle, computed here by brute force over the fluid within the
// support; no transverse component; a backflow cut to zero. The top two rows of a slab are the
// buffer, the fluid below moves with u = (0.3 + 0.5 y, 0.2) and then with u = (-0.3 - 0.5 y, 0.2).
TEST(BufferVelocity, ShepardAverageOfTheFluidsStreamComponentWithoutBackflow) {
  Slab s;
  const int zk = zone_field(s.p);
  for (std::size_t i = 0; i < s.p.size(); ++i)
    if (s.row(i) >= Slab::ny - 2)
      s.p.kind[i] = Kind::Buffer, s.p.scalar(zk)[i] = 2.0;
  auto buffer = [&](std::size_t i) { return s.p.kind[i] == Kind::Buffer; };
  for (const double sign : {1.0, -1.0}) {
    for (std::size_t i = 0; i < s.p.size(); ++i)
      s.p.v[i] = buffer(i) ? V2(9.0, 9.0) : V2(sign * (0.3 + 0.5 * s.p.r[i][1]), 0.2);
    const std::vector<V2> v0 = s.p.v;
    BufferVelocity<2> op{s.p.kind, s.p.v};
    interact(s.nl, op, buffer);
    int checked = 0;
    for (std::size_t i = 0; i < s.p.size(); ++i) {
      if (!buffer(i)) {
        EXPECT_EQ(s.p.v[i], v0[i]); // the fluid is left alone
        continue;
      }
      double num = 0.0, den = 0.0;
      for (std::size_t j = 0; j < s.p.size(); ++j) {
        V2 d = s.p.r[i] - s.p.r[j];
        d[0] -= Slab::nx * Slab::dx * std::round(d[0] / (Slab::nx * Slab::dx)); // periodic in x
        if (buffer(j) || d.norm() >= s.W.support())
          continue;
        num += s.W.W(d.norm()) * v0[j][0], den += s.W.W(d.norm());
      }
      ASSERT_GT(den, 0.0);
      EXPECT_NEAR(s.p.v[i][0], std::max(num / den, 0.0), 1e-12) << i;
      EXPECT_EQ(s.p.v[i][1], 0.0);
      checked += sign > 0 && num / den > 0.3;
    }
    if (sign > 0)
      EXPECT_GT(checked, 0);
  }
}

TEST(FreeStream, AnInteriorVoidIsNotASurface) {
  Slab s;
  FreeStream<2> fs(s.p, fs_config());
  fs.indicate(s.p, s.nl); // the previous indicator: the outer rows only
  std::vector<char> keep(s.p.size(), 1);
  for (std::size_t i = 0; i < s.p.size(); ++i)
    keep[i] = (s.p.r[i] - V2(1.2, 1.0)).norm() > 0.16;
  s.p.keep_only(keep);
  CellList<2> cells(s.box, s.W.support());
  cells.build(s.p);
  s.nl.build(cells, s.p.r, s.W);
  fs.indicate(s.p, s.nl);
  const auto& ind = s.p.scalar(fs.indicator_field());
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    const int k = s.row(i);
    EXPECT_EQ(ind[i], (k < 2 || k >= Slab::ny - 2) ? 1.0 : 0.0) << "row " << k;
  }
}

namespace {

std::map<std::string, double> run_box(double t_end, double perturb, double settle,
                                      const char* inlet_pressure = "reference") {
  Params prm;
  for (const auto& sp : find_case("free_stream_box")->params)
    prm[sp.name] = sp.default_value;
  for (const auto& sp : find_scheme("wcsph_tvf")->params)
    prm[sp.name] = sp.default_value;
  prm["scheme"] = std::string("wcsph_tvf");
  prm["t_end"] = t_end, prm["perturb"] = perturb, prm["settle_fraction"] = settle;
  prm["inlet_pressure"] = std::string(inlet_pressure);
  const RunResult r = find_case("free_stream_box")->run(prm, RunContext{});
  EXPECT_EQ(r.status, RunStatus::Done) << r.message;
  return {r.metrics.begin(), r.metrics.end()};
}

} // namespace

// A uniform stream U through the empty box (L = 4, H = 2, dx = 0.1: 800 fluid particles, 20 rows)
// from a disturbed start (the initial fluid shifted at random by up to +-0.25 dx: densities and
// velocities off by several per cent), to t = 100: 25 flow-throughs. The window t >= 10 (2.5
// flow-throughs) starts after the initial fluid has left through the outlet buffer (t ~ 4.4) and
// its acoustic transient has passed (from t >= 5 the window still sees 0.013 U and 11 particles
// missing). Measured (2026-12-02): vel_err_max 0.0022 U (|v_y| the same), rho_err_max 2.3e-4
// rho0, both at the window's start, round-off (1e-14) at t = 100; fluid and total counts constant
// (800, 977); flux in = flux out to 2e-13, flux in = rho0 U H within 2.6e-4. Bounds about 4x the
// measured and far below what a broken boundary gives (docs/tvf.md: the mutations of
// scripts/mutations.txt).
TEST(FreeStreamBox, UniformStreamStaysUniform) {
  const auto m = run_box(100.0, 0.5, 0.1);
  EXPECT_LT(m.at("vel_err_max"), 0.01);
  EXPECT_LT(m.at("rho_err_max"), 0.001);
  EXPECT_LT(m.at("vel_err_rms_end"), 1e-6);
  EXPECT_LT(m.at("rho_err_rms_end"), 1e-6);
  // The fluid count within one particle per row (20 of 800), every particle (both buffers) within
  // 1 %; the fluxes in and out balance within 0.1 %, the inflow is rho0 U H within one column
  // over the window (dx / (U T) = 0.1 / 90).
  EXPECT_LE(m.at("n_fluid_band"), 20.0 / 800.0);
  EXPECT_LE(m.at("n_total_band"), 0.01);
  EXPECT_LT(std::abs(m.at("flux_imbalance")), 0.001);
  EXPECT_LT(std::abs(m.at("flux_in_rel_err")), 0.1 / 90.0);
  EXPECT_EQ(m.at("mass_lost"), 0.0);
  EXPECT_NEAR(m.at("flow_throughs"), 25.0, 1e-9);
  EXPECT_NEAR(m.at("surface_fraction_end"), 4.0 / 20.0, 1e-12); // two rows each side
}

// The inlet buffer's pressure extrapolated from the fluid (a zero normal gradient, for channels
// driven by their inflow, issue 18) instead of prescribed. The uniform stream is exact (from the
// lattice, 10 flow-throughs: errors 1e-13). From the disturbed start the disturbance does NOT
// leave as it does with the prescribed pressure: with the velocity imposed and the pressure free
// at the inlet, a pressure mode stays between the inlet and the outlet (measured 2026-12-02, window
// t >= 10 of 40: vel_err_max 0.051 U, RMS at t = 40 0.0045 U, fluid count band 3.5 %; at t = 100
// still 0.006 U: no decay; docs/tvf.md). Bounds: 2x the measured, so that a change of this
// behaviour (either way) shows.
TEST(FreeStreamBox, ExtrapolatedInletPressure) {
  const auto exact = run_box(40.0, 0.0, 0.0, "extrapolated");
  EXPECT_LT(exact.at("vel_err_max"), 1e-10);
  EXPECT_LT(exact.at("rho_err_max"), 1e-10);
  const auto m = run_box(40.0, 0.5, 0.25, "extrapolated");
  EXPECT_LT(m.at("vel_err_max"), 0.1);
  EXPECT_LT(m.at("rho_err_max"), 0.004);
  EXPECT_LT(m.at("vel_err_rms_end"), 0.01);
  EXPECT_GT(m.at("vel_err_rms_end"), 1e-4); // not cleared (see above)
  EXPECT_LE(m.at("n_fluid_band"), 0.07);
  EXPECT_LT(std::abs(m.at("flux_imbalance")), 0.001);
}

namespace {

// A coarse cell-centred lattice of spacing 2 dx_f in [0, 1]^2 with random velocities, and the
// two levels with the fine region {x0 < x}: depth x - x0, margin 0.1.
struct Levels {
  static constexpr double dx_f = 0.05;
  Particles<2> p;
  double x0 = -10.0; // the fine region's edge (moved by the tests)
  refinement::TwoLevels<2> lv;
  std::int64_t next_id = 0;
  Levels() : lv(fill(p), config(this)) {}
  static Particles<2>& fill(Particles<2>& p) {
    UniformRandom rn(3);
    for_each_lattice_point<2>({0, 0}, {10, 10}, 2 * dx_f, [&](const V2& x, const auto&) {
      const std::size_t k = p.add(x, 4 * dx_f * dx_f, 1.0 + 0.01 * rn());
      p.v[k] = V2(rn() - 0.5, rn() - 0.5);
      p.p[k] = rn();
    });
    return p;
  }
  static refinement::TwoLevels<2>::Config config(Levels* self) {
    refinement::TwoLevels<2>::Config c;
    c.dx_fine = dx_f, c.rho0 = 1.0, c.h_over_dx = 1.3, c.margin = 0.1;
    c.depth = [self](const V2& x) { return x[0] - self->x0; };
    return c;
  }
  double mass() const {
    double m = 0.0;
    for (double mi : p.m)
      m += mi;
    return m;
  }
  V2 momentum() const {
    V2 P = V2::Zero();
    for (std::size_t i = 0; i < p.size(); ++i)
      P += p.m[i] * p.v[i];
    return P;
  }
  // Positions rounded to the fine half-lattice, sorted (to compare particle sets).
  std::vector<std::pair<long, long>> sites() const {
    std::vector<std::pair<long, long>> s;
    for (const V2& x : p.r)
      s.push_back({std::lround(x[0] / (0.5 * dx_f)), std::lround(x[1] / (0.5 * dx_f))});
    std::sort(s.begin(), s.end());
    return s;
  }
};

} // namespace

// Split: every coarse particle deeper than the margin becomes four fine ones at +-dx_f/2 (the fine
// lattice of the cell), with the parent's velocity; the others keep their level. Merge (the region
// moved away): the four daughters of each cell share a cell of the global grid, so the coarse
// lattice comes back to round-off, with the parent velocities. Mass and momentum exact throughout.
TEST(Refinement, SplitIntoTheFineLatticeAndMergeBack) {
  Levels L;
  const auto coarse_sites = L.sites();
  std::map<std::pair<long, long>, V2> v0; // the coarse velocities by site
  for (std::size_t i = 0; i < L.p.size(); ++i)
    v0[{std::lround(L.p.r[i][0] / (0.5 * L.dx_f)), std::lround(L.p.r[i][1] / (0.5 * L.dx_f))}] =
        L.p.v[i];
  const double M = L.mass();
  const V2 P = L.momentum();
  L.x0 = 0.65; // split where x > 0.75: the coarse columns at x = 0.85, 0.95 (20 particles)
  EXPECT_EQ(L.lv.update(L.p, L.next_id), 20u);
  EXPECT_EQ(L.p.size(), 100u + 3 * 20);
  const auto& h = L.p.scalar(L.lv.h_field());
  for (std::size_t i = 0; i < L.p.size(); ++i) {
    const bool fine = L.p.m[i] < 2 * L.dx_f * L.dx_f;
    EXPECT_EQ(fine, L.p.r[i][0] > 0.8) << i;
    EXPECT_DOUBLE_EQ(h[i], fine ? 1.3 * L.dx_f : 2.6 * L.dx_f) << i;
    if (fine) { // on the fine lattice: (k + 1/2) dx_f
      for (int a = 0; a < 2; ++a)
        EXPECT_NEAR(std::remainder(L.p.r[i][a] / L.dx_f - 0.5, 1.0), 0.0, 1e-9) << i;
    }
  }
  EXPECT_NEAR(L.mass(), M, 1e-14 * M);
  EXPECT_LT((L.momentum() - P).norm(), 1e-14 * M);
  EXPECT_EQ(L.lv.update(L.p, L.next_id), 0u); // nothing more to do
  L.x0 = 10.0; // all coarse region: every fine particle is deeper than the margin outside
  EXPECT_EQ(L.lv.update(L.p, L.next_id), 20u); // 20 groups merged
  ASSERT_EQ(L.p.size(), 100u);
  EXPECT_EQ(L.sites(), coarse_sites);
  for (std::size_t i = 0; i < L.p.size(); ++i) {
    const auto site = std::make_pair(std::lround(L.p.r[i][0] / (0.5 * L.dx_f)),
                                     std::lround(L.p.r[i][1] / (0.5 * L.dx_f)));
    EXPECT_LT((L.p.v[i] - v0.at(site)).norm(), 1e-14) << i; // the daughters carried the parent's v
    EXPECT_DOUBLE_EQ(L.p.m[i], 4 * L.dx_f * L.dx_f);
  }
  EXPECT_NEAR(L.mass(), M, 1e-14 * M);
  EXPECT_LT((L.momentum() - P).norm(), 1e-14 * M);
  EXPECT_EQ(L.lv.splits(), 20u);
  EXPECT_EQ(L.lv.merges(), 20u);
}

// Merging particles that are not on a lattice (random fine positions and velocities): groups of
// four in a grid cell, mass and momentum kept to round-off; particles within the margin of the
// interface are left alone (hysteresis).
TEST(Refinement, MergeKeepsMassAndMomentumAndTheMarginIsLeftAlone) {
  constexpr double dx_f = 0.05;
  Particles<2> p;
  UniformRandom rn(11);
  for_each_lattice_point<2>({0, 0}, {20, 20}, dx_f, [&](V2 x, const auto&) {
    x += 0.3 * dx_f * V2(rn() - 0.5, rn() - 0.5);
    const std::size_t k = p.add(x, dx_f * dx_f, 1.0 + 0.02 * (rn() - 0.5));
    p.v[k] = V2(rn() - 0.5, rn() - 0.5);
  });
  refinement::TwoLevels<2>::Config c;
  c.dx_fine = dx_f, c.margin = 0.1;
  c.depth = [](const V2& x) { return 0.5 - x[0]; }; // fine for x < 0.5; merge where x > 0.6
  refinement::TwoLevels<2> lv(p, c);
  double M = 0.0;
  V2 P = V2::Zero();
  for (std::size_t i = 0; i < p.size(); ++i)
    M += p.m[i], P += p.m[i] * p.v[i];
  std::int64_t next_id = 400;
  const std::size_t groups = lv.update(p, next_id);
  EXPECT_GT(groups, 0u);
  EXPECT_EQ(p.size(), 400u - 3 * groups);
  double M1 = 0.0;
  V2 P1 = V2::Zero();
  std::size_t merged = 0, fine_far = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    M1 += p.m[i], P1 += p.m[i] * p.v[i];
    if (p.m[i] > 1.5 * dx_f * dx_f) {
      ++merged;
      EXPECT_GT(p.r[i][0], 0.6 - 0.1) << i; // a merged particle comes from beyond the margin
    } else if (p.r[i][0] > 0.6 + 2 * dx_f) {
      ++fine_far;
    }
    if (p.r[i][0] < 0.6 - 0.5 * dx_f) // within the margin and the fine region: untouched
      EXPECT_DOUBLE_EQ(p.m[i], dx_f * dx_f) << i;
  }
  EXPECT_EQ(merged, groups);
  EXPECT_NEAR(M1, M, 1e-14 * M);
  EXPECT_LT((P1 - P).norm(), 1e-14 * M);
  // The fine lattice jittered by 0.3 dx_f keeps four particles in every grid cell: all merge.
  EXPECT_EQ(fine_far, 0u);
}

// The free-stream domain with a fine band: the fluid and each emitter on its own level's lattice
// (the band's rows at dx / 2, the others at dx), the band's edges where the rows say, and h from
// the mass; then particles emitted over a few steps keep the level of their rows.
TEST(Refinement, FreeStreamDomainEmitsEachLevelOnItsRows) {
  FreeStreamDomain<2>::Config c;
  c.n = {10, 12}, c.dx = 0.1, c.h = 0.13, c.layers = 3, c.band_rows = 2;
  c.u_in = [](const V2&, double) { return V2(1.0, 0.0); };
  FreeStreamDomain<2> dom(c);
  Particles<2> p;
  dom.fill(p, [](const V2&) { return true; });
  ASSERT_NE(dom.levels(), nullptr);
  auto check = [&] {
    const auto& h = p.scalar(dom.levels()->h_field());
    std::size_t fine = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const bool in_band = std::abs(p.r[i][1] - 0.6) < 0.2;
      const double dx = in_band ? 0.05 : 0.1;
      EXPECT_DOUBLE_EQ(p.m[i], dx * dx) << i << " at " << p.r[i].transpose();
      EXPECT_DOUBLE_EQ(h[i], 1.3 * dx) << i;
      EXPECT_NEAR(std::remainder(p.r[i][1] / dx - 0.5, 1.0), 0.0, 1e-9) << i;
      fine += in_band;
    }
    return fine;
  };
  // fluid: 10 x 8 coarse + 10 x 4 cells of 4 fine; buffer: 3 columns of 8 coarse + 3 of 8 fine
  EXPECT_EQ(check(), 160u + 24u);
  EXPECT_EQ(p.size(), 80u + 160u + 24u + 24u);
  auto total = [&] {
    double m = 0.0;
    for (double mi : p.m)
      m += mi;
    return m;
  };
  const double M0 = total();
  for (int step = 0; step < 10; ++step) {
    for (std::size_t i = 0; i < p.size(); ++i)
      p.r[i][0] += 0.5 * 0.05; // the stream moves everything half a fine spacing
    dom.before_step(p, 0.0);
  }
  check();
  // Nothing deleted yet (the outlet buffer ends at x = 1.3): what was emitted is what was added;
  // 0.25 of the inlet's area would be 0.30, the lattice columns that crossed x = 0 carry 0.26.
  EXPECT_NEAR(total() - M0, dom.mass_in(), 1e-12);
  EXPECT_NEAR(dom.mass_in(), 2 * 0.08 + 5 * 0.02, 1e-12);
}
