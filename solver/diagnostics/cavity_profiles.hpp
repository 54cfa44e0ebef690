// Centreline diagnostics of the lid-driven cavity (seed 001 section 5, Figs. 9-10 and 13-14),
// independent of the scheme that produced the particles:
//   ux along x = 0.5 and uy along y = 0.5, sampled by Shepard interpolation (profiles.hpp) at
//   Ghia's 17 points (metrics ux_at_y_<y>, uy_at_x_<x>, names with Ghia's four decimals) and on a
//   fine line of n_fine points (returned for HDF5); ux_min and its position y (fine line), uy
//   extrema; with a Ghia table (empty cavity at Re = 100 or 1000, data/ghia1982.hpp) the errors
//   against Ghia et al. 1982:
//     ux_min_err = |ux_min - u_min,Ghia|   (seed 001 section 5.1, Err = |u_xmin,n - u_xmin,e|;
//                  ux_min from the fine line, u_min,Ghia the smallest of Ghia's 17 values)
//     ux_rms_err, ux_max_err, uy_rms_err, uy_max_err over Ghia's 15 interior points (the two end
//     points are the boundary values).
// Points inside a solid (`in_solid`) take the solid's velocity 0.
#pragma once

#include "core/params.hpp"
#include "core/run.hpp"
#include "data/ghia1982.hpp"
#include "diagnostics/profiles.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace sph {

struct CavityProfiles {
  std::vector<double> y_line, ux_line; // u_x(0.5, y)
  std::vector<double> x_line, uy_line; // u_y(x, 0.5)
};

inline std::string ghia_metric_name(const char* prefix, double coord) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s%.4f", prefix, coord);
  return buf;
}

template <class Kernel, class Use, class InSolid>
CavityProfiles cavity_profile_metrics(const Particles<2>& p, const Kernel& kernel, Use use,
                                      InSolid in_solid, const data::GhiaTable& ghia, RunResult& res,
                                      int n_fine = 501) {
  using data::ghia_points;
  std::vector<Vec2> pts;
  for (int k = 0; k < ghia_points; ++k)
    pts.emplace_back(0.5, data::ghia_re1000_y[k]);
  for (int k = 0; k < ghia_points; ++k)
    pts.emplace_back(data::ghia_re1000_x[k], 0.5);
  for (int k = 0; k < n_fine; ++k)
    pts.emplace_back(0.5, static_cast<double>(k) / (n_fine - 1));
  for (int k = 0; k < n_fine; ++k)
    pts.emplace_back(static_cast<double>(k) / (n_fine - 1), 0.5);
  auto u = shepard_sample<2>(p, kernel, pts, use);
  for (std::size_t k = 0; k < pts.size(); ++k)
    if (in_solid(pts[k]))
      u[k] = Vec2::Zero();

  CavityProfiles prof;
  double ux_err2 = 0, ux_errmax = 0, uy_err2 = 0, uy_errmax = 0;
  int n_int = 0;
  for (int k = 0; k < ghia_points; ++k)
    res.add(ghia_metric_name("ux_at_y_", data::ghia_re1000_y[k]), u[k].x());
  for (int k = 0; k < ghia_points; ++k)
    res.add(ghia_metric_name("uy_at_x_", data::ghia_re1000_x[k]), u[ghia_points + k].y());
  const bool compare_ghia = ghia.u && ghia.v;
  for (int k = 1; compare_ghia && k + 1 < ghia_points; ++k) {
    const double ex = u[k].x() - (*ghia.u)[k];
    const double ey = u[ghia_points + k].y() - (*ghia.v)[k];
    ux_err2 += ex * ex, uy_err2 += ey * ey, ++n_int;
    ux_errmax = std::max(ux_errmax, std::abs(ex)), uy_errmax = std::max(uy_errmax, std::abs(ey));
  }
  const std::size_t f0 = 2 * ghia_points, f1 = f0 + n_fine;
  double ux_min = 1e300, ux_min_y = 0, uy_max = -1e300, uy_max_x = 0, uy_min = 1e300, uy_min_x = 0;
  for (int k = 0; k < n_fine; ++k) {
    const Vec2 a = u[f0 + k], b = u[f1 + k];
    prof.y_line.push_back(pts[f0 + k].y()), prof.ux_line.push_back(a.x());
    prof.x_line.push_back(pts[f1 + k].x()), prof.uy_line.push_back(b.y());
    if (a.x() < ux_min)
      ux_min = a.x(), ux_min_y = pts[f0 + k].y();
    if (b.y() > uy_max)
      uy_max = b.y(), uy_max_x = pts[f1 + k].x();
    if (b.y() < uy_min)
      uy_min = b.y(), uy_min_x = pts[f1 + k].x();
  }
  res.add("ux_min", ux_min);
  res.add("ux_min_y", ux_min_y);
  res.add("uy_max", uy_max);
  res.add("uy_max_x", uy_max_x);
  res.add("uy_min", uy_min);
  res.add("uy_min_x", uy_min_x);
  if (compare_ghia) {
    res.add("ux_min_err", std::abs(ux_min - ghia.u_min));
    res.add("ux_rms_err", std::sqrt(ux_err2 / n_int));
    res.add("ux_max_err", ux_errmax);
    res.add("uy_rms_err", std::sqrt(uy_err2 / n_int));
    res.add("uy_max_err", uy_errmax);
  }
  return prof;
}

} // namespace sph
