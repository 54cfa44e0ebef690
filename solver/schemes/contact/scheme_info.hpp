// Parameters of scheme "contact" (registry entry in scheme_info.cpp).
#pragma once

#include "schemes/contact/contact.hpp"
#include "schemes/scheme.hpp"

namespace sph {
SchemeInfo make_contact_scheme();
namespace contact {
// Options from resolved parameters (zeta, eta_num, alpha, cfl; kernel is read by the case).
Options options_from(const Params& prm);
} // namespace contact
} // namespace sph
