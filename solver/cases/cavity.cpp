// Geometry, parameters and run loop of the cavity cases (see cavity.hpp).
//
// Run loop (scheme-independent part): advance until t_end, or until the flow is steady: the
// kinetic energy E_k is averaged over each window of steady_window time units (every step), and
// the run stops when two consecutive window means differ by less than steady_tol times the last
// (recorded: t_stop, steady = 1). The window mean, not E_k at one instant, because particle
// disorder makes E_k flicker by a few 1e-3 at a steady state (measured: +-0.3 % at Re = 100,
// dx = 0.02), which an instantaneous comparison would never see settle. Diverged when a
// velocity is not finite or exceeds 20 U0. At the end the centreline profiles and metrics of
// diagnostics/cavity_profiles.hpp are computed; with an output directory the HDF5 file
// <output_dir>/<case>.h5 holds the E_k history, the fine-line profiles and the final fields.
//
// Metrics besides the profiles: ke, div_max (max |div u| of the final velocity, eq. 4, fluid
// particles) and its position div_max_x, div_max_y, div_rms (RMS over the fluid), t_stop,
// steady, steps, wall_time_s, time_per_step_s (wall clock), cpu_time_per_step_s (process CPU
// time of the time loop over its steps: the honest cost on a shared machine, where wall time
// also counts the other processes), ppe_assembly_s_per_step, ppe_solve_s_per_step, ppe_share
// (assembly + solve over the step, wall clock), ppe_iters_mean, ppe_residual (relative residual
// of the last solve), wall_clearance_corrections (see isph.hpp), n_particles, n_fluid.
//
// Checkpoints (io/checkpoint.hpp, with a checkpoint directory): every particle field (the
// pressure is the PPE's warm start), the scheme's counters, this loop's state (the steady-state
// window, CPU and wall time so far) and the E_k history. A resumed job rebuilds the initial lattice
// (so the scheme's reference density is the same), restores the particles and continues bit for
// bit: the saved particles are in the order of the last neighbour search's cells plus that step's
// motion, exactly what the uninterrupted run sorts next.
#include "cases/cavity.hpp"

#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "diagnostics/cavity_profiles.hpp"
#include "io/hdf5.hpp"
#include "io/particle_checkpoint.hpp"
#include "io/particle_fields.hpp"
#include "schemes/isph/isph.hpp"

#include <chrono>
#include <cmath>
#include <ctime>
#include <omp.h>
#include <stdexcept>

namespace sph {

int build_cavity(Particles<2>& p, const CavityGeometry& g) {
  if (p.size() != 0)
    throw std::invalid_argument("build_cavity: particle set must be empty");
  const int n = static_cast<int>(std::lround(1.0 / g.dx));
  if (n < 4 || std::abs(n * g.dx - 1.0) > 1e-9)
    throw std::invalid_argument("cavity: 1/dx must be an integer >= 4, got dx = " +
                                std::to_string(g.dx));
  const int L = g.layers;
  const double R = 0.5 * g.cylinder_d, m = g.dx * g.dx, rho0 = 1.0;
  const Vec2 c(0.5, 0.5);
  std::vector<Vec2> vw;
  for_each_lattice_point<2>({-L, -L}, {n + L, n + L}, g.dx,
                            [&](const Vec2& x, const std::array<int, 2>& i) {
                              const bool inside = i[0] >= 0 && i[0] < n && i[1] >= 0 && i[1] < n;
                              if (inside) {
                                const double d = (x - c).norm();
                                if (R > 0.0 && d < R) {
                                  if (d > R - L * g.dx)
                                    p.add(x, m, rho0, Kind::Body), vw.push_back(Vec2::Zero());
                                  return;
                                }
                                p.add(x, m, rho0, Kind::Fluid), vw.push_back(Vec2::Zero());
                              } else {
                                p.add(x, m, rho0, Kind::Wall);
                                vw.push_back(i[1] >= n ? Vec2(g.U0, 0.0) : Vec2::Zero());
                              }
                            });
  const int f = p.add_vector("v_wall");
  p.vector(f) = vw;
  return f;
}

CavityGeometry cavity_geometry(const Params& prm, bool cylinder, double support) {
  CavityGeometry g;
  g.dx = get_real(prm, "dx");
  g.U0 = 1.0;
  g.layers = static_cast<int>(std::ceil(support / g.dx - 1e-9));
  g.cylinder_d = cylinder ? get_real(prm, "cylinder_d") : 0.0;
  return g;
}

std::vector<ParamSpec> cavity_params(bool cylinder) {
  std::vector<ParamSpec> s = {
      {"Re", ParamType::Real, 1000.0, "Reynolds number U0 L / nu (U0 = L = 1)", 0.0, {}, true},
      {"dx", ParamType::Real, 0.01, "particle spacing (1/dx must be an integer)", 0.0, 0.25, true},
      {"dt",
       ParamType::Real,
       0.001,
       "time step (isph; wcsph_tvf takes its own dual-criteria steps)",
       0.0,
       {},
       true},
      {"t_end", ParamType::Real, 40.0, "end time unless steady earlier", 0.0, {}, true},
      {"steady_tol", ParamType::Real, 5e-4,
       "stop when the means of E_k over two consecutive windows differ by less than steady_tol "
       "times the last (0: run to t_end)",
       0.0, 1.0},
      {"steady_window",
       ParamType::Real,
       2.0,
       "length of the E_k averaging window (time)",
       0.0,
       {},
       true},
      {"output_interval",
       ParamType::Real,
       0.1,
       "time between samples of the E_k history",
       0.0,
       {},
       true,
       {},
       false},
  };
  if (cylinder)
    s.push_back(
        {"cylinder_d", ParamType::Real, 0.5, "cylinder diameter / L (centred)", 0.0, 0.9, true});
  return s;
}

namespace {

template <class Kernel>
RunResult run_cavity_isph(const Params& prm, const RunContext& ctx, bool cylinder,
                          const Kernel& kernel, const IsphOptions& opt) {
  using clock = std::chrono::steady_clock;
  const auto t_start = clock::now();
  const double Re = get_real(prm, "Re"), dx = get_real(prm, "dx"), dt = get_real(prm, "dt");
  const double t_end = get_real(prm, "t_end"), steady_tol = get_real(prm, "steady_tol");
  const double window = get_real(prm, "steady_window");
  const double out_dt = get_real(prm, "output_interval");
  const double U0 = 1.0, nu = U0 * 1.0 / Re;

  const CavityGeometry g = cavity_geometry(prm, cylinder, kernel.support());
  Particles<2> p;
  const int vw = build_cavity(p, g);
  std::size_t n_fluid = 0;
  for (auto k : p.kind)
    n_fluid += k == Kind::Fluid;

  Domain<2> box;
  Isph<2, Kernel> solver(p, box, kernel, opt, vw, nu, dt, dx);

  RunResult res;
  std::vector<double> h_t, h_ke, h_div, h_it;
  const long n_steps = static_cast<long>(std::ceil(t_end / dt - 1e-9));
  const long out_every = std::max(1L, std::lround(out_dt / dt));
  const long steady_every = std::max(1L, std::lround(window / dt));
  double ke_prev = -1.0, ke_sum = 0.0, t = 0.0;
  double cpu_before = 0.0, wall_before = 0.0; // spent by earlier attempts (checkpoints)
  bool steady = false;
  long n = 0;
  std::string resumed;

  std::vector<double> loop, carried;
  io::LoopCheckpoint<2> ck(ctx.checkpoint_dir, ctx.checkpoint_every_steps, ctx.checkpoint_every_s,
                           p,
                           {{"cavity/t", &h_t},
                            {"cavity/ke", &h_ke},
                            {"cavity/div", &h_div},
                            {"cavity/iters", &h_it},
                            {"cavity/loop", &loop},
                            {"cavity/scheme", &carried}});
  if (auto at = ck.restore()) {
    solver.restore_carried_state(carried);
    ke_prev = loop.at(0), ke_sum = loop.at(1), cpu_before = loop.at(2), wall_before = loop.at(3);
    n = static_cast<long>(at->first), t = at->second;
    resumed = io::resumed_message(t, ctx.attempt);
  }
  const std::clock_t cpu0 = std::clock();
  auto cpu_so_far = [&] {
    return cpu_before + static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  };
  auto save_checkpoint = [&](long steps_done) {
    const double wall = std::chrono::duration<double>(clock::now() - t_start).count();
    loop = {ke_prev, ke_sum, cpu_so_far(), wall_before + wall};
    carried = solver.carried_state();
    ck.save(steps_done, t);
  };

  for (; n < n_steps; ++n) {
    if (stop_if_cancelled(ctx, t, res, [&] { save_checkpoint(n); }))
      return res;
    const bool sample = (n + 1) % out_every == 0 || n + 1 == n_steps;
    solver.set_measure_divergence(sample);
    try {
      solver.step();
    } catch (const std::runtime_error& e) { // a failed PPE solve: the particle state is broken
      res.status = RunStatus::Diverged;
      res.message = std::string(e.what()) + " at t = " + std::to_string(t);
      res.add("t_stop", t);
      return res;
    }
    t = (n + 1) * dt;
    if (sample) {
      double vmax = 0.0;
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Fluid)
          vmax = std::max(vmax, std::isfinite(p.v[i].squaredNorm()) ? p.v[i].norm() : 1e300);
      if (!(vmax < 20.0 * U0)) {
        res.status = RunStatus::Diverged;
        res.message = "velocity " + std::to_string(vmax) + " at t = " + std::to_string(t);
        res.add("t_stop", t);
        return res;
      }
      h_t.push_back(t), h_ke.push_back(kinetic_energy(p)), h_div.push_back(solver.div_max());
      h_it.push_back(solver.last_iterations());
      ctx.report(t / t_end);
    }
    ke_sum += kinetic_energy(p);
    if ((n + 1) % steady_every == 0) {
      const double ke = ke_sum / static_cast<double>(steady_every);
      ke_sum = 0.0;
      if (steady_tol > 0.0 && ke_prev > 0.0 && std::abs(ke - ke_prev) < steady_tol * ke) {
        steady = true;
        ++n;
        break;
      }
      ke_prev = ke;
    }
    if (ck.due(n + 1))
      save_checkpoint(n + 1);
  }
  const double cpu_loop = cpu_so_far();
  // Final divergence of the last step's velocity (measured on the configuration it was made on).
  double div_max = solver.div_max();
  const double div_rms = solver.div_rms();
  const Vec2 div_at = solver.div_argmax();
  if (!(h_t.size() && h_t.back() == t)) {
    h_t.push_back(t), h_ke.push_back(kinetic_energy(p)), h_div.push_back(div_max);
    h_it.push_back(solver.last_iterations());
  }

  solver.update_wall_velocity();
  const double R = 0.5 * g.cylinder_d;
  auto use = [&](std::size_t) { return true; };
  auto in_solid = [&](const Vec2& x) { return R > 0.0 && (x - Vec2(0.5, 0.5)).norm() < R; };
  const data::GhiaTable ghia = cylinder ? data::GhiaTable{} : data::ghia_table(Re);
  CavityProfiles prof = cavity_profile_metrics(p, kernel, use, in_solid, ghia, res);

  const double wall = wall_before + std::chrono::duration<double>(clock::now() - t_start).count();
  const double steps = static_cast<double>(solver.steps());
  res.add("ke", kinetic_energy(p));
  res.add("div_max", div_max);
  res.add("div_max_x", div_at.x());
  res.add("div_max_y", div_at.y());
  res.add("div_rms", div_rms);
  res.add("t_stop", t);
  res.add("steady", steady ? 1.0 : 0.0);
  res.add("steps", steps);
  res.add("wall_time_s", wall);
  res.add("time_per_step_s", solver.time_step() / steps);
  res.add("cpu_time_per_step_s", cpu_loop / steps);
  res.add("ppe_assembly_s_per_step", solver.time_assemble() / steps);
  res.add("ppe_solve_s_per_step", solver.time_solve() / steps);
  res.add("ppe_share", (solver.time_assemble() + solver.time_solve()) / solver.time_step());
  res.add("ppe_iters_mean", static_cast<double>(solver.iterations_total()) / steps);
  res.add("ppe_residual", solver.ppe_residual());
  res.add("wall_clearance_corrections", static_cast<double>(solver.clearance_corrections()));
  res.add("n_particles", static_cast<double>(p.size()));
  res.add("n_fluid", static_cast<double>(n_fluid));
  res.message = cavity_run_message(steady, t, resumed);
  write_cavity_h5(ctx.output_dir, cylinder,
                  {{{"scheme", "isph"}, {"visc", get_string(prm, "visc")}},
                   {{"Re", Re}, {"dx", dx}, {"t_stop", t}}},
                  {"t", "ke", "div_max", "ppe_iters"}, {h_t, h_ke, h_div, h_it}, prof, p);
  ck.discard(); // the results are final
  return res;
}

} // namespace

std::string cavity_run_message(bool steady, double t, const std::string& resumed) {
  std::string m = steady ? "steady at t = " + std::to_string(t) : "reached t_end";
  return resumed.empty() ? m : m + "; " + resumed;
}

void write_cavity_h5(const std::filesystem::path& output_dir, bool cylinder,
                     const CavityAttributes& attrs, const std::vector<std::string>& history_names,
                     const std::vector<std::vector<double>>& history, const CavityProfiles& prof,
                     const Particles<2>& p) {
  if (output_dir.empty())
    return;
  io::H5Writer w(output_dir /
                 (std::string(cylinder ? "cavity_cylinder" : "lid_driven_cavity") + ".h5"));
  for (const auto& [k, v] : attrs.text)
    w.attribute(k, v);
  for (const auto& [k, v] : attrs.number)
    w.attribute(k, v);
  w.write_columns("history", history_names, history);
  w.write_columns("profile_x0.5", {"y", "ux"}, {prof.y_line, prof.ux_line});
  w.write_columns("profile_y0.5", {"x", "uy"}, {prof.x_line, prof.uy_line});
  io::write_fluid_fields(w, p, true);
  w.close();
}

RunResult run_cavity(const Params& prm, const RunContext& ctx, bool cylinder) {
  auto it = prm.find("scheme");
  const std::string scheme = it == prm.end() ? "isph" : get_string(prm, "scheme");
  omp_set_num_threads(std::max(1, ctx.threads));
  if (scheme == "isph") {
    const IsphOptions opt = IsphOptions::from_params(prm);
    const double h = opt.h_over_dx * get_real(prm, "dx");
    return with_kernel<2>(opt.kernel, h, [&](const auto& kernel) {
      return run_cavity_isph(prm, ctx, cylinder, kernel, opt);
    });
  }
  if (scheme == "wcsph_tvf")
    return run_cavity_wcsph_tvf(prm, ctx, cylinder);
  throw std::invalid_argument("cavity: unknown scheme '" + scheme + "'");
}

} // namespace sph
