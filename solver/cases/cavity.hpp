// Shared by the cases "lid_driven_cavity" and "cavity_cylinder" (seed 001, Zheng, Ma & Shao
// 2018, sections 5.1 and 5.2; seed 002, section 4.2): the geometry builder, the parameters, the
// steady-state criterion and the run entry point (cavity.cpp: a FlowCase on the shared time loop,
// with any scheme that runs 2D flows with walls: isph, wcsph_tvf).
//
// Geometry: unit square cavity H = L = 1, fluid particles on the cell-centred lattice
// ((i + 1/2) dx, (j + 1/2) dx), surrounded by `layers` layers of wall particles on the same
// lattice. Wall particles above y = 1 form the lid with prescribed velocity (U0, 0): the whole top
// band, the corner columns above the side walls (x < 0, x > 1) included (lid_corners = "moving",
// the default), or only the columns above the cavity, 0 < x < 1 (lid_corners = "resting": the
// corner columns belong to the side walls and are at rest); the others are at rest. With
// cylinder_d > 0 a cylinder of that
// diameter at (0.5, 0.5): lattice points inside it within `layers` dx of its surface are Body
// particles at rest, deeper points are left out. Mass m = rho0 dx^2, rho0 = 1.
#pragma once

#include "cases/case.hpp"
#include "core/particles.hpp"
#include "diagnostics/cavity_profiles.hpp"
#include "diagnostics/profiles.hpp"
#include "io/checkpoint.hpp"
#include "schemes/scheme.hpp"

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
  double cylinder_d = 0.0;      // 0: empty cavity
  bool lid_corners_move = true; // the lid band's corner columns (x < 0, x > 1) move with the lid
};

// Fills p (must be empty) and returns the index of the vector field "v_wall" holding every
// particle's prescribed wall velocity (zero for fluid). Throws if 1/dx is not an integer.
int build_cavity(Particles<2>& p, const CavityGeometry& g);

// The geometry of a cavity job: dx, lid_corners and (with a cylinder) cylinder_d from its
// parameters, U0 = 1, wall layers one kernel support deep.
CavityGeometry cavity_geometry(const Params& prm, bool cylinder, double support);

// The cases' own parameters (Re, dx, dt, t_end, steady-state criterion, output interval); the
// 3D cavity takes them with its own defaults.
std::vector<ParamSpec> cavity_params(bool cylinder);

RunResult run_cavity(const Params& prm, const RunContext& ctx, bool cylinder);
// Its size before it runs (CaseInfo::size).
JobSize size_cavity(const Params& prm, bool cylinder);

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
};

// What the 2D and 3D cavity cases watch while they run, the same for both (their FlowCase hooks
// call it): the steady window (parameters steady_window, steady_tol), the largest |rho / rho0 - 1|
// of the fluid (rho0 = 1), and the history sampled every history_interval and at t_end: t, E_k,
// density deviation and the scheme's probes; the scheme is asked for its costly diagnostics on the
// steps that end on a sample. Its checkpoint state is named under `prefix`.
template <int D>
class CavityMonitor {
public:
  CavityMonitor(const Params& prm, std::string prefix)
      : prefix_(std::move(prefix)), t_end_(get_real(prm, "t_end")),
        out_dt_(get_real(prm, "history_interval")) {
    steady_.window = get_real(prm, "steady_window"), steady_.tol = get_real(prm, "steady_tol");
  }

  void start(const Particles<D>& p, const FlowScheme<D>& s) {
    sample(p, s, 0.0, kinetic_energy(p), 0.0);
    next_out_ = out_dt_;
  }
  void before_step(FlowScheme<D>& s, double t) { s.measure_next_step(due(t + s.stable_dt())); }
  // After a step of length dt that reached t; true when the flow is steady.
  bool after_step(const Particles<D>& p, const FlowScheme<D>& s, double t, double dt) {
    const double ke = kinetic_energy(p), drho = density_dev(p);
    drho_max_ = std::max(drho_max_, drho);
    if (due(t)) {
      sample(p, s, t, ke, drho);
      while (next_out_ <= t * (1.0 + 1e-12))
        next_out_ += out_dt_;
    }
    steady_now_ = steady_.add(ke, dt);
    return steady_now_;
  }
  // The last history row at the end time t, unless the last step sampled it already.
  void finish(const Particles<D>& p, const FlowScheme<D>& s, double t) {
    if (!(hist_[0].size() && hist_[0].back() == t))
      sample(p, s, t, kinetic_energy(p), density_dev(p));
  }

  double t_end() const { return t_end_; }
  bool steady() const { return steady_now_; }
  double density_dev_max() const { return drho_max_; }
  const std::vector<std::string>& history_names() const { return names_; }
  const std::vector<std::vector<double>>& history() const { return hist_; }

  std::vector<std::string> state_names() const {
    std::vector<std::string> n{prefix_ + "/loop"};
    for (const auto& h : names_)
      n.push_back(prefix_ + "/history/" + h);
    return n;
  }
  void save_state(StateArrays& out) const {
    out[prefix_ + "/loop"] = {steady_.sum, steady_.span, steady_.prev, next_out_, drho_max_};
    for (std::size_t k = 0; k < names_.size(); ++k)
      out[prefix_ + "/history/" + names_[k]] = hist_[k];
  }
  void load_state(const StateArrays& in) {
    const auto& a = in.at(prefix_ + "/loop");
    io::expect_state_size(a, 5, "checkpoint array " + prefix_ + "/loop");
    steady_.sum = a[0], steady_.span = a[1], steady_.prev = a[2], next_out_ = a[3];
    drho_max_ = a[4];
    for (std::size_t k = 0; k < names_.size(); ++k)
      hist_[k] = in.at(prefix_ + "/history/" + names_[k]);
  }

private:
  std::string prefix_;
  double t_end_, out_dt_;
  SteadyWindow steady_;
  bool steady_now_ = false;
  double next_out_ = 0.0, drho_max_ = 0.0;
  std::vector<std::string> names_; // named by the first sample
  std::vector<std::vector<double>> hist_;

  bool due(double t) const { return t >= next_out_ * (1.0 - 1e-12) || t >= t_end_ * (1.0 - 1e-12); }
  static double density_dev(const Particles<D>& p) {
    double d = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid)
        d = std::max(d, std::abs(p.rho[i] - 1.0)); // rho0 = 1
    return d;
  }
  void sample(const Particles<D>&, const FlowScheme<D>& s, double t, double ke, double drho) {
    std::vector<std::pair<std::string, double>> row{{"t", t}, {"ke", ke}, {"density_dev", drho}};
    for (auto& pr : s.probes())
      row.push_back(pr);
    if (names_.empty()) {
      for (auto& [n, v] : row)
        names_.push_back(n);
      hist_.resize(row.size());
    }
    for (std::size_t k = 0; k < row.size() && k < hist_.size(); ++k)
      hist_[k].push_back(row[k].second);
  }
};

// The end of a cavity run, common to its schemes: the job's message ("steady at t = ..." or
// "reached t_end", then how it resumed), and the HDF5 file <output_dir>/<case>.h5 (nothing
// without an output directory): the attributes, the history (named columns), the fine-line
// profiles and the final fluid fields (pressure relative to its fluid mean: the level of a closed
// cavity is arbitrary).
std::string cavity_run_message(bool steady, double t, const std::string& resumed);
struct CavityAttributes {
  const Params& params; // every job parameter, typed, and the job key (io/job_attributes.hpp)
  std::string job_key;
  std::vector<std::pair<std::string, double>> number; // derived values (t_stop)
};
void write_cavity_h5(const std::filesystem::path& output_dir, bool cylinder,
                     const CavityAttributes& attrs, const std::vector<std::string>& history_names,
                     const std::vector<std::vector<double>>& history, const CavityProfiles& prof,
                     const Particles<2>& p);

} // namespace sph
