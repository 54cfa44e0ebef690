// Registry entry of scheme "wcsph_tvf" (seed 002, Wang, Haidn & Hu, transport-velocity
// formulation with limiter; equations in ../shared/notes/tvf_equations.md and docs/tvf.md): its
// parameters, shared by every case that runs it, and their translation into wcsph_tvf::Options.
#include "schemes/wcsph_tvf/scheme_info.hpp"

#include <stdexcept>

namespace sph {

namespace wcsph_tvf {

Options options_from(const Params& prm) {
  Options o;
  const std::string& t = get_string(prm, "tvf");
  if (t == "none")
    o.tvf = Tvf::None;
  else if (t == "original")
    o.tvf = Tvf::Original;
  else if (t == "smoothing_length")
    o.tvf = Tvf::SmoothingLength;
  else if (t == "limited")
    o.tvf = Tvf::Limited;
  else
    throw std::invalid_argument("wcsph_tvf: unknown tvf '" + t + "'");
  const std::string& d = get_string(prm, "riemann_dissipation");
  if (d == "limited")
    o.dissipation = Dissipation::Limited;
  else if (d == "full")
    o.dissipation = Dissipation::Full;
  else if (d == "none")
    o.dissipation = Dissipation::None;
  else
    throw std::invalid_argument("wcsph_tvf: unknown riemann_dissipation '" + d + "'");
  const std::string& s = get_string(prm, "limiter_sign");
  if (s == "expansion")
    o.sign = LimiterSign::Expansion;
  else if (s == "compression")
    o.sign = LimiterSign::Compression;
  else
    throw std::invalid_argument("wcsph_tvf: unknown limiter_sign '" + s + "'");
  o.kernel_correction = get_bool(prm, "kernel_correction");
  o.cfl_ad = get_real(prm, "cfl_ad");
  o.cfl_ac = get_real(prm, "cfl_ac");
  o.tvf_alpha = get_real(prm, "tvf_alpha");
  o.tvf_kappa = get_real(prm, "tvf_kappa");
  o.pb_factor = get_real(prm, "pb_factor");
  return o;
}

Options options_for_flow(const Params& prm, double rho0, double U, double L, double Re, double dx) {
  Options o = options_from(prm);
  o.rho0 = rho0;
  o.U_ref = U;
  o.c0 = get_real(prm, "c0_factor") * U;
  o.mu = rho0 * U * L / Re;
  o.dx = dx;
  o.h = get_real(prm, "h_over_dx") * dx;
  return o;
}

} // namespace wcsph_tvf

SchemeInfo make_wcsph_tvf_scheme() {
  SchemeInfo s;
  s.name = "wcsph_tvf";
  s.description = "Riemann WCSPH, dual-criteria time stepping and transport-velocity correction "
                  "with limiter (Wang, Haidn & Hu, arXiv:2411.13992, seed 002)";
  s.params = {
      {"tvf",
       ParamType::String,
       std::string("limited"),
       "transport-velocity correction: none, original (Adami 2013 background pressure, "
       "kick-drift-kick), smoothing_length (eq. 14), limited (eqs. 15-16)",
       {},
       {},
       false,
       {"none", "original", "smoothing_length", "limited"}},
      {"riemann_dissipation",
       ParamType::String,
       std::string("limited"),
       "momentum dissipation of the Riemann solver in the 2nd half: limited (eq. 6), full (no "
       "limiter) or none (central)",
       {},
       {},
       false,
       {"limited", "full", "none"}},
      {"limiter_sign",
       ParamType::String,
       std::string("expansion"),
       "pairs the dissipation limiter acts on: expansion (SPHinXsys) or compression (Zhang 2017)",
       {},
       {},
       false,
       {"expansion", "compression"}},
      {"kernel_correction", ParamType::Bool, false,
       "linear kernel-gradient correction B in the pressure force and the TVF residue"},
      {"kernel",
       ParamType::String,
       std::string("wendland_c2"),
       "smoothing kernel",
       {},
       {},
       false,
       {"wendland_c2", "cubic_spline", "quintic_spline"}},
      {"h_over_dx", ParamType::Real, 1.3, "smoothing length h / particle spacing dx", 0.5, 3.0},
      {"c0_factor", ParamType::Real, 10.0, "artificial sound speed c0 = c0_factor U (eq. 2)", 1.0,
       1000.0},
      {"cfl_ad", ParamType::Real, 0.25, "advection CFL number (eq. 9)", 0.0, 1.0, true},
      {"cfl_ac", ParamType::Real, 0.6, "acoustic CFL number (eq. 11)", 0.0, 2.0, true},
      {"tvf_alpha", ParamType::Real, 0.2, "coefficient alpha of the TVF shift alpha h^2 g (eq. 14)",
       0.0, 10.0},
      {"tvf_kappa", ParamType::Real, 100.0,
       "slope kappa of the TVF limiter min(kappa h^2 |g|^2, 1) "
       "(eq. 15)",
       0.0, 1e6},
      {"pb_factor", ParamType::Real, 1.0,
       "tvf = original: background pressure p_b = pb_factor rho0 c0^2", 0.0, 100.0},
  };
  return s;
}

} // namespace sph
