// Registry of schemes (time-integrator families): one line per scheme. Each scheme folder
// (schemes/<name>/) defines `SchemeInfo make_<name>_scheme()` with its parameters.
#include "cases/case.hpp"

namespace sph {

SchemeInfo make_contact_scheme();
SchemeInfo make_isph_scheme();
SchemeInfo make_alsph_scheme();
SchemeInfo make_wcsph_tvf_scheme();

const std::vector<SchemeInfo>& scheme_registry() {
  static const std::vector<SchemeInfo> schemes{
      make_contact_scheme(),
      make_isph_scheme(),
      make_alsph_scheme(),
      make_wcsph_tvf_scheme(),
  };
  return schemes;
}

const SchemeInfo* find_scheme(const std::string& name) {
  for (const auto& s : scheme_registry())
    if (s.name == name)
      return &s;
  return nullptr;
}

} // namespace sph
