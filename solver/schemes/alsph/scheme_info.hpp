// Registry entry of scheme "alsph" (alsph.cpp), and what a case that runs it needs before the
// scheme exists.
#pragma once

#include "core/params.hpp"

namespace sph::alsph {
// The smoothing length h = h_over_dx dx of the job's parameters (the case's geometry: buffer
// depth, body rings and ghost layers are built on the kernel support 3 h).
double smoothing_length(const Params& prm, double dx);
} // namespace sph::alsph
