// Scheme "alsph": augmented-Lagrangian SPH (seed 004, Kolukisa, Ozbulut & Yildiz 2021, section 2);
// its parameters. The time integrator itself is schemes/alsph/alsph.hpp.
#include "schemes/scheme.hpp"

namespace sph {

SchemeInfo make_alsph_scheme() {
  SchemeInfo s;
  s.name = "alsph";
  s.description = "Augmented-Lagrangian SPH, Algorithms 1 and 2 (Kolukisa, Ozbulut & Yildiz 2021, "
                  "Symmetry 13:472, section 2)";
  s.params = {
      {"c_bv", ParamType::Real, 100.0, "C_BV in the penalty r_AL = C_BV u_max^2 dt (eq. 8)", 0.0,
       1e6, true},
      {"epsilon",
       ParamType::Real,
       1e-3,
       "convergence tolerance on max |div u| (eq. 13), in U/D (the paper: 1e-3 1/s)",
       0.0,
       {}},
      {"max_iterations", ParamType::Int, std::int64_t{5}, "maximum inner iterations per time step",
       1.0, 1000.0},
      {"algorithm", ParamType::Int, std::int64_t{1},
       "1: derivatives on updated positions r^{n+1,m}; 2: on r^n (section 2.4)", 1.0, 2.0},
      {"shifting", ParamType::Bool, true, "artificial particle displacement (eqs. 18-19)"},
  };
  return s;
}

namespace {
const Registrar<SchemeInfo> registered(make_alsph_scheme()); // core/registry.hpp
} // namespace

} // namespace sph
