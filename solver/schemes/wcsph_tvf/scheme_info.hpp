// Parameters of scheme "wcsph_tvf" (registry entry in scheme_info.cpp).
#pragma once

#include "schemes/scheme.hpp"
#include "schemes/wcsph_tvf/wcsph_tvf.hpp"

namespace sph {
SchemeInfo make_wcsph_tvf_scheme();
namespace wcsph_tvf {
// Options from resolved parameters, without the physical ones (rho0, c0, mu, U_ref, dx, h).
Options options_from(const Params& prm);
// The options of a case with reference density rho0, speed U, length L, Reynolds number Re and
// lattice spacing dx: options_from(prm) with rho0, U_ref = U, c0 = c0_factor U,
// mu = rho0 U L / Re, dx and h = h_over_dx dx set.
Options options_for_flow(const Params& prm, double rho0, double U, double L, double Re, double dx);
} // namespace wcsph_tvf
} // namespace sph
