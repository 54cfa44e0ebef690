// Grid-convergence verification of a metric recorded at several resolutions: the observed order
// of accuracy p, the Richardson-extrapolated value and Roache's grid-convergence index (GCI).
//
// Three grids h1 < h2 < h3 (1 the finest) with values f1, f2, f3, ratios r21 = h2/h1, r32 = h3/h2,
// differences e21 = f2 - f1, e32 = f3 - f2 (Celik, Ghia, Roache, Freitas, Coleman & Raad 2008,
// "Procedure for estimation and reporting of uncertainty due to discretization in CFD
// applications", J. Fluids Eng. 130, 078001, eqs. 3-4):
//   p = | ln|e32 / e21| + q(p) | / ln r21,  q(p) = ln((r21^p - s) / (r32^p - s)),  s =
//   sign(e32/e21)
// solved by fixed-point iteration (q = 0 and one step when r21 = r32);
//   f_ext = (r21^p f1 - f2) / (r21^p - 1),
//   GCI_fine = Fs |(f1 - f2) / f1| / (r21^p - 1),  Fs = 1.25 for three or more grids
// (Roache 1994, "Perspective: a method for uniform reporting of grid refinement studies",
// J. Fluids Eng. 116, 405). With two grids the order cannot be observed: a formal order given by
// the user is used and Fs = 3.
//
// An error against a reference (a metric that tends to 0) can instead be taken directly: p from
// the two finest grids, p = ln(e2 / e1) / ln r21, and a least-squares fit of ln|e| against ln h
// over all grids.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace sph::runner {

struct GridValue {
  double h = 0; // grid spacing (or 1 / count)
  double f = 0; // the metric
};

struct Convergence {
  std::size_t grids = 0;
  std::optional<double> p;     // observed order (three finest grids, or the finest pair of errors)
  std::optional<double> p_fit; // least-squares order over all grids (errors only)
  std::optional<double> f_ext; // Richardson-extrapolated value
  std::optional<double> gci_fine; // relative GCI of the finest grid (fraction, 0.01 = 1 %)
  double safety = 0;              // Fs used
  bool oscillatory = false;       // e32 / e21 < 0: the values do not converge monotonically
  std::string note;               // why a value is missing, or what was assumed
};

// Self-convergence of the metric itself. `grids` in any order; at least two. With two, `formal_p`
// (if given) stands in for the observed order and Fs = 3. With three or more, an observed order
// above twice `formal_p` (above 4 without it) is flagged in the note as outside the asymptotic
// range.
Convergence self_convergence(std::vector<GridValue> grids, std::optional<double> formal_p = {});

// Order of an error (tends to 0 under refinement). At least two grids.
Convergence error_convergence(std::vector<GridValue> grids);

} // namespace sph::runner
