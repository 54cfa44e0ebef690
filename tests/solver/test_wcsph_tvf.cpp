// Unit tests of scheme "wcsph_tvf" (schemes/wcsph_tvf/wcsph_tvf.hpp): what must hold exactly.
//  - density summation gives rho0 and the TVF residue g vanishes on a perfect periodic lattice;
//  - the pair forces (pressure with and without kernel correction, Adami's extra stress,
//    Riemann dissipation with every limiter setting, viscous) conserve linear momentum;
//  - a fluid at rest on a lattice stays at rest, for every TVF variant;
//  - uniform translation is exact (Galilean invariance of every pair term);
//  - the dissipation limiter (eq. 6) acts on separating or approaching pairs by its switch;
//  - the TVF limiter (eq. 15): the limited shift is psi times the unlimited one, and on a
//    displaced particle both push it back towards its lattice site;
//  - force_on_walls is minus the total force on the fluid (the fluid pairs cancel);
//  - the Verlet list kept across steps (skin > 0) changes a run only by round-off against a
//    search every step (skin 0), and a run resumed between two builds from the saved reference
//    positions continues to the same bits.
#include "cases/case.hpp"
#include "core/kernels/wendland_c2.hpp"
#include "core/lattice.hpp"
#include "schemes/wcsph_tvf/wcsph_tvf.hpp"
#include "tgv_helpers.hpp"

#include <gtest/gtest.h>

#include <map>

using namespace sph;
using namespace sph::wcsph_tvf;

namespace {

constexpr int n = 16;
constexpr double dx = 1.0 / n;

struct Lattice {
  Particles<2> p;
  Fields f;
  Domain<2> box;
  Options o;
  explicit Lattice(double perturb = 0.0, std::uint64_t seed = 1) {
    UniformRandom rn(seed);
    for_each_lattice_point<2>({0, 0}, {n, n}, dx, [&](Vec2 x, const std::array<int, 2>&) {
      for (int a = 0; a < 2; ++a)
        x[a] += (rn() - 0.5) * perturb * dx;
      p.add(x, dx * dx, 1.0);
    });
    f = Fields::add_to(p);
    box.periodic = {true, true};
    o.dx = dx;
    o.h = 1.3 * dx;
    o.mu = 0.01;
  }
};

using Scheme2 = Scheme<2, WendlandC2<2>>;

Vec2 total(const Particles<2>& p, const std::vector<Vec2>& f) {
  Vec2 s = Vec2::Zero();
  for (std::size_t i = 0; i < p.size(); ++i)
    s += f[i];
  return s;
}
double abs_sum(const std::vector<Vec2>& f) {
  double s = 0.0;
  for (const auto& x : f)
    s += x.norm();
  return s;
}

} // namespace

TEST(WcsphTvf, LatticeDensityAndZeroResidue) {
  Lattice s;
  Scheme2 sc(s.p, s.f, s.box, s.o);
  sc.init();
  std::vector<double> sw;
  sc.number_density(sw);
  for (double w : sw)
    EXPECT_NEAR(w / sc.sigma0(), 1.0, 1e-13);
  for (std::size_t i = 0; i < s.p.size(); ++i)
    s.p.V[i] = dx * dx;
  std::vector<Vec2> g(s.p.size());
  ops::TvfResidue<2> op{s.p, nullptr, g};
  interact(sc.neighbors(), op);
  for (const auto& x : g)
    EXPECT_LT(x.norm() * s.o.h, 1e-12);
  std::vector<Vec2> a(s.p.size());
  ops::BackgroundPressure<2> bp{s.p, 100.0, a};
  interact(sc.neighbors(), bp);
  for (const auto& x : a)
    EXPECT_LT(x.norm(), 1e-9);
}

TEST(WcsphTvf, PairForcesConserveMomentum) {
  Lattice s(0.4, 7);
  Scheme2 sc(s.p, s.f, s.box, s.o);
  sc.init();
  auto& p = s.p;
  UniformRandom rn(3);
  std::vector<Vec2> a_tilde(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.v[i] = Vec2(rn() - 0.5, rn() - 0.5);
    p.rho[i] = 1.0 + 0.02 * (rn() - 0.5);
    p.p[i] = 100.0 * (p.rho[i] - 1.0);
    p.V[i] = p.m[i] / p.rho[i];
    a_tilde[i] = Vec2(rn() - 0.5, rn() - 0.5);
  }
  const auto& nl = sc.neighbors();
  std::vector<Mat<2>> B(p.size());
  std::vector<double> tr(p.size());
  CorrectionMatrix<2> cm{p.V, B, tr};
  interact(nl, cm);
  std::vector<Vec2> zero(p.size(), Vec2::Zero()), F(p.size());
  std::vector<double> drho(p.size());
  for (const std::vector<Mat<2>>* b : {static_cast<const std::vector<Mat<2>>*>(nullptr),
                                       static_cast<const std::vector<Mat<2>>*>(&B)})
    for (const std::vector<Vec2>* at : {static_cast<const std::vector<Vec2>*>(nullptr),
                                        static_cast<const std::vector<Vec2>*>(&a_tilde)}) {
      ops::FirstHalf<2> op{p, b, zero, at, 1e-3, 0.1, F, drho};
      interact(nl, op);
      EXPECT_LT(total(p, F).norm(), 1e-13 * abs_sum(F)) << (b ? "B " : "") << (at ? "A" : "");
    }
  for (Dissipation d : {Dissipation::Limited, Dissipation::Full})
    for (LimiterSign sg : {LimiterSign::Expansion, LimiterSign::Compression}) {
      Options o = s.o;
      o.dissipation = d, o.sign = sg;
      ops::SecondHalf<2> op{p, nullptr, o, 10.0, drho, F};
      interact(nl, op);
      EXPECT_GT(abs_sum(F), 0.0);
      EXPECT_LT(total(p, F).norm(), 1e-13 * abs_sum(F));
    }
  ops::ViscousForce<2> vf{p, nullptr, 0.01, 1e-4, F};
  interact(nl, vf);
  EXPECT_LT(total(p, F).norm(), 1e-13 * abs_sum(F));
}

TEST(WcsphTvf, RestStaysAtRest) {
  for (Tvf t : {Tvf::None, Tvf::Original, Tvf::SmoothingLength, Tvf::Limited})
    for (bool kc : {false, true}) {
      Lattice s;
      s.o.tvf = t;
      s.o.kernel_correction = kc;
      Scheme2 sc(s.p, s.f, s.box, s.o);
      sc.init();
      std::vector<Vec2> r0(s.p.size());
      for (std::size_t i = 0; i < s.p.size(); ++i)
        r0[s.p.id[i]] = s.p.r[i];
      for (int k = 0; k < 5; ++k)
        sc.advance(sc.advection_dt());
      for (std::size_t i = 0; i < s.p.size(); ++i) {
        EXPECT_LT(s.p.v[i].norm(), 1e-12);
        EXPECT_LT((s.p.r[i] - r0[s.p.id[i]]).norm(), 1e-12 * dx);
        EXPECT_NEAR(s.p.rho[i], 1.0, 1e-12);
      }
    }
}

TEST(WcsphTvf, UniformTranslationIsExact) {
  for (Tvf t : {Tvf::None, Tvf::Limited}) {
    Lattice s;
    s.o.tvf = t;
    s.o.dissipation = Dissipation::Full;
    const Vec2 U(0.3, -0.2);
    for (auto& v : s.p.v)
      v = U;
    Scheme2 sc(s.p, s.f, s.box, s.o);
    sc.init();
    std::vector<Vec2> r0(s.p.size());
    for (std::size_t i = 0; i < s.p.size(); ++i)
      r0[s.p.id[i]] = s.p.r[i];
    double t_sum = 0.0;
    for (int k = 0; k < 4; ++k) {
      const double Dt = sc.advection_dt();
      sc.advance(Dt);
      t_sum += Dt;
    }
    for (std::size_t i = 0; i < s.p.size(); ++i) {
      EXPECT_LT((s.p.v[i] - U).norm(), 1e-12);
      Vec2 d = s.p.r[i] - r0[s.p.id[i]] - U * t_sum;
      for (int a = 0; a < 2; ++a)
        d[a] -= std::round(d[a]); // periodic wrap, L = 1
      EXPECT_LT(d.norm(), 1e-11);
      EXPECT_NEAR(s.p.rho[i], 1.0, 1e-12);
    }
  }
}

TEST(WcsphTvf, DissipationLimiterSignSwitch) {
  Options o;
  o.c0 = 10.0;
  const double sep = 0.5, app = -0.5; // u_ij > 0: separating, < 0: approaching
  o.dissipation = Dissipation::Limited;
  o.sign = LimiterSign::Expansion;
  EXPECT_DOUBLE_EQ(dissipation_beta(o, sep), 0.15);
  EXPECT_DOUBLE_EQ(dissipation_beta(o, app), 0.0);
  EXPECT_DOUBLE_EQ(dissipation_beta(o, 10.0), 1.0); // truncated at 1
  o.sign = LimiterSign::Compression;
  EXPECT_DOUBLE_EQ(dissipation_beta(o, sep), 0.0);
  EXPECT_DOUBLE_EQ(dissipation_beta(o, app), 0.15);
  o.dissipation = Dissipation::Full;
  EXPECT_DOUBLE_EQ(dissipation_beta(o, sep), 1.0);
  EXPECT_DOUBLE_EQ(dissipation_beta(o, app), 1.0);
  o.dissipation = Dissipation::None;
  EXPECT_DOUBLE_EQ(dissipation_beta(o, app), 0.0);

  // The dissipation force of an approaching pair pushes the two apart (it damps u_ij).
  Particles<2> p;
  p.add(Vec2(0.0, 0.0), 1.0, 1.0);
  p.add(Vec2(1.0, 0.0), 1.0, 1.0);
  p.v[0] = Vec2(0.5, 0.0), p.v[1] = Vec2(-0.5, 0.0);
  std::vector<double> drho(2, 0.0);
  std::vector<Vec2> F(2);
  o.dissipation = Dissipation::Limited;
  o.sign = LimiterSign::Compression;
  ops::SecondHalf<2> op{p, nullptr, o, 10.0, drho, F};
  auto acc = op.init(0);
  op.pair(0, Pair<2>{1, Vec2(-1.0, 0.0), 1.0, 0.1, -0.2}, acc);
  op.finish(0, acc);
  EXPECT_LT(F[0].x(), 0.0); // particle 0 moves right towards 1: pushed back left
  EXPECT_GT(drho[0], 0.0);  // and its density grows (compression)
}

TEST(WcsphTvf, TransportCorrectionPushesBackAndLimits) {
  for (double disp : {0.02, 0.2}) {
    std::vector<Vec2> shift[2];
    int k = 0;
    for (Tvf t : {Tvf::SmoothingLength, Tvf::Limited}) {
      Lattice s;
      s.o.tvf = t;
      const std::size_t c = (n / 2) * n + n / 2; // an inner particle
      s.p.r[c].x() += disp * dx;
      Scheme2 sc(s.p, s.f, s.box, s.o);
      sc.init();
      sc.advance(1e-6); // one advection step: summation, TVF, a tiny acoustic step
      shift[k].assign(s.p.size(), Vec2::Zero());
      for (std::size_t i = 0; i < s.p.size(); ++i)
        shift[k][s.p.id[i]] = sc.tvf_shift()[i];
      EXPECT_LT(shift[k][c].x(), 0.0) << "displaced particle is pushed back";
      EXPECT_NEAR(shift[k][c].y(), 0.0, 1e-15);
      ++k;
    }
    // psi = min(kappa h^2 |g|^2, 1) with g = shift / (alpha h^2) of the unlimited variant.
    const double h = 1.3 * dx, alpha = 0.2, kappa = 100.0;
    for (std::size_t i = 0; i < shift[0].size(); ++i) {
      const Vec2 g = shift[0][i] / (alpha * h * h);
      const double psi = std::min(kappa * h * h * g.squaredNorm(), 1.0);
      EXPECT_NEAR((shift[1][i] - psi * shift[0][i]).norm(), 0.0, 1e-15);
    }
  }
}

// force_on_walls: the fluid-fluid pairs cancel (PairForcesConserveMomentum), so the fluid's force
// on the walls is minus the total viscous, pressure and dissipation force on the fluid computed
// over all partners; the wall-only share of each op must give that to round-off. A disc of wall
// particles in a periodic box, random velocities and pressures, with and without the kernel
// correction.
TEST(WcsphTvf, ForceOnWallsIsMinusTheFluidsTotal) {
  for (bool kc : {false, true}) {
    Lattice s(0.3, 5);
    auto& p = s.p;
    const Vec2 c(0.5, 0.5);
    for (std::size_t i = 0; i < p.size(); ++i)
      if ((p.r[i] - c).norm() < 0.2)
        p.kind[i] = Kind::Wall;
    const int vw = p.add_vector("v_wall");
    s.f.v_wall = vw;
    s.o.kernel_correction = kc;
    UniformRandom rn(11);
    for (std::size_t i = 0; i < p.size(); ++i) {
      p.v[i] = Vec2(rn() - 0.5, rn() - 0.5);
      p.rho[i] = 1.0 + 0.02 * (rn() - 0.5);
      p.p[i] = 100.0 * (p.rho[i] - 1.0);
      p.V[i] = p.m[i] / p.rho[i];
      if (p.kind[i] == Kind::Wall)
        p.vector(vw)[i] = Vec2(0.1 * (rn() - 0.5), 0.0);
    }
    Scheme2 sc(s.p, s.f, s.box, s.o);
    sc.init();
    const auto& nl = sc.neighbors();
    auto fluid = [&](std::size_t i) { return p.kind[i] == Kind::Fluid; };
    std::vector<Mat<2>> B(p.size(), Mat<2>::Identity());
    std::vector<double> tr(p.size());
    CorrectionMatrix<2> cm{p.V, B, tr};
    interact(nl, cm, fluid);
    std::vector<Vec2> Fv(p.size()), Fp(p.size()), Fd(p.size());
    std::vector<double> drho(p.size(), 0.0);
    const Vec2* vwall = p.vector(vw).data();
    ops::ViscousForce<2> v{p, vwall, s.o.mu, s.o.viscous_eps * s.o.h, Fv};
    interact(nl, v, fluid);
    // The viscous force is also F_prior of the wall pressure extrapolation (no body force).
    ops::FirstHalf<2> f1{p,   kc ? &B : nullptr,         Fv, nullptr,
                         0.0, 1.0 / (s.o.rho0 * s.o.c0), Fp, drho};
    interact(nl, f1, fluid);
    ops::SecondHalf<2> f2{p, vwall, s.o, s.o.rho0 * s.o.c0, drho, Fd};
    interact(nl, f2, fluid);
    Vec2 total = Vec2::Zero(), total_v = Vec2::Zero();
    double scale = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (fluid(i))
        total += Fv[i] + Fp[i] + Fd[i], total_v += Fv[i],
            scale += Fv[i].norm() + Fp[i].norm() + Fd[i].norm();
    Vec2 viscous;
    const Vec2 F = sc.force_on_walls(&viscous);
    EXPECT_GT(F.norm(), 1e-3 * scale);
    EXPECT_LT((F + total).norm(), 1e-12 * scale) << "kernel_correction " << kc;
    EXPECT_LT((viscous + total_v).norm(), 1e-12 * scale) << "kernel_correction " << kc;
  }
}

// Case cylinder_free_stream: the set-up is mirror-symmetric about the cylinder's axis, so without
// the nudge the lift stays small against the drag (it is not held at round-off: the particles'
// motion amplifies the summation-order differences, 0.2 % of the drag by t = 4); the nudge (at
// t = ramp_time) makes the lift over ten times larger. Coarse and short: plumbing, not the
// benchmark.
TEST(CylinderFreeStream, SymmetricWithoutTheNudge) {
  auto run = [](double nudge) {
    Params prm;
    for (const auto& sp : find_case("cylinder_free_stream")->params)
      prm[sp.name] = sp.default_value;
    for (const auto& sp : find_scheme("wcsph_tvf")->params)
      prm[sp.name] = sp.default_value;
    prm["scheme"] = std::string("wcsph_tvf");
    prm["D_over_dx"] = 5.0, prm["t_end"] = 4.0, prm["perturbation"] = nudge;
    const RunResult r = find_case("cylinder_free_stream")->run(prm, RunContext{});
    EXPECT_EQ(r.status, RunStatus::Done) << r.message;
    std::map<std::string, double> m(r.metrics.begin(), r.metrics.end());
    for (const char* k : {"cd_mean", "cl_rms", "cd_viscous_mean", "tv_ratio_max", "sumW_spread_end",
                          "acoustic_steps", "time_per_particle_step_s"})
      EXPECT_TRUE(m.count(k)) << k;
    return m;
  };
  const auto sym = run(0.0), nudged = run(0.05);
  EXPECT_GT(sym.at("cd_mean"), 0.5);
  // Value bands (issue 15): what these deterministic runs measured, 5 % on the drag and its
  // viscous part (2 mu -> mu halves the latter), 10 % on the nudged lift.
  EXPECT_NEAR(sym.at("cd_mean"), 2.3572, 0.05 * 2.3572);
  EXPECT_NEAR(sym.at("cd_viscous_mean"), 0.21643, 0.05 * 0.21643);
  EXPECT_NEAR(nudged.at("cl_rms"), 0.086251, 0.1 * 0.086251);
  EXPECT_GT(sym.at("cd_viscous_mean"), 0.0);
  EXPECT_LT(sym.at("cl_rms"), 0.01 * sym.at("cd_mean"));
  EXPECT_GT(nudged.at("cl_rms"), 10.0 * sym.at("cl_rms"));
}

// Variable resolution (Fields::h): on a lattice of half the reference spacing with h_i = h/2 the
// mass summation gives rho0 and the fluid stays at rest (every TVF variant that scales with h_i);
// on a box whose right half is refined, the pairs' kernels are symmetric (h_ij), so the pair
// forces still conserve momentum.
TEST(WcsphTvf, VariableResolutionLatticeAndMomentum) {
  auto lattice = [](bool refine_right_half) {
    Lattice s; // reference spacing dx, h = 1.3 dx (Options), periodic unit box
    Particles<2> q;
    auto add = [&](double d, int n0, int n1, int m) {
      for (int i = n0; i < n1; ++i)
        for (int j = 0; j < m; ++j)
          q.add(Vec2((i + 0.5) * d, (j + 0.5) * d), d * d, 1.0);
    };
    if (refine_right_half)
      add(dx, 0, n / 2, n), add(0.5 * dx, n, 2 * n, 2 * n);
    else
      add(0.5 * dx, 0, 2 * n, 2 * n);
    const int hf = q.add_scalar("h");
    for (std::size_t i = 0; i < q.size(); ++i)
      q.scalar(hf)[i] = 1.3 * std::sqrt(q.m[i]);
    s.p = q;
    s.f = Fields::add_to(s.p);
    s.f.h = hf;
    return s;
  };
  for (Tvf t : {Tvf::None, Tvf::SmoothingLength, Tvf::Limited}) {
    Lattice s = lattice(false);
    s.o.tvf = t;
    Scheme2 sc(s.p, s.f, s.box, s.o);
    sc.init();
    for (int k = 0; k < 3; ++k)
      sc.advance(sc.advection_dt());
    for (std::size_t i = 0; i < s.p.size(); ++i) {
      EXPECT_NEAR(s.p.rho[i], 1.0, 1e-12);
      EXPECT_LT(s.p.v[i].norm(), 1e-12);
    }
  }
  Lattice s = lattice(true);
  Scheme2 sc(s.p, s.f, s.box, s.o);
  sc.init();
  auto& p = s.p;
  UniformRandom rn(3);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.v[i] = Vec2(rn() - 0.5, rn() - 0.5);
    p.p[i] = 2.0 * (rn() - 0.5);
  }
  const auto& nl = sc.neighbors();
  std::vector<Vec2> zero(p.size(), Vec2::Zero()), F(p.size());
  std::vector<double> drho(p.size());
  ops::FirstHalf<2> f1{p, nullptr, zero, nullptr, 0.0, 0.1, F, drho};
  interact(nl, f1);
  EXPECT_LT(total(p, F).norm(), 1e-13 * abs_sum(F));
  Options o = s.o;
  o.dissipation = Dissipation::Full;
  ops::SecondHalf<2> f2{p, nullptr, o, 10.0, drho, F};
  interact(nl, f2);
  EXPECT_LT(total(p, F).norm(), 1e-13 * abs_sum(F));
  ops::ViscousForce<2> vf{p, nullptr, 0.01, 1e-4, F};
  interact(nl, vf);
  EXPECT_LT(total(p, F).norm(), 1e-13 * abs_sum(F));
  // The mass summation on this box: rho0 away from the interfaces (x = 0.5 and the periodic
  // x = 0); next to them -5.5 % to +6.5 % (measured: the lattices meet with a gap of 0.75 dx and
  // the pair kernels average h), which the pressure and the TVF then relax.
  std::vector<double> sw(p.size());
  ops::MassSummation<2> ms{p,
                           p.scalar(s.f.h),
                           WendlandC2<2>(s.o.h).W(0.0),
                           s.o.h,
                           1.0,
                           dx * dx * sc.sigma0(),
                           sc.sigma0(),
                           sw};
  interact(nl, ms);
  std::size_t far = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double x = p.r[i][0];
    if (std::abs(x - 0.25) < 0.08 || std::abs(x - 0.75) < 0.08) { // one support from both
      EXPECT_NEAR(p.rho[i], 1.0, 1e-12);
      ++far;
    } else {
      EXPECT_NEAR(p.rho[i], 1.0, 0.07);
    }
  }
  EXPECT_GT(far, 100u);
}

namespace {

// A disordered Taylor-Green vortex (U = 1, c0 = 10) on the 16 x 16 periodic lattice.
struct Vortex : Lattice {
  explicit Vortex(double skin) : Lattice(0.3, 21) {
    for (std::size_t i = 0; i < p.size(); ++i)
      p.v[i] = sph::testing::tgv_shape(p.r[i]);
    o.skin = skin;
  }
};

// Index of every particle id.
std::vector<std::size_t> by_id(const Particles<2>& p) {
  std::vector<std::size_t> at(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    at[static_cast<std::size_t>(p.id[i])] = i;
  return at;
}

} // namespace

// 15 advection steps (60 acoustic sub-steps) with the Verlet list kept between builds against a
// search every step: the same pairs with the same geometry, summed in another order (the
// particles are sorted only at builds), so positions and velocities agree to round-off (measured
// 7e-15 and 3e-14; 6 builds in 15 steps). A pair missing from the kept list (a stale list) moves
// them by ~1e-3.
TEST(WcsphTvf, VerletSkinChangesTheRunOnlyByRoundOff) {
  Vortex a(0.5), b(0.0);
  Scheme2 sa(a.p, a.f, a.box, a.o), sb(b.p, b.f, b.box, b.o);
  sa.init(), sb.init();
  double ta = 0.0, tb = 0.0;
  const int steps = 15;
  for (int k = 0; k < steps; ++k)
    sa.advance_towards(ta, 1.0), sb.advance_towards(tb, 1.0);
  EXPECT_NEAR(ta, tb, 1e-14);                 // the time steps follow the velocities: round-off too
  EXPECT_EQ(sb.verlet().builds(), steps + 1); // skin 0: every step
  EXPECT_GT(sa.verlet().builds(), 1);         // the kept list was rebuilt...
  EXPECT_LT(sa.verlet().builds(), steps / 2); // ...but mostly kept
  const auto ia = by_id(a.p), ib = by_id(b.p);
  const MinimumImage<2> image(a.box);
  double dr = 0.0, dv = 0.0;
  for (std::size_t id = 0; id < ia.size(); ++id) {
    dr = std::max(dr, image(a.p.r[ia[id]] - b.p.r[ib[id]]).norm());
    dv = std::max(dv, (a.p.v[ia[id]] - b.p.v[ib[id]]).norm());
  }
  EXPECT_LT(dr, 1e-12) << dr;
  EXPECT_LT(dv, 1e-12) << dv;
}

// A checkpoint between two Verlet builds: a scheme resumed from the particles, the reference
// positions and the build count continues to the same bits as the uninterrupted one (the same
// candidate rows in the same order, the same later rebuilds). A fresh build at the checkpoint
// instead (sorting the particles there) gives other bits: the check can see a wrong list.
TEST(WcsphTvf, ResumedBetweenVerletBuildsContinuesToTheSameBits) {
  Vortex a(0.5);
  Scheme2 sa(a.p, a.f, a.box, a.o);
  sa.init();
  double t = 0.0;
  for (int k = 0; k < 6; ++k)
    sa.advance_towards(t, 1.0);
  ASSERT_GT(sa.verlet().max_displacement2(a.p.r), 0.0); // not at a build
  const Particles<2> saved = a.p;
  const std::vector<Vec2> r0 = sa.verlet().reference();
  const long builds = sa.verlet().builds();
  const std::vector<double> carried = sa.carried_state();
  const double t_saved = t;
  for (int k = 0; k < 6; ++k)
    sa.advance_towards(t, 1.0);
  EXPECT_GT(sa.verlet().builds(), builds); // a rebuild after the checkpoint too

  Vortex b(0.5), c(0.5);
  b.p = saved, c.p = saved;
  Scheme2 sb(b.p, b.f, b.box, b.o), sc(c.p, c.f, c.box, c.o);
  sb.resume(r0, builds);
  sb.restore_carried_state(carried);
  sc.init();
  sc.restore_carried_state(carried);
  double tb = t_saved, tc = t_saved;
  for (int k = 0; k < 6; ++k)
    sb.advance_towards(tb, 1.0), sc.advance_towards(tc, 1.0);
  EXPECT_EQ(tb, t);
  EXPECT_EQ(sb.verlet().builds(), sa.verlet().builds());
  std::size_t same = 0, fresh_differs = 0;
  const auto ia = by_id(a.p), ic = by_id(c.p);
  for (std::size_t i = 0; i < a.p.size(); ++i) {
    same += a.p.id[i] == b.p.id[i] && a.p.r[i] == b.p.r[i] && a.p.v[i] == b.p.v[i] &&
            a.p.rho[i] == b.p.rho[i];
    fresh_differs += a.p.v[ia[i]] != c.p.v[ic[i]];
  }
  EXPECT_EQ(same, a.p.size());
  EXPECT_GT(fresh_differs, 0u);
}
