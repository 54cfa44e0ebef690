// Observed order, Richardson extrapolation and GCI: see convergence.hpp for the equations.
#include "convergence.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sph::runner {

namespace {

void sort_fine_first(std::vector<GridValue>& g) {
  if (g.size() < 2)
    throw std::invalid_argument("convergence needs at least two resolutions");
  std::sort(g.begin(), g.end(), [](const GridValue& a, const GridValue& b) { return a.h < b.h; });
  for (std::size_t i = 1; i < g.size(); ++i)
    if (!(g[i].h > g[i - 1].h))
      throw std::invalid_argument("two results at one resolution (aggregate or filter them first)");
  for (const GridValue& x : g)
    if (!(x.h > 0) || !std::isfinite(x.f))
      throw std::invalid_argument("a resolution must be positive and a value finite");
}

// Richardson value and GCI of the finest pair for a given order.
void finish(Convergence& c, const GridValue& g1, const GridValue& g2, double p) {
  const double rp = std::pow(g2.h / g1.h, p);
  if (!(rp > 1.0 + 1e-12))
    return;
  c.f_ext = (rp * g1.f - g2.f) / (rp - 1.0);
  if (g1.f != 0.0)
    c.gci_fine = c.safety * std::abs((g1.f - g2.f) / g1.f) / (rp - 1.0);
  else
    c.note += (c.note.empty() ? "" : "; ") + std::string("finest value 0: no relative GCI");
}

} // namespace

Convergence self_convergence(std::vector<GridValue> g, std::optional<double> formal_p) {
  sort_fine_first(g);
  Convergence c;
  c.grids = g.size();
  if (g.size() == 2) {
    c.safety = 3.0;
    if (!formal_p) {
      c.note = "two resolutions: the order cannot be observed (give a formal order)";
      return c;
    }
    c.p = *formal_p;
    c.note = "two resolutions: formal order assumed";
    finish(c, g[0], g[1], *formal_p);
    return c;
  }
  c.safety = 1.25;
  const GridValue &g1 = g[0], &g2 = g[1], &g3 = g[2];
  const double e21 = g2.f - g1.f, e32 = g3.f - g2.f;
  if (e21 == 0.0 || e32 == 0.0) {
    c.note = "two resolutions give the same value: no order";
    return c;
  }
  const double ratio = e32 / e21;
  c.oscillatory = ratio < 0;
  const double s = ratio < 0 ? -1.0 : 1.0;
  const double r21 = g2.h / g1.h, r32 = g3.h / g2.h;
  const double lr21 = std::log(r21), lr32 = std::log(r32);
  // The model f = f0 + C h^p gives |e32/e21| = r21^p (r32^p - s) / (r21^p - s) =: m(p), which
  // grows with p from m(0) = ln r32 / ln r21 (s = 1) or 1 (s = -1). Celik et al.'s fixed-point
  // form p = |ln|e32/e21| + q(p)| / ln r21 is solved here as m(p) = |e32/e21| by bisection (the
  // fixed point does not always converge for unequal ratios), and a ratio at or below m(0),
  // which that form's absolute value would turn into a positive order, is said instead: the
  // differences then do not shrink under refinement.
  auto log_m = [&](double q) {
    return q * lr21 + std::log((std::pow(r32, q) - s) / (std::pow(r21, q) - s));
  };
  const double target = std::log(std::abs(ratio));
  if (target <= (s > 0 ? std::log(lr32 / lr21) : 0.0)) {
    c.note = s > 0 ? "the differences do not shrink under refinement: not converging, no order"
                   : "the oscillations do not shrink under refinement: not converging, no order";
    return c;
  }
  double lo = 1e-9, hi = 1.0;
  while (log_m(hi) < target && hi < 1e3)
    hi *= 2;
  if (!(log_m(hi) >= target)) {
    c.note = "no order up to 1000 fits the differences";
    return c;
  }
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (log_m(mid) < target ? lo : hi) = mid;
  }
  const double p = 0.5 * (lo + hi);
  c.p = p;
  if (c.oscillatory)
    c.note = "oscillatory convergence (the differences change sign)";
  // An order far above what SPH discretisations reach (at most about 2 in space) means the
  // coarse runs are outside the asymptotic range: the extrapolation and a small GCI are then not
  // to be trusted (Celik et al. 2008 advise reporting this rather than the index alone).
  const double ceiling = formal_p ? 2.0 * *formal_p : 4.0;
  if (p > ceiling)
    c.note += std::string(c.note.empty() ? "" : "; ") + "p above " +
              (formal_p ? "twice the formal order" : "4") +
              ": not in the asymptotic range, the GCI understates the uncertainty";
  finish(c, g1, g2, p);
  return c;
}

Convergence error_convergence(std::vector<GridValue> g) {
  sort_fine_first(g);
  Convergence c;
  c.grids = g.size();
  c.safety = g.size() >= 3 ? 1.25 : 3.0;
  for (const GridValue& x : g)
    if (!(std::abs(x.f) > 0)) {
      c.note = "an error of 0: no order";
      return c;
    }
  c.p = std::log(std::abs(g[1].f / g[0].f)) / std::log(g[1].h / g[0].h);
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(g.size());
  for (const GridValue& x : g) {
    const double lx = std::log(x.h), ly = std::log(std::abs(x.f));
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  c.p_fit = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  c.f_ext = 0.0; // the reference the error is measured against
  return c;
}

} // namespace sph::runner
