// Shared by the cases "lid_driven_cavity" and "cavity_cylinder" (seed 001, Zheng, Ma & Shao
// 2018, sections 5.1 and 5.2; seed 002, section 4.2): the geometry builder, the parameters, the
// steady-state criterion and the run entry point (cavity.cpp: a FlowCase on the shared time loop,
// with any scheme that runs 2D flows with walls: isph, wcsph_tvf).
//
// Geometry: unit square cavity H = L = 1, fluid particles on the cell-centred lattice
// ((i + 1/2) dx, (j + 1/2) dx), surrounded by `layers` layers of wall particles on the same
// lattice. Wall particles above y = 1 (the whole top band, corners included) form the lid with
// prescribed velocity (U0, 0); the others are at rest. With cylinder_d > 0 a cylinder of that
// diameter at (0.5, 0.5): lattice points inside it within `layers` dx of its surface are Body
// particles at rest, deeper points are left out. Mass m = rho0 dx^2, rho0 = 1.
#pragma once

#include "cases/case.hpp"
#include "core/particles.hpp"
#include "diagnostics/cavity_profiles.hpp"

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sph {

struct CavityGeometry {
  double dx = 0.01;
  int layers = 3;
  double U0 = 1.0;
  double cylinder_d = 0.0; // 0: empty cavity
};

// Fills p (must be empty) and returns the index of the vector field "v_wall" holding every
// particle's prescribed wall velocity (zero for fluid). Throws if 1/dx is not an integer.
int build_cavity(Particles<2>& p, const CavityGeometry& g);

// The geometry of a cavity job: dx and (with a cylinder) cylinder_d from its parameters, U0 = 1,
// wall layers one kernel support deep.
CavityGeometry cavity_geometry(const Params& prm, bool cylinder, double support);

// The cases' own parameters (Re, dx, dt, t_end, steady-state criterion, output interval).
std::vector<ParamSpec> cavity_params(bool cylinder);

RunResult run_cavity(const Params& prm, const RunContext& ctx, bool cylinder);

// The cavity cases' constraint on their parameters (CaseInfo::check): 1/dx an integer >= 4.
std::optional<std::string> cavity_dx_check(const Params& prm);

// The steady-state criterion of the cavity cases: the time-weighted mean of E_k over consecutive
// windows of length `window`; steady when two consecutive means differ by less than tol times the
// last (tol = 0: never). The window mean, not E_k at one instant, because particle disorder makes
// E_k flicker by a few 1e-3 at a steady state (measured: +-0.3 % at Re = 100, dx = 0.02).
struct SteadyWindow {
  double window = 2.0, tol = 5e-4;
  double sum = 0.0, span = 0.0, prev = -1.0; // the open window's integral and length; last mean

  // Adds E_k over a step of length dt; true when the flow is steady.
  bool add(double ke, double dt) {
    sum += ke * dt, span += dt;
    if (span < window * (1.0 - 1e-9))
      return false;
    const double mean = sum / span;
    sum = span = 0.0;
    if (tol > 0.0 && prev > 0.0 && std::abs(mean - prev) < tol * mean)
      return true;
    prev = mean;
    return false;
  }
  std::vector<double> state() const { return {sum, span, prev}; }
  void restore(const std::vector<double>& s) { sum = s.at(0), span = s.at(1), prev = s.at(2); }
};

// The end of a cavity run, common to its schemes: the job's message ("steady at t = ..." or
// "reached t_end", then how it resumed), and the HDF5 file <output_dir>/<case>.h5 (nothing
// without an output directory): the attributes, the history (named columns), the fine-line
// profiles and the final fluid fields (pressure relative to its fluid mean: the level of a closed
// cavity is arbitrary).
std::string cavity_run_message(bool steady, double t, const std::string& resumed);
struct CavityAttributes {
  std::vector<std::pair<std::string, std::string>> text;
  std::vector<std::pair<std::string, double>> number;
};
void write_cavity_h5(const std::filesystem::path& output_dir, bool cylinder,
                     const CavityAttributes& attrs, const std::vector<std::string>& history_names,
                     const std::vector<std::vector<double>>& history, const CavityProfiles& prof,
                     const Particles<2>& p);

} // namespace sph
