// The "fields" group of a job's HDF5 output: x, y, ux, uy, p of the fluid particles at the end of
// the run (2D), for field plots. With remove_mean_pressure the pressure is given relative to its
// mean over the fluid (an incompressible solver's pressure is defined up to a constant).
#pragma once

#include "core/particles.hpp"
#include "io/hdf5.hpp"

#include <algorithm>

namespace sph::io {

inline void write_fluid_fields(H5Writer& w, const Particles<2>& p,
                               bool remove_mean_pressure = false) {
  std::vector<double> fx, fy, fu, fv, fp;
  double p_mean = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.kind[i] == Kind::Fluid)
      fx.push_back(p.r[i].x()), fy.push_back(p.r[i].y()), fu.push_back(p.v[i].x()),
          fv.push_back(p.v[i].y()), fp.push_back(p.p[i]), p_mean += p.p[i];
  if (remove_mean_pressure) {
    p_mean /= static_cast<double>(std::max<std::size_t>(fp.size(), 1));
    for (auto& x : fp)
      x -= p_mean;
  }
  w.write_columns("fields", {"x", "y", "ux", "uy", "p"}, {fx, fy, fu, fv, fp});
}

} // namespace sph::io
