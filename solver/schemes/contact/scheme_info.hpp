// Registry entry of scheme "contact" (scheme_info.cpp): its parameters, and what a case that runs
// it needs before the scheme exists (its options, the search radius that sizes periodic axes).
#pragma once

#include "schemes/contact/contact.hpp"
#include "schemes/scheme.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

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

// The cases' divergence test: max_dev grows to the largest |rho_i / rho0_i - 1| over the fluid
// particles seen so far (rho0_i the per-particle material field); std::runtime_error ("density
// deviation ... after N steps": the job is diverged) once it is above limit or not finite.
template <int D>
void check_density_deviation(const Particles<D>& p, double& max_dev, double limit, long steps) {
  const auto& rho0 = p.scalar(p.find_scalar("rho0"));
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == Kind::Fluid)
      max_dev = std::max(max_dev, std::abs(p.rho[i] / rho0[i] - 1.0));
  if (!std::isfinite(max_dev) || max_dev > limit)
    throw std::runtime_error("density deviation " + std::to_string(max_dev) + " after " +
                             std::to_string(steps) + " steps");
}
} // namespace contact
} // namespace sph
