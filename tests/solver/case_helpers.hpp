// Helpers of the tests that run a registered case through its run function (cases/case.hpp):
// the resolved default parameters of a case with a scheme, and a metric of the result.
#pragma once

#include "cases/case.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace sph::testing {

// Every parameter of the case and of the scheme at its default, and "scheme" set.
inline Params case_defaults(const std::string& case_name, const std::string& scheme) {
  Params prm;
  for (const auto& s : find_case(case_name)->params)
    prm[s.name] = s.default_value;
  for (const auto& s : find_scheme(scheme)->params)
    prm[s.name] = s.default_value;
  prm["scheme"] = scheme;
  return prm;
}

// The recorded metric `name` of r; a test failure (and NaN) when r has none.
inline double metric(const RunResult& r, const std::string& name) {
  for (const auto& [k, v] : r.metrics)
    if (k == name)
      return v;
  ADD_FAILURE() << "no metric " << name;
  return NAN;
}

} // namespace sph::testing
