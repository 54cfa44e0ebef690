// Parameters of scheme "elastic_solid" (registry entry in scheme_info.cpp).
#pragma once

#include "schemes/scheme.hpp"
#include "schemes/solid/elastic_solid.hpp"

namespace sph {
SchemeInfo make_elastic_solid_scheme();
namespace solid {
// Options from resolved parameters with the flow's material (rho0, E, nu) and spacing set,
// h = h_over_dx dx.
Options options_for_flow(const Params& prm, double rho0, double E, double nu, double dx);
} // namespace solid
} // namespace sph
