// Case "taylor_green": the 2D viscous Taylor-Green vortex of seed 002 (Wang, Haidn & Hu,
// section 4.1; Taylor & Green 1937), run with scheme "wcsph_tvf" (schemes/wcsph_tvf/).
//
// Set-up as SPHinXsys' test_2d_taylor_green (../shared/notes/tvf_equations.md, section 6):
// unit square [0, 1]^2, periodic in x and y, n_side^2 particles on the cell-centred lattice
// ((i + 1/2) dx, (j + 1/2) dx), dx = 1/n_side, m = rho0 dx^2, rho0 = 1, U = 1, mu = rho0 U L / Re,
// c0 = c0_factor U. Initial velocity u = -cos(2 pi x) sin(2 pi y), v = sin(2 pi x) cos(2 pi y),
// rho = rho0 (p = 0). With perturb > 0 every coordinate is shifted by (Rn - 0.5) perturb dx
// (Rn uniform in [0, 1), random seed `seed`; core/lattice.hpp), the velocity taken at the shifted
// position.
//
// Analytic solution: u(t) = e^{bt} u(0), b = -8 pi^2 / Re; |v|max(t) = e^{bt};
// E_k(t) = E_k(0) e^{2bt} (E_k(0) = 1/4 on the lattice).
//
// Metrics (all from this run):
//   ke_rate             slope of the least-squares line of ln E_k(t) over all advection steps
//   ke_rate_rel_err     |ke_rate - (-16 pi^2 / Re)| / (16 pi^2 / Re)
//   ke_rel_err_end      |E_k(t_end) / (E_k(0) e^{-16 pi^2 t_end / Re}) - 1|
//   umax_rel_err_end    ||v|max(t_end) / e^{b t_end} - 1|
//   l1_vel_err_end      mean_i ||v_i| - |v_exact(r_i)|| / mean_i |v_exact(r_i)| (PySPH's "l1")
//   tv_ratio_max        max over advection steps of max_i |Delta r^tvf_i| / Dt over max_i |v_i|:
//                       the over-correction indicator of seed 002, Fig. 1 (> 1: over-correction);
//                       Dt is the advection criterion's step (the last steps are shortened to
//                       land on t_end, which must not inflate a shift that does not scale with Dt)
//   sumW_spread_end     (max_i - min_i) sum_j W_ij / sigma0 at t_end, sigma0 the lattice value:
//                       uniformity of the particle distribution (0 on a perfect lattice)
//   sumW_rms_end        RMS of (sum_j W_ij / sigma0 - 1) at t_end
//   sumW_spread_max     largest sumW spread over the run
//   advection_steps, acoustic_steps, wall_s, time_per_particle_step_s (wall over particles x
//   acoustic sub-steps), time_per_particle_adv_step_s, n_particles
// With an output directory, <output_dir>/taylor_green.h5 holds the per-step series
// (series/t, ke, ke_exact, umax, umax_exact, tv_max, tv_ratio, sumW_spread) and final fields.
// With a checkpoint directory the run saves its whole state every N steps / M seconds and on
// cancellation, and resumes from it bit for bit (tests/solver/test_wcsph_tvf.cpp).
#include "cases/case.hpp"
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "diagnostics/profiles.hpp"
#include "io/hdf5.hpp"
#include "io/particle_checkpoint.hpp"
#include "io/particle_fields.hpp"
#include "schemes/wcsph_tvf/scheme_info.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <omp.h>
#include <stdexcept>

namespace sph {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

Vec2 tgv_velocity(const Vec2& x, double factor) {
  return factor * Vec2(-std::cos(two_pi * x[0]) * std::sin(two_pi * x[1]),
                       std::sin(two_pi * x[0]) * std::cos(two_pi * x[1]));
}

template <class K>
RunResult run_tgv(const Params& prm, const RunContext& ctx) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const int n = static_cast<int>(get_int(prm, "n_side"));
  const double Re = get_real(prm, "Re"), t_end = get_real(prm, "t_end");
  const double perturb = get_real(prm, "perturb");
  const double L = 1.0, U = 1.0, rho0 = 1.0, dx = L / n;

  const wcsph_tvf::Options o = wcsph_tvf::options_for_flow(prm, rho0, U, L, Re, dx);

  Particles<2> p;
  p.reserve(static_cast<std::size_t>(n) * n);
  UniformRandom rn(static_cast<std::uint64_t>(get_int(prm, "seed")));
  for_each_lattice_point<2>({0, 0}, {n, n}, dx, [&](Vec2 x, const std::array<int, 2>&) {
    if (perturb > 0.0)
      for (int a = 0; a < 2; ++a)
        x[a] += (rn() - 0.5) * perturb * dx;
    const std::size_t i = p.add(x, rho0 * dx * dx, rho0);
    p.v[i] = tgv_velocity(x, U);
  });
  const wcsph_tvf::Fields f = wcsph_tvf::Fields::add_to(p);
  Domain<2> box;
  box.lo = Vec2::Zero(), box.hi = Vec2::Constant(L);
  box.periodic = {true, true};
  const K kernel(o.h);
  if (3.0 * kernel.support() > L)
    throw std::invalid_argument("taylor_green: n_side = " + std::to_string(n) +
                                " is too small: the periodic box must hold 3 kernel supports");
  wcsph_tvf::Scheme<2, K> scheme(p, f, box, o);
  scheme.init();

  const double b = -8.0 * std::numbers::pi * std::numbers::pi / Re;
  auto kinetic = [&]() { return kinetic_energy(p); }; // every particle is fluid
  auto umax = [&]() {
    double v = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
      v = std::max(v, p.v[i].norm());
    return v;
  };
  // Spread and RMS of sum_j W_ij / sigma0 - 1 over the particles.
  auto sumw_stats = [&](const std::vector<double>& s, double& spread, double& rms) {
    double lo = 1e300, hi = -1e300, sq = 0.0;
    for (double w : s) {
      const double x = w / scheme.sigma0();
      lo = std::min(lo, x), hi = std::max(hi, x), sq += (x - 1.0) * (x - 1.0);
    }
    spread = hi - lo;
    rms = std::sqrt(sq / static_cast<double>(s.size()));
  };

  const double ke0 = kinetic();
  std::vector<double> s_t{0.0}, s_ke{ke0}, s_ke_ex{ke0}, s_um{umax()}, s_um_ex{U};
  std::vector<double> s_tv{0.0}, s_ratio{0.0}, s_spread{0.0};
  RunResult res;
  double t = 0.0, tv_ratio_max = 0.0, spread_max = 0.0;
  long steps = 0;

  // Checkpoints (io/checkpoint.hpp): every particle field, the scheme's carried state, this
  // loop's state and the series so far. A resumed run continues bit for bit: the saved particles
  // are in cell order, so re-sorting them in init() is the identity.
  std::vector<double> loop, carried;
  io::LoopCheckpoint<2> ck(ctx.checkpoint_dir, ctx.checkpoint_every_steps, ctx.checkpoint_every_s,
                           p,
                           {{"tg/t", &s_t},
                            {"tg/ke", &s_ke},
                            {"tg/ke_ex", &s_ke_ex},
                            {"tg/um", &s_um},
                            {"tg/um_ex", &s_um_ex},
                            {"tg/tv", &s_tv},
                            {"tg/ratio", &s_ratio},
                            {"tg/spread", &s_spread},
                            {"tg/loop", &loop},
                            {"tg/scheme", &carried}});
  if (auto at = ck.restore()) {
    scheme.init();
    scheme.restore_carried_state(carried);
    steps = at->first, t = at->second, tv_ratio_max = loop.at(0), spread_max = loop.at(1);
    res.message = io::resumed_message(t, ctx.attempt);
  }
  auto save_checkpoint = [&] {
    loop = {tv_ratio_max, spread_max};
    carried = scheme.carried_state();
    ck.save(steps, t);
  };

  while (t < t_end * (1.0 - 1e-12)) {
    if (stop_if_cancelled(ctx, t, res, save_checkpoint))
      return res;
    const wcsph_tvf::StepInfo info = scheme.advance_towards(t, t_end);
    ++steps;
    const double ke = kinetic(), um = umax();
    if (!std::isfinite(ke) || um > 10.0 * U) {
      res.status = RunStatus::Diverged;
      res.message = "max speed " + std::to_string(um) + " at t = " + std::to_string(t);
      res.add("t_stop", t);
      return res;
    }
    // The density summation of this step measured the configuration the step started from.
    double spread = 0.0, rms = 0.0;
    sumw_stats(scheme.sum_w(), spread, rms);
    spread_max = std::max(spread_max, spread);
    const double ratio = info.v_max > 0.0 ? info.tv_max / info.v_max : 0.0;
    tv_ratio_max = std::max(tv_ratio_max, ratio);
    s_t.push_back(t), s_ke.push_back(ke), s_ke_ex.push_back(ke0 * std::exp(2.0 * b * t));
    s_um.push_back(um), s_um_ex.push_back(U * std::exp(b * t));
    s_tv.push_back(info.tv_max), s_ratio.push_back(ratio), s_spread.push_back(spread);
    if (ck.due(steps))
      save_checkpoint();
    ctx.report(t / t_end);
  }
  const double wall = std::chrono::duration<double>(clock::now() - t0).count();

  // Least-squares slope of ln E_k against t.
  double st = 0.0, sy = 0.0, stt = 0.0, sty = 0.0;
  const double m = static_cast<double>(s_t.size());
  for (std::size_t k = 0; k < s_t.size(); ++k) {
    const double y = std::log(s_ke[k]);
    st += s_t[k], sy += y, stt += s_t[k] * s_t[k], sty += s_t[k] * y;
  }
  const double rate = (m * sty - st * sy) / (m * stt - st * st);
  const double rate_ex = 2.0 * b;

  // Final distribution: one more density summation measures sum_j W_ij at t_end.
  double spread_end = 0.0, rms_end = 0.0;
  {
    std::vector<double> sw(p.size());
    scheme.number_density(sw);
    sumw_stats(sw, spread_end, rms_end);
    spread_max = std::max(spread_max, spread_end);
  }
  double l1 = 0.0, l1_ref = 0.0;
  const double fac = U * std::exp(b * t);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double ve = tgv_velocity(p.r[i], fac).norm();
    l1 += std::abs(p.v[i].norm() - ve), l1_ref += ve;
  }

  const double N = static_cast<double>(p.size());
  const double ke_end = s_ke.back(), um_end = s_um.back();
  res.add("ke_rate_rel_err", std::abs(rate - rate_ex) / std::abs(rate_ex));
  res.add("ke_rel_err_end", std::abs(ke_end / (ke0 * std::exp(2.0 * b * t)) - 1.0));
  res.add("umax_rel_err_end", std::abs(um_end / std::exp(b * t) - 1.0));
  res.add("l1_vel_err_end", l1 / l1_ref);
  res.add("tv_ratio_max", tv_ratio_max);
  res.add("sumW_spread_end", spread_end);
  res.add("sumW_rms_end", rms_end);
  res.add("sumW_spread_max", spread_max);
  res.add("ke_rate", rate);
  res.add("ke_rate_exact", rate_ex);
  res.add("ke_end", ke_end);
  res.add("umax_end", um_end);
  res.add("t_end", t);
  res.add("advection_steps", static_cast<double>(steps));
  res.add("acoustic_steps", static_cast<double>(scheme.acoustic_steps()));
  res.add("wall_s", wall);
  res.add("time_per_particle_step_s", wall / (N * static_cast<double>(scheme.acoustic_steps())));
  res.add("time_per_particle_adv_step_s", wall / (N * static_cast<double>(steps)));
  res.add("n_particles", N);

  if (!ctx.output_dir.empty()) {
    io::H5Writer w(ctx.output_dir / "taylor_green.h5");
    w.attribute("tvf", get_string(prm, "tvf"));
    w.attribute("n_side", static_cast<double>(n));
    w.attribute("Re", Re);
    w.write_columns(
        "series",
        {"t", "ke", "ke_exact", "umax", "umax_exact", "tv_max", "tv_ratio", "sumW_spread"},
        {s_t, s_ke, s_ke_ex, s_um, s_um_ex, s_tv, s_ratio, s_spread});
    io::write_fluid_fields(w, p); // every particle is fluid
    w.close();
  }
  ck.discard(); // the results are final
  return res;
}

} // namespace

CaseInfo make_taylor_green_case() {
  CaseInfo c;
  c.name = "taylor_green";
  c.description = "2D Taylor-Green vortex, unit periodic square: kinetic-energy decay and "
                  "transport-velocity over-correction (Wang, Haidn & Hu, seed 002, section 4.1)";
  c.schemes = {"wcsph_tvf"};
  c.params = {
      {"n_side", ParamType::Int, std::int64_t{100}, "particles per side (dx = 1 / n_side)", 8.0,
       4000.0},
      {"Re", ParamType::Real, 100.0, "Reynolds number U L / nu (U = L = 1)", 0.0, {}, true},
      {"t_end", ParamType::Real, 5.0, "end time", 0.0, {}, true},
      {"perturb", ParamType::Real, 0.0,
       "random shift of the initial lattice, fraction of dx (0: perfect lattice)", 0.0, 1.0},
      {"seed", ParamType::Int, std::int64_t{1}, "random seed of the perturbation", 0.0, {}},
  };
  c.run = [](const Params& prm, const RunContext& ctx) {
    omp_set_num_threads(std::max(1, ctx.threads));
    return with_kernel<2>(get_string(prm, "kernel"), 1.0, [&](const auto& k) {
      return run_tgv<std::decay_t<decltype(k)>>(prm, ctx);
    });
  };
  return c;
}

} // namespace sph
