// Case "cavity_cylinder": the lid-driven square cavity with a fixed no-slip cylinder of diameter
// d = 0.5 L at its centre, seed 001 (Zheng, Ma & Shao 2018) section 5.2, Figs. 11-14. The paper
// compares with OpenFOAM (no tabulated data), so this case records the profiles and ux_min
// without reference errors. Geometry, run loop and metrics: cases/cavity.hpp, cavity.cpp.
#include "cases/cavity.hpp"

namespace sph {

CaseInfo make_cavity_cylinder_case() {
  CaseInfo c;
  c.name = "cavity_cylinder";
  c.description = "Lid-driven cavity with a centred cylinder d = 0.5 L (Zheng, Ma & Shao 2018, "
                  "5.2)";
  c.schemes = {"isph", "wcsph_tvf"};
  c.params = cavity_params(true);
  c.run = [](const Params& prm, const RunContext& ctx) { return run_cavity(prm, ctx, true); };
  c.size = [](const Params& prm) { return size_cavity(prm, true); };
  c.check = cavity_dx_check; // build_cavity's constraint, checked when the study is validated
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_cavity_cylinder_case()); // core/registry.hpp
} // namespace

} // namespace sph
