// Tests of the ALSPH scheme (seed 004), the cylinder_channel case and the signal diagnostics.
#include "cases/case.hpp"
#include "core/cell_list.hpp"
#include "core/kernels/quintic_spline.hpp"
#include "core/lattice.hpp"
#include "core/neighbor_list.hpp"
#include "diagnostics/signal.hpp"
#include "schemes/alsph/alsph.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace sph;

namespace {

std::vector<double> linspace_t(double t1, std::size_t n) {
  std::vector<double> t(n);
  for (std::size_t k = 0; k < n; ++k)
    t[k] = t1 * k / (n - 1);
  return t;
}

} // namespace

TEST(Signal, MeanAndRmsOfSine) {
  const auto t = linspace_t(10.0, 20001);
  std::vector<double> f(t.size());
  for (std::size_t k = 0; k < t.size(); ++k)
    f[k] = 1.5 + 2.0 * std::sin(2.0 * std::numbers::pi * 0.5 * t[k]);
  EXPECT_NEAR(diag::time_mean(t, f), 1.5, 1e-6);
  // rms of 1.5 + 2 sin: sqrt(1.5^2 + 2^2 / 2)
  EXPECT_NEAR(diag::time_rms(t, f), std::sqrt(2.25 + 2.0), 1e-6);
  EXPECT_NEAR(diag::time_mean(t, f, 4.0), 1.5, 1e-6); // 3 whole periods
}

// The Gaussian low-pass keeps a constant, multiplies a sine by exp(-2 pi^2 sigma^2 f^2) away from
// the ends, and removes a fast component: shedding-like lift plus particle noise.
TEST(Signal, GaussianLowpassTransferFunction) {
  const auto t = linspace_t(100.0, 10001); // dt = 0.01
  const double sigma = 0.25, f0 = 0.165, f1 = 2.0;
  std::vector<double> s(t.size());
  for (std::size_t k = 0; k < t.size(); ++k)
    s[k] = 1.5 + std::sin(2.0 * std::numbers::pi * f0 * t[k]) +
           0.5 * std::sin(2.0 * std::numbers::pi * f1 * t[k]);
  const auto g = diag::gaussian_lowpass(t, s, sigma);
  const double a0 = std::exp(-2.0 * std::pow(std::numbers::pi * sigma * f0, 2));
  const double a1 = std::exp(-2.0 * std::pow(std::numbers::pi * sigma * f1, 2));
  double worst = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < 1.0 || t[k] > 99.0)
      continue;
    const double expect = 1.5 + a0 * std::sin(2.0 * std::numbers::pi * f0 * t[k]) +
                          0.5 * a1 * std::sin(2.0 * std::numbers::pi * f1 * t[k]);
    worst = std::max(worst, std::abs(g[k] - expect));
  }
  EXPECT_LT(worst, 1e-4);
  EXPECT_EQ(diag::gaussian_lowpass(t, s, 0.0), s);
}

TEST(Signal, StrouhalOfSineFromZeroCrossingsAndSpectrum) {
  // A lift-like signal: 0.2 Hz sine with a transient and sample jitter-free steps of 0.01.
  const double f0 = 0.2134;
  const auto t = linspace_t(200.0, 20001);
  std::vector<double> cl(t.size());
  for (std::size_t k = 0; k < t.size(); ++k)
    cl[k] = 0.7 * std::sin(2.0 * std::numbers::pi * f0 * t[k] + 0.3) +
            (t[k] < 50.0 ? 3.0 * std::exp(-t[k]) : 0.0);
  const auto z = diag::zero_crossing_frequency(t, cl, 60.0);
  EXPECT_NEAR(z.f, f0, 1e-4 * f0);
  EXPECT_GE(z.cycles, 27);
  EXPECT_LT(z.period_std, 1e-3);
  // [t_first, t_last] holds exactly z.cycles periods: the mean over it of a sine is ~0 and the
  // rms is amplitude / sqrt(2), although the window does not start at a multiple of the period.
  EXPECT_NEAR(z.t_last - z.t_first, z.cycles / f0, 1e-3);
  EXPECT_NEAR(diag::time_mean(t, cl, z.t_first, z.t_last), 0.0, 1e-4);
  EXPECT_NEAR(diag::time_rms(t, cl, z.t_first, z.t_last), 0.7 / std::sqrt(2.0), 1e-4);
  const auto s = diag::spectral_peak_frequency(t, cl, 60.0);
  EXPECT_NEAR(s.f, f0, 5e-3 * f0);
  // A constant signal has no frequency.
  std::vector<double> c(t.size(), 1.0);
  EXPECT_EQ(diag::zero_crossing_frequency(t, c).cycles, 0);
}

TEST(Signal, ZeroCrossingsIgnoreParticleNoiseNearZero) {
  // The lift of the ALSPH Re = 100 run (docs/results/alsph_re.csv): amplitude 0.4, period ~5.2,
  // sampled every 0.02, with particle noise of about +-0.1 from sample to sample, which re-crosses
  // zero just after a true crossing. Model: a sine plus uniform noise in [-0.08, 0.08] per sample.
  // Only a half swing below the mean re-arms the crossing detector, so each period counts once:
  // f within 2 %, period spread under 5 %. (With the former re-arming band of 0.1 of the half
  // range this signal gives 17 "periods" of 0.03-5.2 and f 2.8 times too high; the recorded run
  // gave a 0.17-long period and St 0.222 instead of 0.190.)
  const double f0 = 0.19;
  const auto t = linspace_t(70.0, 3501);
  UniformRandom noise(1);
  std::vector<double> cl(t.size());
  for (std::size_t k = 0; k < t.size(); ++k)
    cl[k] = 0.4 * std::sin(2.0 * std::numbers::pi * f0 * t[k]) + 0.16 * (noise() - 0.5);
  const auto z = diag::zero_crossing_frequency(t, cl, 35.0);
  EXPECT_NEAR(z.f, f0, 0.02 * f0);
  EXPECT_LT(z.period_std * z.f, 0.05);
  EXPECT_GE(z.cycles, 5);
  EXPECT_LE(z.cycles, 6);
}

namespace {

// Square lattice patch [0, n dx)^2, neighbour list built, fields to test on the interior.
struct Patch {
  Particles<2> p;
  QuinticSpline<2> kernel;
  CellList<2> cells;
  NeighborList<2> nl;
  double dx;
  explicit Patch(int n, double disorder = 0.0)
      : kernel(1.0 / n), cells(Domain<2>{}, 3.0 / n), dx(1.0 / n) {
    UniformRandom rn(7);
    for_each_lattice_point<2>(
        {-4, -4}, {n + 4, n + 4}, dx, [&](Vec<2> x, const std::array<int, 2>& i) {
          x[0] += (rn() - 0.5) * disorder * dx, x[1] += (rn() - 0.5) * disorder * dx;
          const bool inside = i[0] >= 0 && i[0] < n && i[1] >= 0 && i[1] < n;
          p.add(x, dx * dx, 1.0, inside ? Kind::Fluid : Kind::Buffer);
        });
    cells.build(p);
    nl.build(cells, p.r, kernel);
  }
};

} // namespace

// <grad u>, <div u>, <lap u> of the field u on the patch's fluid particles (the scheme's grad_u,
// div, lap_u), from the pair coefficients stored as Real, eta = 0 (the exact forms).
template <class Real>
alsph::Scheme<2, QuinticSpline<2>, Real> derivatives(Patch& t, const std::vector<Vec<2>>& u) {
  alsph::Settings s;
  s.eta_over_h = 0.0;
  alsph::Scheme<2, QuinticSpline<2>, Real> sc(t.kernel, s);
  const std::size_t N = t.p.size();
  sc.grad_u.resize(N), sc.div.resize(N), sc.lap_u.resize(N), sc.gamma.resize(N);
  sc.trace_b.resize(N);
  sc.geometry(t.p, t.nl);
  alsph::ops::VelocityDerivatives<2, Real> op{sc.coefficients(), u, sc.grad_u, sc.div, sc.lap_u};
  interact_indexed(t.nl, op, [&](std::size_t i) { return t.p.kind[i] == Kind::Fluid; });
  return sc;
}

// <grad u> and <div u> of u = A x + b on a disordered lattice, and <lap u> of a quadratic on the
// regular lattice. Double: exact to round-off. Float: each coefficient carries a relative error
// <= 6e-8 (2^-24); measured, the largest errors are 3.7e-8 (|<grad u> - A|, |A| = 1.5) and 3.2e-8
// (<lap u>, 6), so the bound 1e-6 leaves a factor 25 and fails on a coefficient wrong by 1e-5
// relative.
template <class Real>
void check_exact_derivatives(double tol_grad, double tol_lap) {
  Patch t(20, 0.4);
  Mat<2> A;
  A << 0.3, -1.2, 0.7, 0.5;
  std::vector<Vec<2>> u(t.p.size());
  for (std::size_t i = 0; i < u.size(); ++i)
    u[i] = A * t.p.r[i] + Vec<2>(1.0, 2.0);
  const auto sc = derivatives<Real>(t, u);
  for (std::size_t i = 0; i < u.size(); ++i) {
    if (t.p.kind[i] != Kind::Fluid)
      continue;
    EXPECT_LT((sc.grad_u[i] - A).norm(), tol_grad) << i;
    EXPECT_NEAR(sc.div[i], A.trace(), tol_grad) << i;
  }
  Patch q(20);
  std::vector<Vec<2>> w(q.p.size());
  for (std::size_t i = 0; i < w.size(); ++i) {
    const auto& x = q.p.r[i];
    w[i] = Vec<2>(x[0] * x[0] + 2 * x[1] * x[1], x[0] * x[1]); // lap = (6, 0)
  }
  const auto sq = derivatives<Real>(q, w);
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (q.p.kind[i] != Kind::Fluid)
      continue;
    EXPECT_NEAR(sq.lap_u[i][0], 6.0, tol_lap) << i;
    EXPECT_NEAR(sq.lap_u[i][1], 0.0, tol_lap) << i;
  }
}

TEST(AlsphOperators, ExactDerivativesFromDoubleCoefficients) {
  check_exact_derivatives<double>(1e-10, 1e-6);
}

TEST(AlsphOperators, ExactDerivativesFromFloatCoefficients) {
  check_exact_derivatives<float>(1e-6, 1e-6);
}

// Algorithm 1 recomputes V_i = 1 / sum_j W_ij on every pair refresh (row by row, right after the
// row is refreshed): after a step, V is that of the final pair geometry, not that of r^n.
TEST(AlsphOperators, Algorithm1VolumesFollowTheRefreshedPairs) {
  Patch t(16);
  alsph::Settings s;
  s.algorithm = 1, s.shifting = false, s.max_iterations = 2, s.dt = 1e-2;
  alsph::Scheme<2, QuinticSpline<2>> sc(t.kernel, s);
  for (std::size_t i = 0; i < t.p.size(); ++i) // a rotation with strain: pair distances change
    t.p.v[i] = Vec<2>(0.3 * t.p.r[i][1], -0.2 * t.p.r[i][0]);
  const MirrorGhosts<2> ghosts;
  const std::vector<Vec<2>> normal(t.p.size(), Vec<2>::Zero());
  sc.step(t.p, t.nl, ghosts, normal, [](auto&, auto&) {});
  double moved = 0.0;
  for (std::size_t i = 0; i < t.p.size(); ++i) {
    double w = t.kernel.W(0.0);
    for (std::uint32_t k = t.nl.offset[i]; k < t.nl.offset[i + 1]; ++k)
      w += t.nl.W[k];
    ASSERT_NEAR(t.p.V[i] * w, 1.0, 1e-12) << "particle " << i;
    moved = std::max(moved, std::abs(t.p.r[i][0] - sc.r_n[i][0]));
  }
  EXPECT_GT(moved, 0.01 * t.dx); // the test is not vacuous
}

// Algorithm 1's refresh of the cached pairs equals the kernel values of a fresh search on the moved
// positions for every pair that stays in the list.
TEST(AlsphOperators, PairRefreshMatchesFreshSearch) {
  Patch t(16);
  alsph::Settings s;
  alsph::Scheme<2, QuinticSpline<2>> sc(t.kernel, s);
  sc.r_prev = t.p.r;
  UniformRandom rn(3);
  for (auto& x : t.p.r)
    x += Vec<2>(rn() - 0.5, rn() - 0.5) * 0.05 * t.dx;
  sc.refresh_pairs(t.p, t.nl);
  std::size_t checked = 0;
  for (std::size_t i = 0; i < t.p.size(); ++i)
    for (std::uint32_t k = t.nl.offset[i]; k < t.nl.offset[i + 1]; ++k) {
      const auto j = t.nl.j[k];
      const Vec<2> rij = t.p.r[i] - t.p.r[j];
      ASSERT_LT((t.nl.r_ij[k] - rij).norm(), 1e-14);
      ASSERT_NEAR(t.nl.W[k], t.kernel.W(rij.norm()), 1e-9 * t.kernel.W(0.0));
      ++checked;
    }
  EXPECT_GT(checked, 1000u);
}

namespace {

Params cylinder_params() {
  Params prm;
  for (const auto& sp : find_case("cylinder_channel")->params)
    prm[sp.name] = sp.default_value;
  for (const auto& sp : find_scheme("alsph")->params)
    prm[sp.name] = sp.default_value;
  prm["scheme"] = std::string("alsph");
  // Small channel, coarse, short: plumbing and stability, not physics.
  prm["D_over_dx"] = 6.0, prm["channel_length"] = 6.0, prm["channel_height"] = 4.0;
  prm["upstream_length"] = 2.0, prm["Re"] = 100.0, prm["dt_star"] = 2.54e-2;
  prm["t_end"] = 0.4;
  return prm;
}

double metric(const RunResult& r, const std::string& k) {
  for (const auto& [n, v] : r.metrics)
    if (n == k)
      return v;
  return std::numeric_limits<double>::quiet_NaN();
}

} // namespace

TEST(CylinderChannel, BothAlgorithmsRunAndReportMetrics) {
  for (std::int64_t alg : {1, 2}) {
    Params prm = cylinder_params();
    prm["algorithm"] = alg;
    const RunResult r = find_case("cylinder_channel")->run(prm, RunContext{});
    EXPECT_EQ(r.status, RunStatus::Done) << "algorithm " << alg << ": " << r.message;
    for (const char* k : {"cd_mean", "cl_rms", "st_cycles", "div_mean", "iterations_mean",
                          "converged_fraction", "wall_s", "cpu_s", "iteration_cpu_us_per_particle"})
      EXPECT_TRUE(std::isfinite(metric(r, k))) << k;
    // 0.4 D/U holds no shedding period: St is left out rather than recorded as a number.
    EXPECT_EQ(metric(r, "st_cycles"), 0.0);
    EXPECT_TRUE(std::isnan(metric(r, "St")));
    EXPECT_GT(metric(r, "cd_mean"), 0.0);
    // Value bands (issue 15): what these deterministic runs measured, 5 % on cd_mean (the force
    // integration, the penalty or the pressure update move it by more), 10 % on div_mean.
    EXPECT_NEAR(metric(r, "cd_mean"), alg == 1 ? 3.2450 : 3.2616, 0.05 * 3.25);
    EXPECT_NEAR(metric(r, "div_mean"), 0.01967, 0.1 * 0.01967);
    EXPECT_LE(metric(r, "iterations_mean"), 5.0);
    EXPECT_TRUE(std::isnan(metric(r, "t_diverged")));
  }
}

// ramp_time: the fluid starts at rest and the channel accelerates as a whole with the inlet
// (U (1 - cos(pi t / T)) / 2 and the body force dU/dt). After the ramp the flow is the impulsive
// start's: the drag over [1.5, 3] D/U agrees within a few per cent. (A ramp of the inlet alone,
// without the body force, piled the inflow into the resting fluid and diverged at t = 1.1.)
TEST(CylinderChannel, SmoothStartReachesTheImpulsiveFlow) {
  Params prm = cylinder_params();
  prm["t_end"] = 3.0;
  const RunResult impulsive = find_case("cylinder_channel")->run(prm, RunContext{});
  prm["ramp_time"] = 1.0;
  const RunResult smooth = find_case("cylinder_channel")->run(prm, RunContext{});
  ASSERT_EQ(impulsive.status, RunStatus::Done) << impulsive.message;
  ASSERT_EQ(smooth.status, RunStatus::Done) << smooth.message;
  const double cd_i = metric(impulsive, "cd_mean"), cd_s = metric(smooth, "cd_mean");
  EXPECT_GT(cd_i, 1.0);
  EXPECT_NEAR(cd_s, cd_i, 0.03 * cd_i);
}

// coefficients = "float" (the pair coefficients of the inner iterations stored in single
// precision, sums in double) gives the double run's flow. These short runs are sensitive to
// round-off-size changes (a particle entering the fluid from the inlet buffer one step earlier, a
// mirror ghost more): changing dt by 1.2e-7 relative, about float's resolution, moved cd_mean by
// 1e-3 to 4e-3 and div_mean by 8e-4 to 4e-3 relative over these 3 D/U (measured, two samples).
// Float storage moved them by 1.4e-3 / 2.6e-3 (algorithm 1) and 9e-5 / 1.4e-4 (algorithm 2), so
// the bound is 1 %: tighter would test the flow's sensitivity, not the storage. A wrong float
// coefficient is an O(1) error (the operator tests bound the storage itself at 1e-5).
TEST(CylinderChannel, FloatCoefficientsGiveTheDoubleFlow) {
  for (int alg : {1, 2}) {
    Params prm = cylinder_params();
    prm["algorithm"] = alg, prm["t_end"] = 3.0;
    const RunResult d = find_case("cylinder_channel")->run(prm, RunContext{});
    prm["coefficients"] = std::string("float");
    const RunResult f = find_case("cylinder_channel")->run(prm, RunContext{});
    ASSERT_EQ(d.status, RunStatus::Done) << d.message;
    ASSERT_EQ(f.status, RunStatus::Done) << f.message;
    for (const char* k : {"cd_mean", "div_mean"}) {
      const double a = metric(d, k), b = metric(f, k);
      EXPECT_NE(b, a) << "algorithm " << alg << ": the float storage was not used";
      EXPECT_NEAR(b, a, 1e-2 * std::abs(a)) << "algorithm " << alg << " " << k;
    }
  }
}

TEST(CylinderChannel, TooLargeTimeStepIsRecordedAsDiverged) {
  Params prm = cylinder_params();
  prm["dt_star"] = 2.0;
  prm["t_end"] = 20.0;
  const RunResult r = find_case("cylinder_channel")->run(prm, RunContext{});
  EXPECT_EQ(r.status, RunStatus::Diverged);
  EXPECT_GT(metric(r, "t_diverged"), 0.0);
  EXPECT_LT(metric(r, "t_diverged"), 20.0);
  EXPECT_TRUE(std::isnan(metric(r, "cd_mean"))); // no averages over a blow-up
  EXPECT_EQ(metric(r, "iterations_mean"), 5.0);
}

TEST(MirrorGhosts, CopiesScalarsMirrorsVectorsAndPositions) {
  MirrorGhosts<2> g;
  std::vector<Vec<2>> r{Vec<2>(0.3, 0.1), Vec<2>(0.0, 0.0)}, v{Vec<2>(1.0, -0.5), Vec<2>::Zero()};
  std::vector<double> p{2.5, 0.0};
  g.add(1, 0, 1, 0.0);
  g.copy_scalar(p), g.copy_vector(v), g.copy_positions(r);
  EXPECT_EQ(p[1], 2.5);
  EXPECT_EQ(v[1], Vec<2>(1.0, 0.5));
  EXPECT_EQ(r[1], Vec<2>(0.3, -0.1));
}
