// Registry entry of scheme "contact" (scheme_info.cpp): its parameters, and what a case that runs
// it needs before the scheme exists (its options, the search radius that sizes periodic axes).
#pragma once

#include "schemes/contact/contact.hpp"
#include "schemes/scheme.hpp"

namespace sph {
SchemeInfo make_contact_scheme();
namespace contact {
// Options from resolved parameters (zeta, eta_num, alpha, cfl, kernel).
Options options_from(const Params& prm);
// The neighbour-search radius of the job's options and kernel for largest particle size Dmax.
double search_radius(const Params& prm, double Dmax);
// Numerical viscosity before the factor zeta of a particle of size D0 and impedance Z: the given
// eta_num, or eq. (37).
double eta_num_of(const Options& o, double D0, double Z);
} // namespace contact
} // namespace sph
