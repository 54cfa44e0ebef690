// The cavity cases ("lid_driven_cavity", "cavity_cylinder"; cavity.hpp) run with scheme
// "wcsph_tvf" (schemes/wcsph_tvf/wcsph_tvf.hpp): seed 002 (Wang, Haidn & Hu), section 4.2, the
// lid-driven cavity against Ghia, Ghia & Shin (1982), with the metrics of the ISPH runs
// (diagnostics/cavity_profiles.hpp), so that both schemes answer the same queries.
//
// Set-up: the geometry of build_cavity (cell-centred fluid lattice, wall layers one kernel support
// deep on the same lattice, lid = the top band moving at U0 = 1; a cylinder's particles become
// walls at rest), rho0 = 1, c0 = c0_factor U0, mu = rho0 U0 L / Re, h = h_over_dx dx. Walls as in
// the scheme: density summation over walls, the pressure extrapolated into them, no-slip by the
// mirrored velocity 2 v_wall - v_i in the viscous, continuity and dissipation terms.
// Time stepping: the scheme's dual criteria (advection step with acoustic sub-steps); the case's
// `dt` parameter (ISPH's fixed step) is not used. The last two advection steps share what remains
// so that the run lands on t_end.
// Steady state: as the ISPH run, the time-weighted mean of E_k over consecutive windows of
// steady_window; steady when two consecutive means differ by less than steady_tol times the last.
// Profiles: the fluid velocities and, on the wall particles, the no-slip mirror velocity
// (operators/wall_velocity.hpp), so that the Shepard interpolation next to the lid sees the lid.
// Metrics: the profile metrics, ke, t_stop, steady, steps (advection steps), acoustic_steps,
// wall_time_s, time_per_step_s (wall per advection step), cpu_time_per_step_s,
// time_per_particle_step_s (wall per particle and acoustic sub-step), density_dev_max (largest
// |rho / rho0 - 1| of the fluid over the run: the compressibility, about (U/c0)^2 = 1 % by
// design), n_particles, n_fluid.
// Checkpoints: every particle field, the scheme's carried state, this loop's state and history
// (as the ISPH run; resumes bit for bit, tests/runner/test_checkpoint.cpp).
#include "cases/cavity.hpp"
#include "core/kernels/kernel.hpp"
#include "io/particle_checkpoint.hpp"
#include "operators/wall_velocity.hpp"
#include "schemes/wcsph_tvf/scheme_info.hpp"

#include <chrono>
#include <cmath>
#include <ctime>
#include <stdexcept>

namespace sph {
namespace {

template <class K>
RunResult run(const Params& prm, const RunContext& ctx, bool cylinder) {
  using clock = std::chrono::steady_clock;
  const auto t_start = clock::now();
  const double Re = get_real(prm, "Re"), dx = get_real(prm, "dx");
  const double t_end = get_real(prm, "t_end"), steady_tol = get_real(prm, "steady_tol");
  const double window = get_real(prm, "steady_window");
  const double out_dt = get_real(prm, "output_interval");
  const double U0 = 1.0, L = 1.0, rho0 = 1.0;

  const wcsph_tvf::Options o = wcsph_tvf::options_for_flow(prm, rho0, U0, L, Re, dx);
  const K kernel(o.h);

  const CavityGeometry g = cavity_geometry(prm, cylinder, kernel.support());
  Particles<2> p;
  const int vw = build_cavity(p, g);
  std::size_t n_fluid = 0;
  for (auto& k : p.kind) {
    if (k == Kind::Body)
      k = Kind::Wall; // the scheme's walls: the cylinder is a wall at rest
    n_fluid += k == Kind::Fluid;
  }
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == Kind::Wall)
      p.v[i] = p.vector(vw)[i];
  const wcsph_tvf::Fields f = wcsph_tvf::Fields::add_to(p, vw);
  Domain<2> box; // not periodic: the cell list follows the particles
  wcsph_tvf::Scheme<2, K> scheme(p, f, box, o);
  scheme.init();

  auto fluid_extremes = [&](double& vmax, double& drho) {
    vmax = 0.0, drho = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid) {
        const double v2 = p.v[i].squaredNorm();
        vmax = std::max(vmax, std::isfinite(v2) ? std::sqrt(v2) : 1e300);
        drho = std::max(drho, std::abs(p.rho[i] / rho0 - 1.0));
      }
  };

  RunResult res;
  std::vector<double> h_t{0.0}, h_ke{kinetic_energy(p)}, h_drho{0.0};
  double t = 0.0, next_out = out_dt, win_sum = 0.0, win_span = 0.0, ke_prev = -1.0;
  double drho_max = 0.0, cpu_before = 0.0, wall_before = 0.0;
  long steps = 0;
  bool steady = false;
  std::string resumed;

  std::vector<double> a, carried; // the loop's scalars, the scheme's state
  io::LoopCheckpoint<2> ck(ctx.checkpoint_dir, ctx.checkpoint_every_steps, ctx.checkpoint_every_s,
                           p,
                           {{"cavity/t", &h_t},
                            {"cavity/ke", &h_ke},
                            {"cavity/drho", &h_drho},
                            {"cavity/loop", &a},
                            {"cavity/scheme", &carried}});
  if (auto at = ck.restore()) {
    scheme.init();
    scheme.restore_carried_state(carried);
    io::expect_state_size(a, 7, "cavity (wcsph_tvf): checkpoint loop state");
    next_out = a[0], win_sum = a[1], win_span = a[2], ke_prev = a[3], drho_max = a[4];
    cpu_before = a[5], wall_before = a[6];
    steps = static_cast<long>(at->first), t = at->second;
    resumed = io::resumed_message(t, ctx.attempt);
  }
  const std::clock_t cpu0 = std::clock();
  auto cpu_so_far = [&] {
    return cpu_before + static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  };
  auto wall_so_far = [&] {
    return wall_before + std::chrono::duration<double>(clock::now() - t_start).count();
  };
  auto save_checkpoint = [&] {
    a = {next_out, win_sum, win_span, ke_prev, drho_max, cpu_so_far(), wall_so_far()};
    carried = scheme.carried_state();
    ck.save(steps, t);
  };

  while (t < t_end * (1.0 - 1e-12)) {
    if (stop_if_cancelled(ctx, t, res, save_checkpoint))
      return res;
    const double Dt = scheme.advance_towards(t, t_end).Dt;
    ++steps;
    double vmax = 0.0, drho = 0.0;
    fluid_extremes(vmax, drho);
    drho_max = std::max(drho_max, drho);
    if (!(vmax < 20.0 * U0)) {
      res.status = RunStatus::Diverged;
      res.message = "velocity " + std::to_string(vmax) + " at t = " + std::to_string(t);
      res.add("t_stop", t);
      return res;
    }
    const double ke = kinetic_energy(p);
    if (t >= next_out * (1.0 - 1e-12) || t >= t_end) {
      h_t.push_back(t), h_ke.push_back(ke), h_drho.push_back(drho);
      while (next_out <= t * (1.0 + 1e-12))
        next_out += out_dt;
      ctx.report(t / t_end);
    }
    win_sum += ke * Dt, win_span += Dt;
    if (win_span >= window * (1.0 - 1e-9)) {
      const double mean = win_sum / win_span;
      win_sum = win_span = 0.0;
      if (steady_tol > 0.0 && ke_prev > 0.0 && std::abs(mean - ke_prev) < steady_tol * mean) {
        steady = true;
        break;
      }
      ke_prev = mean;
    }
    if (ck.due(steps))
      save_checkpoint();
  }
  const double cpu_loop = cpu_so_far(), wall_loop = wall_so_far();
  const long acoustic = scheme.acoustic_steps();

  // Profiles: fluid velocities, and the no-slip mirror velocity on the walls (on the scheme's
  // neighbour list, built on the final positions at the end of the last step).
  WallVelocity<2> wv{p.kind, p.vector(vw), p.v};
  interact(scheme.neighbors(), wv, [&](std::size_t i) { return p.kind[i] == Kind::Wall; });
  const double R = 0.5 * g.cylinder_d;
  auto use = [&](std::size_t) { return true; };
  auto in_solid = [&](const Vec2& x) { return R > 0.0 && (x - Vec2(0.5, 0.5)).norm() < R; };
  const data::GhiaTable ghia = cylinder ? data::GhiaTable{} : data::ghia_table(Re);
  const CavityProfiles prof = cavity_profile_metrics(p, kernel, use, in_solid, ghia, res);

  const double N = static_cast<double>(p.size()), n_steps = static_cast<double>(steps);
  res.add("ke", kinetic_energy(p));
  res.add("t_stop", t);
  res.add("steady", steady ? 1.0 : 0.0);
  res.add("steps", n_steps);
  res.add("acoustic_steps", static_cast<double>(acoustic));
  res.add("wall_time_s", wall_so_far());
  res.add("time_per_step_s", wall_loop / n_steps);
  res.add("cpu_time_per_step_s", cpu_loop / n_steps);
  res.add("time_per_particle_step_s", wall_loop / (N * static_cast<double>(acoustic)));
  res.add("density_dev_max", drho_max);
  res.add("n_particles", N);
  res.add("n_fluid", static_cast<double>(n_fluid));
  res.message = cavity_run_message(steady, t, resumed);
  write_cavity_h5(ctx.output_dir, cylinder,
                  {{{"scheme", "wcsph_tvf"}, {"tvf", get_string(prm, "tvf")}},
                   {{"Re", Re}, {"dx", dx}, {"t_stop", t}}},
                  {"t", "ke", "density_dev"}, {h_t, h_ke, h_drho}, prof, p);
  ck.discard(); // the results are final
  return res;
}

} // namespace

RunResult run_cavity_wcsph_tvf(const Params& prm, const RunContext& ctx, bool cylinder) {
  return with_kernel<2>(get_string(prm, "kernel"), 1.0, [&](const auto& k) {
    return run<std::decay_t<decltype(k)>>(prm, ctx, cylinder);
  });
}

} // namespace sph
