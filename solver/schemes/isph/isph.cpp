// Scheme "isph" (seed 001, Zheng, Ma & Shao 2018, section 2): its parameters and their parsing.
// The time integrator itself is schemes/isph/isph.hpp (a template on dimension and kernel).
#include "schemes/isph/isph.hpp"

#include "core/kernels/kernel.hpp"

namespace sph {

IsphOptions IsphOptions::from_params(const Params& prm) {
  IsphOptions o;
  o.visc = parse_visc(get_string(prm, "visc"));
  o.alpha_ppe = get_real(prm, "alpha_ppe");
  o.solver = parse_ppe_solver(get_string(prm, "ppe_solver"));
  o.ppe_tol = get_real(prm, "ppe_tol");
  o.ppe_max_iter = static_cast<int>(get_int(prm, "ppe_max_iter"));
  o.kernel = get_string(prm, "kernel");
  o.h_over_dx = get_real(prm, "h_over_dx");
  o.eta_over_h = get_real(prm, "eta_over_h");
  o.grad_correction = get_bool(prm, "grad_correction");
  o.shifting = get_string(prm, "shifting") == "fickian";
  o.shift_A = get_real(prm, "shift_A");
  o.shift_max = get_real(prm, "shift_max");
  o.shift_velocity = get_bool(prm, "shift_velocity");
  o.wall_clearance = get_real(prm, "wall_clearance");
  return o;
}

SchemeInfo make_isph_scheme() {
  SchemeInfo s;
  s.name = "isph";
  s.description = "ISPH two-step projection with VISC-01..04 viscous Laplacians "
                  "(Zheng, Ma & Shao 2018, section 2)";
  const IsphOptions d;
  s.params = {
      {"visc",
       ParamType::String,
       std::string("visc04"),
       "viscous Laplacian form (seed 001 eqs. 15-20)",
       {},
       {},
       false,
       visc_names()},
      {"alpha_ppe", ParamType::Real, d.alpha_ppe,
       "weight alpha of the density-invariance part of the mixed PPE source (seed 001 eq. 13)", 0.0,
       1.0},
      {"ppe_solver",
       ParamType::String,
       std::string("bicgstab_ilu0"),
       "PPE linear solver: umfpack (sparse LU), or bicgstab (warm-started) with ilut, ilu0, "
       "jacobi or amg (HYPRE BoomerAMG), or gmres_amg",
       {},
       {},
       false,
       ppe_solver_names()},
      {"ppe_tol", ParamType::Real, d.ppe_tol, "relative residual tolerance of bicgstab", 0.0, 1e-2,
       true},
      {"ppe_max_iter", ParamType::Int, std::int64_t{d.ppe_max_iter}, "iteration limit of bicgstab",
       1.0, 100000.0},
      {"kernel",
       ParamType::String,
       d.kernel,
       "smoothing kernel (the paper uses the cubic spline)",
       {},
       {},
       false,
       kernel_names()},
      {"h_over_dx", ParamType::Real, d.h_over_dx, "smoothing length h / dx", 0.8, 3.0},
      {"eta_over_h", ParamType::Real, d.eta_over_h,
       "eta / h, singularity guard in r^2 + eta^2 (eqs. 14, 15, 17, 20)", 0.0, 0.5},
      {"grad_correction", ParamType::Bool, d.grad_correction,
       "kernel-corrected pressure gradient (Gamma of eq. 19) in the projection step"},
      {"shifting",
       ParamType::String,
       std::string("fickian"),
       "particle shifting: none, or fickian (Lind et al. 2012 with D = A h |u| dt, Skillen et "
       "al. 2013)",
       {},
       {},
       false,
       {"none", "fickian"}},
      {"shift_A", ParamType::Real, d.shift_A, "shifting coefficient A in D = A h |u| dt", 0.0,
       100.0},
      {"shift_max", ParamType::Real, d.shift_max, "cap of one step's shift, in units of dx", 0.0,
       1.0},
      {"shift_velocity", ParamType::Bool, d.shift_velocity,
       "correct the velocity of a shifted particle by u += grad u . dr"},
      {"wall_clearance", ParamType::Real, d.wall_clearance,
       "minimum fluid-to-wall-particle distance / dx enforced after each step (0: off)", 0.0, 1.0},
  };
  return s;
}

} // namespace sph
