// Contact SPH (seed 003) on its analytic flow (issue 15, section 1): the erf shear layer of case
// shear_layer, u(x, t) = U0 erf(x / sqrt(4 nu t)) (with images for the slip walls,
// diagnostics/erf_fit.hpp), run through the case interface (find_case("shear_layer")->run): ports
// to issue 14's interface unchanged as long as the case keeps its parameters and metrics.
#include "case_helpers.hpp"
#include "cases/case.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sph;
using sph::testing::metric;

namespace {
Params shear_params() {
  Params prm;
  for (const auto& s : find_case("shear_layer")->params)
    prm[s.name] = s.default_value;
  for (const auto& s : find_scheme("contact")->params)
    prm[s.name] = s.default_value;
  return prm;
}
} // namespace

// A 2D liquid layer (eta = 5 mPa s, about 4 times the numerical viscosity of eq. 37, 1.34 mPa s)
// with the correction zeta = 1: the fitted viscosity is the physical one times the factor of the
// pair stresses (30)-(32) for a shear flow, 1 + 1/(3 (d + 2)) = 1.083 in 2D (docs/contact.md),
// less the part of eta_num that eq. (37), fitted to 3D runs, does not remove in 2D (~ -2 %):
// measured 1.066. Band 1.066 +- 0.025: a contact viscosity error (the 1/3 doubled: 1.17), a zeta
// error (zeta ignored: +0.27) or an erf-fit width error (a factor 2 in nu) all leave it. The
// profile's RMS deviation from the fitted erf is small (the shape is an erf): < 1 % of U0.
TEST(AnalyticContact, ShearLayerViscosityBand) {
  Params prm = shear_params();
  prm["dim"] = std::int64_t{2};
  prm["material"] = std::string("custom");
  prm["rho0"] = 1000.0, prm["c0"] = 1500.0, prm["eta"] = 5e-3;
  prm["U0"] = 100.0, prm["D0"] = 1e-8, prm["t_end"] = 3.2e-10;
  prm["nx"] = std::int64_t{40}, prm["ny"] = std::int64_t{8};
  prm["zeta"] = 1.0;
  const RunResult r = find_case("shear_layer")->run(prm, RunContext{});
  ASSERT_EQ(r.status, RunStatus::Done) << r.message;
  std::printf("eta_fit / eta %.5f  fit_rms %.5f  profile_err %.5f\n", metric(r, "eta_fit") / 5e-3,
              metric(r, "fit_rms"), metric(r, "profile_err"));
  EXPECT_NEAR(metric(r, "eta_fit") / 5e-3, 1.066, 0.025);
  EXPECT_LT(metric(r, "fit_rms"), 0.01);
}
