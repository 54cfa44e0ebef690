// Parameters of scheme "wcsph_tvf" (registry entry in scheme_info.cpp).
#pragma once

#include "cases/case.hpp"
#include "schemes/wcsph_tvf/wcsph_tvf.hpp"

namespace sph {
SchemeInfo make_wcsph_tvf_scheme();
namespace wcsph_tvf {
// Options from resolved parameters. The case sets the physical ones afterwards: rho0, c0 (as
// c0_factor U_ref, see c0_factor()), mu, U_ref, dx and h = h_over_dx dx.
Options options_from(const Params& prm);
double c0_factor(const Params& prm);
double h_over_dx(const Params& prm);
} // namespace wcsph_tvf
} // namespace sph
