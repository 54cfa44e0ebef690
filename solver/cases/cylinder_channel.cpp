// Case "cylinder_channel": 2D flow past a circular cylinder in a channel (seed 004, Kolukisa,
// Ozbulut & Yildiz 2021, section 3 and Figure 1), run with the ALSPH scheme (schemes/alsph).
//
// Units: D = 1, U = 1, rho = 1, nu = 1 / Re; times in D/U.
// Geometry: channel [0, L] x [0, H], L = channel_length D (14), H = channel_height D (13),
// cylinder centre (upstream_length D, H/2) (L_U = 4 D). Fluid starts on a Cartesian lattice of
// spacing dx = D / D_over_dx with u = (U, 0), p = 0, outside the cylinder.
// Boundaries:
//   top/bottom  free-slip mirror ghosts (Figure 2), regenerated every step within one support;
//   inlet       buffer zone x in [-L_b, 0) of L_b >= 6h (whole lattice columns) moving at U; a
//               buffer particle crossing x = 0 becomes fluid and a new one enters at x - L_b;
//               buffer pressure = Shepard average of the neighbouring fluid pressures;
//   outlet      fluid crossing x = L becomes outlet buffer: velocity frozen (its normal component
//               preserved) until it leaves x = L + L_b; buffer pressure p = 0 (reference);
//   cylinder    fixed particles on radial rings at spacing dx (radii R - (k + 1/2) dx, ring k with
//               round(2 pi r_k / dx) particles) down to two kernel supports deep (the rings a
//               fluid particle sees then have complete supports, so their V_i = 1/sum W is right;
//               deeper particles never meet fluid), u = 0, pressure from eq. (20)
//               (see schemes/alsph/alsph.hpp).
// Forces (section 3): the paper sums V_i rho_i a_i over the cylinder particles; we compute the same
// force as the reaction of the fluid-body pair forces (Newton's third law):
//   F = sum_{i fluid} sum_{j body} [ V_i V_j (p_i + p_j) grad_i W_ij
//                                    - 2 mu V_i V_j (r_ij . grad_i W_ij)/(r_ij^2 + eta^2) (u_i -
//                                    u_j) ],
// which needs no pressures deeper inside the cylinder than one support.
// C_D = 2 F_x / (rho U^2 D), C_L = 2 F_y / (rho U^2 D); C_p(theta) = 2 (p - p_0) / (rho U^2) on the
// outer cylinder ring, theta from the upstream stagnation point, counter-clockwise,
// p_0 = mean pressure of the fluid with x < D/2 (the "instantaneous mean inlet pressure").
//
// Symmetry breaking: the set-up is mirror-symmetric about y = H/2 and the solver keeps that
// symmetry to round-off, so shedding would start only after O(100) D/U; the initial fluid velocity
// gets a transverse component perturbation * U * exp(-|x - x_c - (D, 0)|^2 / D^2) (parameter
// `perturbation`, default 0.05; 0 for the symmetric start). The periodic state does not depend on
// it; only the onset time does.
// Start: impulsive by default (u = U everywhere at t = 0, also next to the no-slip cylinder); with
// `ramp_time` T > 0 the fluid starts at rest and the inlet velocity rises as
// U_in(t) = U (1 - cos(pi t / T)) / 2 for t < T, the fluid driven by the uniform body force
// dU_in/dt (an incompressible channel accelerates as a whole: without it the inlet buffer runs
// into resting fluid and piles up). The nudge is added as before.
// Metrics (averages over t >= settle_fraction t_end): cd_mean (eq. 21), cl_rms (eq. 23), St = f D/U
// of C_L (zero crossings; st_cycles periods; St_spectral from the periodogram peak), cd_amplitude,
// cl_amplitude (half peak-to-peak), div_mean (mean over steps of the mean |div u| over fluid),
// div_max_mean, iterations_mean, converged_fraction (steps meeting eq. 13 before max_iterations),
// t_diverged (only for a diverged run), costs: wall_s, cpu_s (process CPU), steps, n_particles,
// and per particle in CPU microseconds: iteration_cpu_us_per_particle (one inner iteration),
// search_cpu_us_per_particle (a fresh neighbour search: cells, pairs, kernel values, V, Gamma),
// search_over_iteration (their ratio), refresh_cpu_us_per_particle (algorithm 1's per-iteration
// pair refresh, included in the iteration), shifting_cpu_us_per_particle, cpu_us_per_particle_step
// (everything).
// Averages: when the lift after t_settle holds >= 2 whole periods (upward zero crossings), cd_mean,
// cl_rms, the amplitudes are taken over exactly those periods (t_average = their length).
// St is recorded only when at least one period was found; st_period_cv is the spread of the
// periods relative to their mean (small for periodic shedding).
// HDF5 (<output_dir>/cylinder_channel.h5): series/{t,cd,cl,div_mean,div_max,iterations}, one
// sample per `sample_interval` (mean of the steps in the interval),
// cp/{theta,cp_mean}.
// Checkpoints (io/checkpoint.hpp, with a checkpoint directory): the particles as they end a step
// (their count changes: inflow, outflow, ghosts), the series, the averaging sums, the scheme's
// timers and this loop's counters. A resumed job continues bit for bit (tested): each step
// starts by dropping the ghosts and regenerating them, and the cell sort starts from the saved
// order, as in the uninterrupted run.
#include "cases/case.hpp"
#include "cases/shedding.hpp"
#include "core/cell_list.hpp"
#include "core/kernels/quintic_spline.hpp"
#include "core/neighbor_list.hpp"
#include "io/hdf5.hpp"
#include "io/particle_checkpoint.hpp"
#include "schemes/alsph/alsph.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <omp.h>
#include <sstream>

namespace sph {
namespace {

constexpr int D = 2;
using V2 = Vec<2>;

// Removes the particles with keep[i] == 0, preserving order, for every field the case uses (the
// common ones and the normal vector field).
void compact(Particles<D>& p, const std::vector<char>& keep, int normal_field) {
  std::size_t w = 0;
  auto& nrm = p.vector(normal_field);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!keep[i])
      continue;
    if (w != i) {
      p.r[w] = p.r[i], p.v[w] = p.v[i], p.m[w] = p.m[i], p.rho[w] = p.rho[i], p.p[w] = p.p[i];
      p.V[w] = p.V[i], p.kind[w] = p.kind[i], p.id[w] = p.id[i], nrm[w] = nrm[i];
    }
    ++w;
  }
  p.r.resize(w), p.v.resize(w), p.m.resize(w), p.rho.resize(w), p.p.resize(w), p.V.resize(w);
  p.kind.resize(w), p.id.resize(w), nrm.resize(w);
}

// Buffer pressure: inlet (x < 0) Shepard average of fluid neighbours; outlet p = 0.
struct BufferPressureOp {
  const std::vector<Kind>& kind;
  const std::vector<V2>& r;
  std::vector<double>& p;
  struct Acc {
    double num = 0.0, den = 0.0;
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t, const Pair<D>& q, Acc& a) const {
    if (kind[q.j] == Kind::Fluid)
      a.num += q.W * p[q.j], a.den += q.W;
  }
  void finish(std::size_t i, const Acc& a) {
    p[i] = (r[i][0] < 0.0 && a.den > 0.0) ? a.num / a.den : 0.0;
  }
};

// Force of the body particles on each fluid particle (see header comment), stored per particle.
struct BodyForceOp {
  const std::vector<Kind>& kind;
  const std::vector<double>& V;
  const std::vector<double>& p;
  const std::vector<V2>& u;
  double mu, eta2;
  std::vector<V2>& f;
  struct Acc {
    V2 f = V2::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    if (kind[q.j] != Kind::Body)
      return;
    const V2 gw = q.grad();
    const double vv = V[i] * V[q.j];
    a.f -= vv * (p[i] + p[q.j]) * gw;
    a.f += (2.0 * mu * vv * q.r_ij.dot(gw) / (q.r * q.r + eta2)) * (u[i] - u[q.j]);
  }
  void finish(std::size_t i, const Acc& a) { f[i] = a.f; }
};

RunResult run_cylinder_channel(const Params& prm, const RunContext& ctx) {
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = alsph::cpu_seconds();
  omp_set_num_threads(std::max(1, ctx.threads));
  const double Re = get_real(prm, "Re");
  const double dx = 1.0 / get_real(prm, "D_over_dx");
  const double h = get_real(prm, "h_over_dx") * dx;
  const double dt = get_real(prm, "dt_star") * dx; // dt U / dx, U = 1
  const double t_end = get_real(prm, "t_end");
  const double t_settle = get_real(prm, "settle_fraction") * t_end;
  const double speed_bound = get_real(prm, "speed_bound");
  const double perturbation = get_real(prm, "perturbation");
  const double ramp_time = get_real(prm, "ramp_time");
  const int nx = static_cast<int>(std::lround(get_real(prm, "channel_length") / dx));
  const int ny = static_cast<int>(std::lround(get_real(prm, "channel_height") / dx));
  const double L = nx * dx, H = ny * dx;
  const V2 c(get_real(prm, "upstream_length"), 0.5 * H);
  const double R = 0.5, U = 1.0, rho = 1.0, nu = U * 1.0 / Re;
  auto inflow_speed = [&](double time) {
    return time < ramp_time ? 0.5 * U * (1.0 - std::cos(std::numbers::pi * time / ramp_time)) : U;
  };

  alsph::Settings s;
  s.c_bv = get_real(prm, "c_bv");
  s.epsilon = get_real(prm, "epsilon");
  s.max_iterations = static_cast<int>(get_int(prm, "max_iterations"));
  s.algorithm = static_cast<int>(get_int(prm, "algorithm"));
  s.shifting = get_bool(prm, "shifting");
  s.nu = nu, s.rho = rho, s.dt = dt;

  const QuinticSpline<D> kernel(h);
  const double support = kernel.support();
  const int nb = static_cast<int>(std::ceil(6.0 * h / dx - 1e-9));
  const double Lb = nb * dx;
  if (c[0] - R < 2.0 * support || c[0] + R > L - 2.0 * support || R + 2 * support > 0.5 * H)
    throw std::invalid_argument("cylinder_channel: the cylinder must lie two supports inside");

  // --- initial particles -------------------------------------------------------------------
  Particles<D> p;
  const int normal = p.add_vector("normal");
  const double mass = rho * dx * dx;
  std::int64_t next_id = 0;
  auto add = [&](const V2& x, Kind k, const V2& v) {
    const std::size_t i = p.add(x, mass, rho, k);
    p.v[i] = v;
    p.id[i] = next_id++;
    return i;
  };
  // Body rings, outer ring first: its particles are ids [0, n_ring0).
  std::vector<double> theta0;
  for (int k = 0;; ++k) {
    const double rk = R - (k + 0.5) * dx;
    if (rk <= 0.25 * dx || (k + 0.5) * dx > 2.0 * support)
      break;
    const int n = std::max(1, static_cast<int>(std::lround(2.0 * std::numbers::pi * rk / dx)));
    for (int a = 0; a < n; ++a) {
      const double th = (a + 0.5) * 2.0 * std::numbers::pi / n; // from the upstream point
      const V2 nrm(-std::cos(th), std::sin(th));
      const std::size_t i = add(c + rk * nrm, Kind::Body, V2::Zero());
      p.vector(normal)[i] = nrm;
      if (k == 0)
        theta0.push_back(th);
    }
  }
  const std::size_t n_ring0 = theta0.size();
  for (int j = 0; j < ny; ++j) {
    for (int i = -nb; i < nx; ++i) {
      const V2 x((i + 0.5) * dx, (j + 0.5) * dx);
      if ((x - c).norm() < R)
        continue;
      // Symmetry breaking (see header): a transverse nudge centred one D behind the cylinder.
      const V2 w = x - c - V2(1.0, 0.0);
      add(x, i < 0 ? Kind::Buffer : Kind::Fluid,
          V2(inflow_speed(0.0), i < 0 ? 0.0 : perturbation * U * std::exp(-w.squaredNorm())));
    }
  }

  Domain<D> box; // not periodic: the cell list follows the particles
  CellList<D> cells(box, support);
  NeighborList<D> nl;
  MirrorGhosts<D> ghosts;
  alsph::Scheme<D, QuinticSpline<D>> scheme(kernel, s);
  std::vector<char> keep;
  std::vector<std::int64_t> ghost_src_old; // per particle before the build: source index or -1
  std::vector<std::uint32_t> inv;
  std::vector<V2> fbody;
  const double eta2 = std::pow(s.eta_over_h * h, 2);

  // Time series, one sample per sample_interval: each sample is the mean over the steps of its
  // interval (a box filter: the step-to-step force noise of SPH averages out instead of aliasing).
  std::vector<double> ts, cds, cls, divs, divmax, iters;
  struct Bin {
    double t = 0, cd = 0, cl = 0, div = 0, divmax = 0, it = 0;
    int n = 0;
  } bin;
  const double sample_interval = std::max(get_real(prm, "sample_interval"), dt);
  double next_sample = sample_interval;
  // Per-step sums after the settling time (div_mean, div_max_mean average every step).
  double div_sum = 0.0, divmax_sum = 0.0;
  long settled_steps = 0;
  std::vector<double> cp_sum(n_ring0, 0.0);
  double cp_time = 0.0;
  long steps = 0, converged_steps = 0, total_iterations = 0;
  double search_s = 0.0;
  std::size_t n_max = 0;
  RunResult res;
  RunStatus status = RunStatus::Done;
  std::string why;
  double t = 0.0;
  auto buffer_pressure = [&](Particles<D>& q, const NeighborList<D>& list) {
    BufferPressureOp op{q.kind, q.r, q.p};
    interact(list, op, [&](std::size_t i) { return q.kind[i] == Kind::Buffer; });
  };

  const long n_steps = static_cast<long>(std::ceil(t_end / dt - 1e-9));
  double cpu_before = 0.0, wall_before = 0.0; // spent by earlier attempts (checkpoints)
  std::string resumed;
  std::vector<double> a, carried; // the loop's scalars, the scheme's state
  io::LoopCheckpoint<D> ck(ctx.checkpoint_dir, ctx.checkpoint_every_steps, ctx.checkpoint_every_s,
                           p,
                           {{"cc/t", &ts},
                            {"cc/cd", &cds},
                            {"cc/cl", &cls},
                            {"cc/div", &divs},
                            {"cc/divmax", &divmax},
                            {"cc/iters", &iters},
                            {"cc/cp_sum", &cp_sum},
                            {"cc/loop", &a},
                            {"cc/scheme", &carried}});
  if (auto at = ck.restore()) {
    scheme.restore_carried_state(carried);
    io::expect_state_size(a, 19, "cylinder_channel: checkpoint loop state");
    bin = Bin{a[0], a[1], a[2], a[3], a[4], a[5], static_cast<int>(a[6])};
    next_sample = a[7], div_sum = a[8], divmax_sum = a[9];
    settled_steps = static_cast<long>(a[10]), cp_time = a[11];
    converged_steps = static_cast<long>(a[12]), total_iterations = static_cast<long>(a[13]);
    search_s = a[14], n_max = static_cast<std::size_t>(a[15]);
    next_id = static_cast<std::int64_t>(a[16]), cpu_before = a[17], wall_before = a[18];
    steps = static_cast<long>(at->first), t = at->second;
    resumed = io::resumed_message(t, ctx.attempt);
  }
  auto cpu_so_far = [&] { return cpu_before + alsph::cpu_seconds() - cpu0; };
  auto wall_so_far = [&] {
    return wall_before +
           std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  };
  auto save_checkpoint = [&] {
    a = {bin.t,
         bin.cd,
         bin.cl,
         bin.div,
         bin.divmax,
         bin.it,
         static_cast<double>(bin.n),
         next_sample,
         div_sum,
         divmax_sum,
         static_cast<double>(settled_steps),
         cp_time,
         static_cast<double>(converged_steps),
         static_cast<double>(total_iterations),
         search_s,
         static_cast<double>(n_max),
         static_cast<double>(next_id),
         cpu_so_far(),
         wall_so_far()};
    carried = scheme.carried_state();
    ck.save(steps, t);
  };

  for (long step = steps; step < n_steps; ++step) {
    if (ctx.cancelled()) {
      save_checkpoint();
      status = RunStatus::Cancelled;
      why = "cancelled";
      break;
    }
    // 1. Drop last step's ghosts and particles that left the outlet buffer.
    keep.assign(p.size(), 1);
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Wall || p.r[i][0] >= L + Lb)
        keep[i] = 0;
    compact(p, keep, normal);
    // 2. Inlet: buffer particles crossing x = 0 become fluid, a new one enters L_b upstream.
    //    Outlet: fluid crossing x = L becomes buffer (velocity frozen from now on).
    const std::size_t n0 = p.size();
    for (std::size_t i = 0; i < n0; ++i) {
      if (p.kind[i] == Kind::Buffer && p.r[i][0] >= 0.0 && p.r[i][0] < 0.5 * L) {
        p.kind[i] = Kind::Fluid;
        const std::size_t k =
            add(V2(p.r[i][0] - Lb, p.r[i][1]), Kind::Buffer, V2(inflow_speed(t + dt), 0.0));
        p.p[k] = p.p[i];
      } else if (p.kind[i] == Kind::Fluid && p.r[i][0] >= L) {
        p.kind[i] = Kind::Buffer;
      }
    }
    if (t < ramp_time) // smooth start: the inlet buffer moves at this step's inflow speed
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Buffer && p.r[i][0] < 0.0)
          p.v[i] = V2(inflow_speed(t + dt), 0.0);
    // 3. Mirror ghosts of every particle within one support of the top or bottom wall.
    const std::size_t n1 = p.size();
    ghost_src_old.assign(n1, -1);
    for (std::size_t i = 0; i < n1; ++i) {
      if (p.kind[i] != Kind::Fluid && p.kind[i] != Kind::Buffer)
        continue;
      const double y = p.r[i][1];
      for (int side = 0; side < 2; ++side) {
        const double plane = side == 0 ? 0.0 : H;
        if (std::abs(y - plane) >= support)
          continue;
        V2 x = p.r[i];
        x[1] = 2.0 * plane - y;
        V2 v = p.v[i];
        v[1] = -v[1];
        const std::size_t g = add(x, Kind::Wall, v);
        p.p[g] = p.p[i];
        ghost_src_old.push_back(static_cast<std::int64_t>(i));
      }
    }
    n_max = std::max(n_max, p.size());
    // 4. The one neighbour search of the step.
    const double ts0 = alsph::cpu_seconds();
    cells.build(p);
    nl.build(cells, p.r, kernel);
    search_s += alsph::cpu_seconds() - ts0;
    // 5. Ghost -> source in the new order.
    const auto& perm = cells.perm();
    inv.resize(perm.size());
    for (std::size_t i = 0; i < perm.size(); ++i)
      inv[perm[i]] = static_cast<std::uint32_t>(i);
    ghosts.clear();
    for (std::size_t i = 0; i < perm.size(); ++i) {
      const std::int64_t so = ghost_src_old[perm[i]];
      if (so < 0)
        continue;
      const std::uint32_t src = inv[static_cast<std::size_t>(so)];
      ghosts.add(static_cast<std::uint32_t>(i), src, 1, p.r[src][1] < 0.5 * H ? 0.0 : H);
    }
    // 6. ALSPH step.
    // Smooth start: the whole channel accelerates with the inlet (a uniform body force equal to
    // the inflow's acceleration at mid-step; the cylinder feels it through the pressure).
    const V2 g = t < ramp_time ? V2(0.5 * U * std::numbers::pi / ramp_time *
                                        std::sin(std::numbers::pi * (t + 0.5 * dt) / ramp_time),
                                    0.0)
                               : V2::Zero();
    const alsph::StepStats st = scheme.step(p, nl, ghosts, p.vector(normal), buffer_pressure, g);
    t = (step + 1) * dt;
    ++steps;
    total_iterations += st.iterations;
    converged_steps += st.converged ? 1 : 0;

    // 7. Forces and pressure coefficient.
    fbody.resize(p.size());
    BodyForceOp fo{p.kind, p.V, p.p, p.v, rho * nu, eta2, fbody};
    interact(nl, fo, [&](std::size_t i) { return p.kind[i] == Kind::Fluid; });
    V2 F = V2::Zero();
    double p0 = 0.0;
    long n_in = 0;
    bool bad = false;
    double vmax2 = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.kind[i] != Kind::Fluid)
        continue;
      F -= fbody[i];
      if (p.r[i][0] < 0.5)
        p0 += p.p[i], ++n_in;
      vmax2 = std::max(vmax2, p.v[i].squaredNorm());
      if (!std::isfinite(p.p[i]) || !std::isfinite(p.v[i][0]) || !std::isfinite(p.v[i][1]) ||
          std::abs(p.r[i][1] - 0.5 * H) > 0.5 * H + support || p.r[i][0] < -Lb - support)
        bad = true;
    }
    p0 = n_in ? p0 / n_in : 0.0;
    const double q = 0.5 * rho * U * U * 1.0;
    bin.t += t, bin.cd += F[0] / q, bin.cl += F[1] / q, bin.div += st.div_mean;
    bin.divmax += st.div_max, bin.it += st.iterations, ++bin.n;
    if (t >= next_sample - 1e-9 * dt || step + 1 == n_steps) {
      const double w = 1.0 / bin.n;
      ts.push_back(bin.t * w), cds.push_back(bin.cd * w), cls.push_back(bin.cl * w);
      divs.push_back(bin.div * w), divmax.push_back(bin.divmax * w), iters.push_back(bin.it * w);
      bin = Bin{};
      while (next_sample <= t + 1e-9 * dt)
        next_sample += sample_interval;
    }
    if (t >= t_settle) {
      div_sum += st.div_mean, divmax_sum += st.div_max, ++settled_steps;
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Body && static_cast<std::size_t>(p.id[i]) < n_ring0)
          cp_sum[p.id[i]] += dt * (p.p[i] - p0) / q;
      cp_time += dt;
    }
    // 8. Divergence detection.
    if (bad || !std::isfinite(F[0]) || !std::isfinite(F[1]) || std::sqrt(vmax2) > speed_bound * U) {
      status = RunStatus::Diverged;
      std::ostringstream os;
      os << "diverged at t = " << t << " (step " << steps
         << "): " << (bad ? "NaN or particle out of the channel" : "speed or force beyond bound")
         << ", max |u| = " << std::sqrt(vmax2);
      why = os.str();
      break;
    }
    if (ck.due(steps))
      save_checkpoint();
    ctx.report(t / t_end);
  }

  if (bin.n > 0) { // the partial interval of a run that stopped early (diverged, cancelled)
    const double w = 1.0 / bin.n;
    ts.push_back(bin.t * w), cds.push_back(bin.cd * w), cls.push_back(bin.cl * w);
    divs.push_back(bin.div * w), divmax.push_back(bin.divmax * w), iters.push_back(bin.it * w);
  }

  // --- metrics -----------------------------------------------------------------------------
  const double t_avg = std::min(t_settle, ts.empty() ? 0.0 : ts.back());
  // Flow metrics only for a run that reached t_end: averages over a blow-up mean nothing (a
  // diverged run records t_diverged, iteration counts and costs).
  if (status == RunStatus::Done) {
    // Shedding frequency and force coefficients after the settling time (cases/shedding.hpp).
    const AveragingWindow w = add_shedding_metrics(ts, cds, cls, t_avg, 1.0 / U, res);
    // Mean over the steps after the settling time of the mean |div u| over the fluid (section 3).
    if (settled_steps > 0) {
      res.add("div_mean", div_sum / settled_steps);
      res.add("div_max_mean", divmax_sum / settled_steps);
    }
    res.add("t_average", w.whole_periods ? w.t1 - w.t0 : t - w.t0);
  }
  res.add("iterations_mean", steps ? double(total_iterations) / steps : 0.0);
  res.add("converged_fraction", steps ? double(converged_steps) / steps : 0.0);
  if (status == RunStatus::Diverged)
    res.add("t_diverged", t);
  const double wall = wall_so_far();
  const auto& tm = scheme.timers();
  res.add("wall_s", wall);
  res.add("steps", static_cast<double>(steps));
  res.add("t_end_reached", t);
  res.add("n_particles", static_cast<double>(n_max));
  res.add("dt", dt);
  res.add("cpu_s", cpu_so_far());
  if (steps > 0 && tm.particle_steps > 0) {
    // Costs in process CPU time. A "fresh search" is what a new neighbour configuration costs:
    // cell list + pair list with kernel values + V, Gamma. An inner iteration is eqs. (8)-(12)
    // with its derivative evaluation (algorithm 1: plus its pair refresh and V, Gamma).
    const double search_us = 1e6 * (search_s + tm.geometry) / tm.particle_steps;
    res.add("search_cpu_us_per_particle", search_us);
    res.add("shifting_cpu_us_per_particle", 1e6 * tm.shifting / tm.particle_steps);
    res.add("cpu_us_per_particle_step", 1e6 * cpu_so_far() / tm.particle_steps);
    if (tm.particle_iterations > 0) {
      const double it_us = 1e6 * tm.iterations / tm.particle_iterations;
      res.add("iteration_cpu_us_per_particle", it_us);
      res.add("refresh_cpu_us_per_particle", 1e6 * tm.refresh / tm.particle_iterations);
      res.add("search_over_iteration", search_us / it_us);
    }
  }
  res.message = why;
  if (!resumed.empty())
    res.message += (why.empty() ? "" : "; ") + resumed;

  if (!ctx.output_dir.empty()) {
    std::filesystem::create_directories(ctx.output_dir);
    io::H5Writer w(ctx.output_dir / "cylinder_channel.h5");
    w.write_columns("series", {"t", "cd", "cl", "div_mean", "div_max", "iterations"},
                    {ts, cds, cls, divs, divmax, iters});
    std::vector<double> cp_mean(n_ring0, 0.0);
    for (std::size_t k = 0; k < n_ring0; ++k)
      cp_mean[k] = cp_time > 0 ? cp_sum[k] / cp_time : 0.0;
    w.write("cp/theta", theta0);
    w.write("cp/cp_mean", cp_mean);
    w.attribute("case", "cylinder_channel");
    w.attribute("scheme", "alsph");
    w.attribute("Re", Re);
    w.attribute("D_over_dx", 1.0 / dx);
    w.attribute("dt_star", dt / dx);
    w.attribute("t_settle", t_avg);
    w.attribute("status", status == RunStatus::Done       ? "done"
                          : status == RunStatus::Diverged ? "diverged"
                                                          : "cancelled");
    w.close();
  }
  res.status = status;
  if (status == RunStatus::Done)
    ck.discard(); // the results are final
  return res;
}

} // namespace

CaseInfo make_cylinder_channel_case() {
  CaseInfo c;
  c.name = "cylinder_channel";
  c.description = "2D flow past a cylinder in a channel, C_D, C_L, St (Kolukisa, Ozbulut & "
                  "Yildiz 2021, Symmetry 13:472, section 3)";
  c.schemes = {"alsph"};
  c.params = {
      {"Re", ParamType::Real, 200.0, "Reynolds number U D / nu", 0.0, 1e5, true},
      {"D_over_dx", ParamType::Real, 20.0, "particles per cylinder diameter D / dx", 4.0, 400.0},
      {"dt_star", ParamType::Real, 5.08e-3, "dimensionless time step dt U / dx", 0.0, 10.0, true},
      {"t_end", ParamType::Real, 100.0, "simulated time in D / U", 0.0, 1e5, true},
      {"settle_fraction", ParamType::Real, 0.5, "averages and St use t >= settle_fraction * t_end",
       0.0, 0.99},
      {"channel_length", ParamType::Real, 14.0, "channel length L in D", 2.0, 1000.0},
      {"channel_height", ParamType::Real, 13.0, "channel height H in D", 2.0, 1000.0},
      {"upstream_length", ParamType::Real, 4.0, "cylinder centre to inlet L_U in D", 1.0, 1000.0},
      {"h_over_dx", ParamType::Real, 1.2, "smoothing length h / dx (quintic kernel, support 3h)",
       0.5, 3.0},
      {"perturbation", ParamType::Real, 0.05,
       "initial transverse velocity nudge behind the cylinder, in U (breaks the symmetry)", 0.0,
       1.0},
      {"ramp_time", ParamType::Real, 0.0,
       "smooth start: fluid at rest, inlet speed U (1 - cos(pi t / T)) / 2 up to T (in D/U; 0: "
       "impulsive start, u = U everywhere)",
       0.0, 1e4},
      {"speed_bound", ParamType::Real, 10.0, "diverged when max |u| exceeds this many U", 1.0, 1e6},
      {"sample_interval", ParamType::Real, 0.02,
       "time series sample interval in D/U (each sample averages the steps of its interval)", 0.0,
       1e3},
  };
  c.run = [](const Params& prm, const RunContext& ctx) { return run_cylinder_channel(prm, ctx); };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_cylinder_channel_case()); // core/registry.hpp
} // namespace

} // namespace sph
