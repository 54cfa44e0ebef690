// Case "lid_driven_cavity": the lid-driven square cavity of seed 001 (Zheng, Ma & Shao 2018)
// section 5.1, compared with Ghia, Ghia & Shin (1982) at Re = 1000. H = L = 1, U0 = 1,
// nu = U0 L / Re. Geometry, run loop and metrics: cases/cavity.hpp, cavity.cpp,
// diagnostics/cavity_profiles.hpp.
#include "cases/cavity.hpp"

namespace sph {

CaseInfo make_lid_driven_cavity_case() {
  CaseInfo c;
  c.name = "lid_driven_cavity";
  c.description = "Lid-driven square cavity vs Ghia et al. 1982 (Zheng, Ma & Shao 2018, 5.1)";
  c.schemes = {"isph", "wcsph_tvf"};
  c.params = cavity_params(false);
  c.run = [](const Params& prm, const RunContext& ctx) { return run_cavity(prm, ctx, false); };
  c.size = [](const Params& prm) { return size_cavity(prm, false); };
  c.check = cavity_dx_check; // build_cavity's constraint, checked when the study is validated
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_lid_driven_cavity_case()); // core/registry.hpp
} // namespace

} // namespace sph
