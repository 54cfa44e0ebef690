// Case "shear_layer": the impulsively started shear layer of seed 003 (Parshikov et al.), sections
// 3.1-3.2 (numerical viscosity of the contact scheme), 5.1 (zeta sweep, liquid lead) and 5.2
// (paraffin | glycerol), run with scheme "contact" (solver/schemes/contact/contact.hpp).
//
// Set-up: a lattice of nx x ny (x nz) particles of size D0 (the paper: 80 x 40 x 4, D0 = 10 nm,
// an 800 x 400 x 40 nm box). x (axis 0) is across the flow with slip walls at x = +-nx D0 / 2, y
// along the flow and z are periodic. At t = 0, U_y = +U0 for x > 0 and -U0 for x < 0, rho = rho0,
// P = 0. Left (x < 0) and right layers may be different materials (Table 1 of seed 003, in
// materials.hpp).
//
// Periodic depth: the cell list needs a periodic axis of at least 3 search radii; the paper's 4
// layers in z are less than that, so nz (and ny) are raised to the smallest count that is
// enough (metrics nz_used, ny_used). The initial state and the equations are invariant under a
// shift by D0 in z, so every z layer carries the same solution and the depth changes nothing but
// the cost.
//
// Measurement (diagnostics/erf_fit.hpp): at 5 times t_k = (0.6, 0.7, 0.8, 0.9, 1.0) t_end the
// particle velocities U_y(x) are fitted by least squares with the erf solution of seed 003 eq.
// (10) (with its images in the slip walls, which matter only once the layer reaches them):
//   eta_fit         rho0 times the mean of the fitted nu_k (Pa s); with eta = 0 and zeta = 0 it is
//                   the scheme's numerical viscosity eta_num (the paper's method, section 3.2)
//   eta_fit_spread  (max_k nu_k - min_k nu_k) / mean_k nu_k: departure from self-similarity
//   fit_rms         RMS residual of the fit at t_end / U0 (how erf-like the profile is)
//   profile_err     RMS over particles of (U_y - u_phys(x, t_end)) / U0, u_phys the solution with
//                   the physical viscosity only
// Two fluids: nu_left, nu_right are fitted jointly (eta_fit_left, eta_fit_right) with the
// composite-medium solution; profile_err uses the same solution with the physical viscosities.
// Parameter impedance: a checked copy of rho0 c0 (the x axis of the eta_num-against-Z figure);
// with material = custom it may set c0 instead.
// Cost: steps, wall_s, wall_per_step_s, n_fluid, n_ghost, neighbors_mean.
// Checkpoints (io/checkpoint.hpp, with a checkpoint directory): every particle field (ghosts
// included), the scheme's search count and cell radius, the fits made so far and this loop's
// sums. A resumed job continues bit for bit (tested).
#include "cases/case.hpp"
#include "cases/contact_step.hpp"
#include "cases/materials.hpp"
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "diagnostics/erf_fit.hpp"
#include "io/particle_checkpoint.hpp"
#include "schemes/contact/scheme_info.hpp"

#include <chrono>
#include <cmath>
#include <omp.h>
#include <sstream>
#include <stdexcept>

namespace sph {
namespace {

struct Side {
  double rho0, c0, eta;
};

Side resolve_side(const Params& prm, const std::string& key) {
  Side s{-1.0, -1.0, -1.0};
  if (key != "custom") {
    const Material* m = find_material(key);
    if (!m)
      throw std::invalid_argument("shear_layer: unknown material '" + key + "'");
    s = {m->rho0, m->c0, m->eta};
  }
  if (get_real(prm, "rho0") >= 0.0)
    s.rho0 = get_real(prm, "rho0");
  if (get_real(prm, "c0") >= 0.0)
    s.c0 = get_real(prm, "c0");
  if (get_real(prm, "eta") >= 0.0)
    s.eta = get_real(prm, "eta");
  const double Z = get_real(prm, "impedance");
  if (Z > 0.0) {
    if (key == "custom" && get_real(prm, "c0") < 0.0 && s.rho0 > 0.0)
      s.c0 = Z / s.rho0;
    else if (!(std::abs(Z - s.rho0 * s.c0) <= 1e-3 * s.rho0 * s.c0))
      throw std::invalid_argument("shear_layer: impedance = " + std::to_string(Z) +
                                  " differs from rho0 c0 = " + std::to_string(s.rho0 * s.c0) +
                                  " of material '" + key + "' by more than 0.1%");
  }
  if (!(s.rho0 > 0.0) || !(s.c0 > 0.0) || !(s.eta >= 0.0))
    throw std::invalid_argument(
        "shear_layer: material 'custom' needs rho0 > 0, c0 > 0 (or impedance) and eta >= 0");
  return s;
}

template <int D>
RunResult run_shear_layer(const Params& prm, const RunContext& ctx) {
  const auto wall0 = std::chrono::steady_clock::now();
  omp_set_num_threads(std::max(1, ctx.threads));
  const std::string mat = get_string(prm, "material");
  const std::string ml =
      get_string(prm, "material_left").empty() ? mat : get_string(prm, "material_left");
  const std::string mr =
      get_string(prm, "material_right").empty() ? mat : get_string(prm, "material_right");
  const Side L = resolve_side(prm, ml), R = resolve_side(prm, mr);
  const bool two = ml != mr;
  const double U0 = get_real(prm, "U0"), D0 = get_real(prm, "D0");

  const contact::Options opt = contact::options_from(prm);
  double t_end = get_real(prm, "t_end");
  if (t_end <= 0.0)
    t_end = 1000.0 * D0 / std::max(L.c0, R.c0);

  return with_kernel<D>(get_string(prm, "kernel"), 1.0, [&](const auto& kernel_tag) {
    using K = std::decay_t<decltype(kernel_tag)>;
    // Periodic axes must hold 3 search radii; allow 5% growth of the particle size.
    const double Rs = contact::search_radius<K>(opt, 1.05 * D0);
    const int nmin = static_cast<int>(std::ceil(3.0 * Rs / D0));
    const int nx = static_cast<int>(get_int(prm, "nx"));
    const int ny = std::max<int>(static_cast<int>(get_int(prm, "ny")), nmin);
    const int nz = D == 3 ? std::max<int>(static_cast<int>(get_int(prm, "nz")), nmin) : 1;
    const double half = 0.5 * nx * D0;

    Particles<D> p;
    const contact::Fields f = contact::Fields::add_to(p);
    std::array<int, D> lo{}, hi{};
    hi[0] = nx, hi[1] = ny;
    if constexpr (D == 3)
      hi[2] = nz;
    const double vol = std::pow(D0, D);
    for_each_lattice_point<D>(lo, hi, D0, [&](Vec<D> x, const std::array<int, D>&) {
      x[0] -= half;
      x[1] -= 0.5 * ny * D0;
      if constexpr (D == 3)
        x[2] -= 0.5 * nz * D0;
      const Side& s = x[0] < 0.0 ? L : R;
      const std::size_t i = p.add(x, s.rho0 * vol, s.rho0);
      p.v[i][1] = x[0] < 0.0 ? -U0 : U0;
      p.scalar(f.rho0)[i] = s.rho0;
      p.scalar(f.c0)[i] = s.c0;
      p.scalar(f.eta)[i] = s.eta;
    });
    const std::size_t n_fluid = p.size();

    Domain<D> box;
    box.lo[0] = -half - 2.0 * Rs, box.hi[0] = half + 2.0 * Rs;
    box.lo[1] = -0.5 * ny * D0, box.hi[1] = 0.5 * ny * D0, box.periodic[1] = true;
    if constexpr (D == 3)
      box.lo[2] = -0.5 * nz * D0, box.hi[2] = 0.5 * nz * D0, box.periodic[2] = true;
    contact::Scheme<D, K> scheme(p, f, box, opt,
                                 {contact::SlipWall{0, -half, +1}, contact::SlipWall{0, half, -1}});
    scheme.init();

    ShearLayer sl{U0, two ? 0.0 : half, 3};
    const double nuL = L.eta / L.rho0, nuR = R.eta / R.rho0;
    std::vector<double> xs, us, nu_k, nul_k, nur_k;
    double fit_rms = 0.0;
    auto sample = [&]() {
      xs.clear(), us.clear();
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Fluid)
          xs.push_back(p.r[i][0]), us.push_back(p.v[i][1]);
    };

    RunResult res;
    double t = 0.0, dt_sum = 0.0, max_drho = 0.0, wall_before = 0.0;
    long steps = 0;
    int next = 0;
    const double fit_at[5] = {0.6, 0.7, 0.8, 0.9, 1.0};
    auto wall_so_far = [&] {
      return wall_before +
             std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    };

    std::vector<double> a, carried; // the loop's scalars, the scheme's state
    io::LoopCheckpoint<D> ck(ctx.checkpoint_dir, ctx.checkpoint_every_steps, ctx.checkpoint_every_s,
                             p,
                             {{"sl/nu", &nu_k},
                              {"sl/nu_left", &nul_k},
                              {"sl/nu_right", &nur_k},
                              {"sl/loop", &a},
                              {"sl/scheme", &carried}});
    std::string resumed;
    if (auto at = ck.restore()) {
      scheme.restore_carried_state(carried);
      io::expect_state_size(a, 5, "shear_layer: checkpoint loop state");
      dt_sum = a[0], max_drho = a[1], fit_rms = a[2], next = static_cast<int>(a[3]);
      wall_before = a[4];
      steps = static_cast<long>(at->first), t = at->second;
      std::ostringstream os; // t is of order 1e-10 s
      os << "resumed at t = " << t << " s, step " << steps << " (attempt " << ctx.attempt << ")";
      resumed = os.str();
    }
    auto save_checkpoint = [&] {
      a = {dt_sum, max_drho, fit_rms, static_cast<double>(next), wall_so_far()};
      carried = scheme.carried_state();
      ck.save(steps, t);
    };

    while (next < 5) {
      if (ctx.cancelled())
        save_checkpoint(); // contact_step below records the cancellation
      const double dt = contact_step(scheme, t, t_end, ctx, res);
      if (dt == 0.0)
        return res;
      dt_sum += dt, ++steps;
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Fluid)
          max_drho = std::max(max_drho, std::abs(p.rho[i] / p.scalar(f.rho0)[i] - 1.0));
      if (!std::isfinite(max_drho) || max_drho > 0.5) {
        res.status = RunStatus::Diverged;
        res.message = "density deviation " + std::to_string(max_drho) +
                      " at t = " + std::to_string(t) + " after " + std::to_string(steps) + " steps";
        return res;
      }
      while (next < 5 && t >= fit_at[next] * t_end * (1.0 - 1e-12)) {
        sample();
        if (two) {
          const ErfFit ft = fit_shear_layer2(sl, xs, us, t, L.rho0, R.rho0);
          nul_k.push_back(ft.nu_left), nur_k.push_back(ft.nu_right);
          fit_rms = ft.rms;
        } else {
          const ErfFit ft = fit_shear_layer(sl, xs, us, t);
          nu_k.push_back(ft.nu);
          fit_rms = ft.rms;
        }
        ++next;
      }
      if (ck.due(steps))
        save_checkpoint();
      ctx.report(t / t_end);
    }
    const double wall_s = wall_so_far();

    auto spread = [](const std::vector<double>& v) {
      double lo = v[0], hi = v[0], s = 0.0;
      for (double x : v)
        lo = std::min(lo, x), hi = std::max(hi, x), s += x;
      return (hi - lo) / (s / v.size());
    };
    auto mean = [](const std::vector<double>& v) {
      double s = 0.0;
      for (double x : v)
        s += x;
      return s / v.size();
    };
    // Profile error against the physical-viscosity solution at t_end.
    sample();
    double err2 = 0.0;
    for (std::size_t k = 0; k < xs.size(); ++k) {
      const double ue = two ? shear_layer_u2(sl, xs[k], t, nuL, L.rho0, nuR, R.rho0)
                            : shear_layer_u(sl, xs[k], t, nuL);
      err2 += (us[k] - ue) * (us[k] - ue);
    }
    if (two) {
      res.add("eta_fit_left", L.rho0 * mean(nul_k));
      res.add("eta_fit_right", R.rho0 * mean(nur_k));
      res.add("eta_fit_spread", std::max(spread(nul_k), spread(nur_k)));
    } else {
      res.add("eta_fit", L.rho0 * mean(nu_k));
      res.add("eta_fit_spread", spread(nu_k));
    }
    res.add("profile_err", std::sqrt(err2 / xs.size()) / U0);
    res.add("fit_rms", fit_rms);
    if (!two) {
      res.add("eta_phys", L.eta);
      res.add("Z", L.rho0 * L.c0);
      res.add("eta_num_ref", opt.eta_num >= 0.0
                                 ? opt.eta_num
                                 : contact::eta_num_eq37(D0, L.rho0 * L.c0, opt.alpha));
    } else {
      res.add("eta_phys_left", L.eta);
      res.add("eta_phys_right", R.eta);
    }
    res.add("t_end", t_end);
    res.add("max_density_dev", max_drho);
    res.add("steps", static_cast<double>(steps));
    res.add("dt_mean", dt_sum / steps);
    res.add("wall_s", wall_s);
    res.add("wall_per_step_s", wall_s / steps);
    res.add("n_fluid", static_cast<double>(n_fluid));
    res.add("n_ghost", static_cast<double>(scheme.num_ghosts()));
    res.add("ny_used", ny);
    res.add("nz_used", nz);
    double pairs = 0.0;
    const auto& nl = scheme.neighbors();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid)
        pairs += nl.offset[i + 1] - nl.offset[i];
    res.add("neighbors_mean", pairs / n_fluid);
    if (!resumed.empty())
      res.message = resumed;
    ck.discard(); // the results are final
    return res;
  });
}

} // namespace

CaseInfo make_shear_layer_case() {
  CaseInfo c;
  c.name = "shear_layer";
  c.description = "Shear layer of two sliding layers vs the erf solution; numerical viscosity of "
                  "contact SPH (Parshikov et al., seed 003, sections 3 and 5.1-5.2)";
  c.schemes = {"contact"};
  std::vector<std::string> mats = material_keys();
  mats.push_back("custom");
  std::vector<std::string> sides = mats;
  sides.insert(sides.begin(), "");
  c.params = {
      {"material",
       ParamType::String,
       std::string("lead"),
       "liquid of both layers: a Table 1 material of seed 003, or custom (rho0, c0, eta)",
       {},
       {},
       false,
       mats},
      {"material_left",
       ParamType::String,
       std::string(""),
       "liquid of the layer x < 0 (empty: material)",
       {},
       {},
       false,
       sides},
      {"material_right",
       ParamType::String,
       std::string(""),
       "liquid of the layer x > 0 (empty: material)",
       {},
       {},
       false,
       sides},
      {"rho0",
       ParamType::Real,
       -1.0,
       "reference density, kg/m^3 (< 0: from the material)",
       -1.0,
       {}},
      {"c0", ParamType::Real, -1.0, "sound speed, m/s (< 0: from the material)", -1.0, {}},
      {"eta",
       ParamType::Real,
       -1.0,
       "physical dynamic viscosity, Pa s (< 0: from the material; 0: inviscid)",
       -1.0,
       {}},
      {"impedance",
       ParamType::Real,
       -1.0,
       "acoustic impedance rho0 c0, kg/(m^2 s) (< 0: from the material). With a Table 1 material "
       "it must equal rho0 c0 within 0.1% (a checked label that figures can plot against); with "
       "custom and no c0 it sets c0 = impedance / rho0",
       -1.0,
       {}},
      {"U0",
       ParamType::Real,
       500.0,
       "layer speed, m/s (+U0 for x > 0, -U0 for x < 0)",
       0.0,
       {},
       true},
      {"D0", ParamType::Real, 1e-8, "particle size, m", 0.0, {}, true},
      {"t_end", ParamType::Real, 0.0, "end time, s (0: 1000 D0 / c0)", 0.0, {}},
      {"dim", ParamType::Int, std::int64_t{3}, "space dimension (the paper's box is 3D)", 2.0, 3.0},
      {"nx", ParamType::Int, std::int64_t{80}, "particles across the flow (between the walls)", 4.0,
       100000.0},
      {"ny", ParamType::Int, std::int64_t{40}, "particles along the flow (periodic)", 1.0,
       100000.0},
      {"nz", ParamType::Int, std::int64_t{4}, "particles in depth (3D, periodic)", 1.0, 100000.0},
  };
  c.run = [](const Params& prm, const RunContext& ctx) {
    return get_int(prm, "dim") == 3 ? run_shear_layer<3>(prm, ctx) : run_shear_layer<2>(prm, ctx);
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_shear_layer_case()); // core/registry.hpp
} // namespace

} // namespace sph
