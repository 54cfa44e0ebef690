// Registry entry of scheme "contact" (seed 003, Parshikov et al.): its parameters, shared by every
// case that runs it, and their translation into contact::Options.
#include "schemes/contact/scheme_info.hpp"

#include "core/kernels/kernel.hpp"

#include <stdexcept>

namespace sph {

namespace contact {

Options options_from(const Params& prm) {
  Options o;
  o.alpha = get_real(prm, "alpha");
  o.zeta = get_real(prm, "zeta");
  o.cfl = get_real(prm, "cfl");
  const std::string& en = get_string(prm, "eta_num");
  if (en != "eq37") {
    std::size_t used = 0;
    try {
      o.eta_num = std::stod(en, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != en.size() || !(o.eta_num >= 0.0))
      throw std::invalid_argument(
          "contact: eta_num must be \"eq37\" or a number >= 0 (Pa s), got '" + en + "'");
  }
  return o;
}

} // namespace contact

SchemeInfo make_contact_scheme() {
  SchemeInfo s;
  s.name = "contact";
  s.description = "Godunov-type contact SPH with numerical-viscosity correction zeta "
                  "(Parshikov, Medin, Rublev & Dyachkov, seed 003)";
  s.params = {
      {"zeta", ParamType::Real, 0.0,
       "fraction of the numerical viscosity removed by the correcting stress (eq. 26)", 0.0, 1.0},
      {"eta_num", ParamType::String, std::string("eq37"),
       "numerical viscosity the correction is built on: \"eq37\" (eq. 37 per particle) or a "
       "number in Pa s written as a string"},
      {"alpha", ParamType::Real, 0.5, "smoothing length factor, h_ij = alpha (D_i + D_j) (eq. 12)",
       0.5, 2.0},
      {"kernel",
       ParamType::String,
       std::string("wendland_c2"),
       "smoothing kernel",
       {},
       {},
       false,
       {"wendland_c2", "cubic_spline"}},
      {"cfl", ParamType::Real, 0.3, "Courant number, dt = cfl min D_i / (c0_i + |U_i|)", 0.0, 1.0,
       true},
  };
  return s;
}

namespace {
const Registrar<SchemeInfo> registered(make_contact_scheme()); // core/registry.hpp
} // namespace

} // namespace sph
