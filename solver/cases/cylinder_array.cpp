// Case "cylinder_array": slow (Stokes) flow through a square array of cylinders, seed 003
// (Parshikov et al.), section 5.5 and Table 2, run with scheme "contact" with and without the
// numerical-viscosity correction zeta; reference: Sangani & Acrivos, Int. J. Multiphase Flow 8
// (1982) 193-206 (Table 1: K against the solid fraction c), and the paper's eq. (39).
//
// Set-up (2D): one cylinder of diameter d at the centre of a periodic square cell of side S (the
// array of period S, Fig. 10). A lattice of particles of size D0 = d / n_d; S = N D0 with
// N = round(n_d / d_over_S) (so d/S is rounded to a lattice: metric d_over_S_used). Lattice points
// with |x| >= d/2 are fluid; those with d/2 - 1.05 R_search < |x| < d/2 are the solid, a no-slip
// wall at rest (contact.hpp: mirrored velocity and pressure per pair). The fluid starts at rest and
// is driven by a uniform body force g along x, equivalent to a mean pressure gradient G = rho0 g
// (reference/analytic_solutions section 4: with a body force on the fluid only the flow is that of
// the pressure gradient G, whose drag per unit length is F = G S^2).
//
// Drive: G = K_d(c) eta U / S^2 with U = Re eta / (rho0 d) and K_d the dilute expansion of
// Sangani & Acrivos (eq. 13 there, 4 pi / (-ln(c)/2 - 0.738 + c - 0.887 c^2 + 2.038 c^3)): the
// pressure gradient that would give Reynolds number Re if the drag were that of the dilute
// theory. It only sets the forcing level; every metric is measured.
//
// Measurement, at t = (0.8, 0.9, 1.0) t_end, t_end = t_end_visc S^2 rho0 / eta:
//   U_s        superficial velocity: (1/S^2) sum_fluid V_i U_x,i (flow rate per unit width)
//   K          dimensionless drag F / (eta U_s) = G S^2 / (eta U_s): compare with Sangani &
//              Acrivos's K(c) (their Table 1); with the numerical viscosity uncorrected K grows by
//              about (eta + eta_num) / eta
//   Re         rho0 U_s d / eta
//   CD         drag coefficient F / (rho0 U_s^2 d / 2) = 2 K / Re (seed 003, section 5.5)
//   CD_eq39    16 pi a0 / Re, seed 003 eq. (39), a0 the series in omega = pi d / (2 S)
//   CD_ratio   CD / CD_eq39 (= K / (8 pi a0); Table 2 of seed 003 gives 1.13-1.33 corrected,
//              2.5-3.4 uncorrected)
//   U_drift    |U_s(t_end) - U_s(0.8 t_end)| / U_s(t_end): how close to steady the flow is
//   drag_balance  the drag measured on the solid particles (pair forces) over the body force on
//              the fluid, g M_fluid: 1 in a steady state
// Cost: steps, wall_s, wall_per_step_s, n_fluid, n_solid.
#include "cases/case.hpp"
#include "cases/contact_step.hpp"
#include "cases/materials.hpp"
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "schemes/contact/scheme_info.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <omp.h>
#include <stdexcept>

namespace sph {

// Seed 003, eq. (39): the coefficient a0 of C_D = 16 pi a0 / Re, omega = pi d / (2 S).
double cylinder_array_a0(double d_over_S) {
  const double w = std::numbers::pi * d_over_S / 2.0, w2 = w * w;
  const double c[] = {2.0 / 3.0,          -1.0 / 9.0,       8.0 / 135.0,
                      -53.0 / 1350.0,     1112.0 / 42525.0, -241643.0 / 13395375.0,
                      18776.0 / 1488375.0};
  double s = 1.0 - 2.0 * std::log(2.0 * w), wp = 1.0;
  for (double ck : c)
    wp *= w2, s += ck * wp;
  return 1.0 / s;
}

namespace {

// Sangani & Acrivos (1982) eq. 13, the dilute expansion of K (used only to set the drive).
double k_dilute(double c) {
  return 4.0 * std::numbers::pi /
         (-0.5 * std::log(c) - 0.738 + c - 0.887 * c * c + 2.038 * c * c * c);
}

RunResult run_cylinder_array(const Params& prm, const RunContext& ctx) {
  constexpr int D = 2;
  const auto wall0 = std::chrono::steady_clock::now();
  omp_set_num_threads(std::max(1, ctx.threads));
  const Material* mat = find_material(get_string(prm, "material"));
  if (!mat)
    throw std::invalid_argument("cylinder_array: unknown material '" + get_string(prm, "material") +
                                "'");
  const double rho0 = mat->rho0, c0 = mat->c0;
  const double eta = get_real(prm, "eta") >= 0.0 ? get_real(prm, "eta") : mat->eta;
  if (!(eta > 0.0))
    throw std::invalid_argument("cylinder_array: the fluid needs a viscosity eta > 0 (material '" +
                                std::string(mat->key) + "' has none in Table 1: set eta)");
  const double d = get_real(prm, "d");
  const int n_d = static_cast<int>(get_int(prm, "n_d"));
  const double D0 = d / n_d;
  const int N = static_cast<int>(std::lround(n_d / get_real(prm, "d_over_S")));
  const double S = N * D0, a = 0.5 * d;
  if (S <= d + 2.0 * D0)
    throw std::invalid_argument("cylinder_array: d_over_S too close to 1 for n_d = " +
                                std::to_string(n_d) + " (less than 2 particles in the gap)");
  const double c = std::numbers::pi * a * a / (S * S);
  const double U_target = get_real(prm, "Re") * eta / (rho0 * d);
  const double G = k_dilute(c) * eta * U_target / (S * S);
  const double t_end = get_real(prm, "t_end_visc") * S * S * rho0 / eta;

  contact::Options opt = contact::options_from(prm);
  opt.g = {G / rho0, 0.0, 0.0};

  return with_kernel<D>(get_string(prm, "kernel"), 1.0, [&](const auto& kernel_tag) {
    using K = std::decay_t<decltype(kernel_tag)>;
    const double Rs = contact::search_radius<K>(opt, 1.05 * D0);
    if (S < 3.0 * Rs)
      throw std::invalid_argument("cylinder_array: the cell (S = " + std::to_string(N) +
                                  " D0) is smaller than 3 search radii; raise n_d");
    Particles<D> p;
    const contact::Fields f = contact::Fields::add_to(p);
    const double vol = D0 * D0;
    std::size_t n_fluid = 0;
    for_each_lattice_point<D>({0, 0}, {N, N}, D0, [&](Vec<D> x, const std::array<int, D>&) {
      x[0] -= 0.5 * S, x[1] -= 0.5 * S;
      const double r = x.norm();
      if (r < a - 1.05 * Rs)
        return;
      const bool solid = r < a;
      const std::size_t i = p.add(x, rho0 * vol, rho0, solid ? Kind::Wall : Kind::Fluid);
      p.scalar(f.rho0)[i] = rho0;
      p.scalar(f.c0)[i] = c0;
      p.scalar(f.eta)[i] = eta;
      n_fluid += !solid;
    });
    double M_fluid = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid)
        M_fluid += p.m[i];

    Domain<D> box;
    box.lo[0] = box.lo[1] = -0.5 * S;
    box.hi[0] = box.hi[1] = 0.5 * S;
    box.periodic[0] = box.periodic[1] = true;
    contact::Scheme<D, K> scheme(p, f, box, opt);
    scheme.init();

    auto superficial = [&]() {
      double q = 0.0;
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Fluid)
          q += p.m[i] / p.rho[i] * p.v[i][0];
      return q / (S * S);
    };

    RunResult res;
    double t = 0.0, max_drho = 0.0;
    long steps = 0;
    int next = 0;
    const double sample_at[3] = {0.8, 0.9, 1.0};
    double U_k[3] = {0.0, 0.0, 0.0};
    while (next < 3) {
      if (contact_step(scheme, t, t_end, ctx, res) == 0.0)
        return res;
      ++steps;
      if (steps % 100 == 0 || t >= sample_at[next] * t_end * (1.0 - 1e-12)) {
        for (std::size_t i = 0; i < p.size(); ++i)
          if (p.kind[i] == Kind::Fluid)
            max_drho = std::max(max_drho, std::abs(p.rho[i] / rho0 - 1.0));
        if (!std::isfinite(max_drho) || max_drho > 0.1) {
          res.status = RunStatus::Diverged;
          res.message = "density deviation " + std::to_string(max_drho) +
                        " at t = " + std::to_string(t) + " after " + std::to_string(steps) +
                        " steps";
          return res;
        }
      }
      while (next < 3 && t >= sample_at[next] * t_end * (1.0 - 1e-12))
        U_k[next++] = superficial();
      ctx.report(t / t_end);
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    const double U_s = U_k[2];
    const double Kd = G * S * S / (eta * U_s);
    const double Re = rho0 * U_s * d / eta;
    const double CD = 2.0 * Kd / Re;
    const double CD39 = 16.0 * std::numbers::pi * cylinder_array_a0(d / S) / Re;
    res.add("K", Kd);
    res.add("U_s", U_s);
    res.add("Re", Re);
    res.add("CD", CD);
    res.add("CD_eq39", CD39);
    res.add("CD_ratio", CD / CD39);
    res.add("U_drift", std::abs(U_k[2] - U_k[0]) / std::abs(U_s));
    res.add("drag_balance", -scheme.solid_force()[0] / (opt.g[0] * M_fluid));
    res.add("solid_fraction", c);
    res.add("d_over_S_used", d / S);
    res.add("eta_phys", eta);
    res.add("eta_num_ref", scheme.eta_num(0, D0));
    res.add("D0", D0);
    res.add("t_end", t_end);
    res.add("max_density_dev", max_drho);
    res.add("steps", static_cast<double>(steps));
    res.add("wall_s", wall_s);
    res.add("wall_per_step_s", wall_s / steps);
    res.add("n_fluid", static_cast<double>(n_fluid));
    res.add("n_solid", static_cast<double>(scheme.num_solids()));
    return res;
  });
}

} // namespace

CaseInfo make_cylinder_array_case() {
  CaseInfo c;
  c.name = "cylinder_array";
  c.description = "Stokes flow through a square array of cylinders: drag K vs Sangani & Acrivos "
                  "(1982); contact SPH with and without the zeta correction (seed 003, 5.5)";
  c.schemes = {"contact"};
  c.params = {
      {"material",
       ParamType::String,
       std::string("glycerol"),
       "liquid: a Table 1 material of seed 003 (rho0, c0, eta)",
       {},
       {},
       false,
       material_keys()},
      {"eta", ParamType::Real, -1.0, "dynamic viscosity, Pa s (< 0: the material's)", -1.0, {}},
      {"d", ParamType::Real, 1e-3, "cylinder diameter, m", 0.0, {}, true},
      {"d_over_S", ParamType::Real, 0.5, "diameter over the period of the array", 0.0, 0.85, true},
      {"n_d", ParamType::Int, std::int64_t{20}, "particles per cylinder diameter (D0 = d / n_d)",
       4.0, 10000.0},
      {"Re", ParamType::Real, 0.005,
       "Reynolds number rho0 U d / eta that sets the drive (dilute-theory estimate; Re is "
       "measured)",
       0.0, 1.0, true},
      {"t_end_visc",
       ParamType::Real,
       0.15,
       "end time in units of the viscous time S^2 rho0 / eta",
       0.0,
       {},
       true},
  };
  c.run = [](const Params& prm, const RunContext& ctx) { return run_cylinder_array(prm, ctx); };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_cylinder_array_case()); // core/registry.hpp
} // namespace

} // namespace sph
