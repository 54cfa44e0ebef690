// Geometry, parameters and the FlowCase of the cavity cases (see cavity.hpp), on the shared time
// loop (cases/time_loop.hpp) with the job's scheme (isph: fixed steps dt; wcsph_tvf: its own
// dual-criteria steps, the case's dt unused).
//
// Per step: E_k and the largest |rho / rho0 - 1| of the fluid (density_dev_max: the
// compressibility of a weakly-compressible scheme, about (U/c0)^2 = 1 % by design; 0 for ISPH);
// the steady-state window (SteadyWindow: t_stop, steady = 1); a history sample every
// history_interval (HDF5 history/{t, ke, density_dev} and the scheme's probes, ISPH: div_max,
// ppe_iters), the scheme asked for its costly diagnostics on the steps that end on a sample.
// Diverged when a fluid velocity is not finite or exceeds 20 U0 (checked every step).
// At the end the solid particles take the no-slip mirror velocity the fluid sees, and the
// centreline profiles and metrics of diagnostics/cavity_profiles.hpp are computed with the
// scheme's kernel; with an output directory <output_dir>/<case>.h5 holds the history, the
// fine-line profiles and the final fields.
//
// Metrics besides the profiles: ke, t_stop, steady, density_dev_max, n_fluid, fluid_outside (fluid
// particles that ended the run outside the fluid domain, i.e. went through a wall), the scheme's
// own (isph: div_max, div_max_x, div_max_y, div_rms of the last measured step, ppe_*; wcsph_tvf:
// acoustic_steps) and the loop's costs (steps, wall_time_s, time_per_step_s, cpu_time_per_step_s,
// time_per_particle_step_s, n_particles).
//
// Checkpoints: the loop's (particles, costs), this case's state (sample clock, steady window,
// density extreme, history) and the scheme's; a resumed job rebuilds the initial lattice (so the
// scheme's reference density is the same) and continues bit for bit.
#include "cases/cavity.hpp"

#include "cases/time_loop.hpp"
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "diagnostics/cavity_profiles.hpp"
#include "io/hdf5.hpp"
#include "io/job_attributes.hpp"
#include "io/particle_fields.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <omp.h>
#include <stdexcept>

namespace sph {

int build_cavity(Particles<2>& p, const CavityGeometry& g) {
  if (p.size() != 0)
    throw std::invalid_argument("build_cavity: particle set must be empty");
  const int n = static_cast<int>(std::lround(1.0 / g.dx));
  if (n < 4 || std::abs(n * g.dx - 1.0) > 1e-9)
    throw std::invalid_argument("cavity: 1/dx must be an integer >= 4, got dx = " +
                                std::to_string(g.dx));
  const int L = g.layers;
  const double R = 0.5 * g.cylinder_d, m = g.dx * g.dx, rho0 = 1.0;
  const Vec2 c(0.5, 0.5);
  std::vector<Vec2> vw;
  for_each_lattice_point<2>({-L, -L}, {n + L, n + L}, g.dx,
                            [&](const Vec2& x, const std::array<int, 2>& i) {
                              const bool inside = i[0] >= 0 && i[0] < n && i[1] >= 0 && i[1] < n;
                              if (inside) {
                                const double d = (x - c).norm();
                                if (R > 0.0 && d < R) {
                                  if (d > R - L * g.dx)
                                    p.add(x, m, rho0, Kind::Body), vw.push_back(Vec2::Zero());
                                  return;
                                }
                                p.add(x, m, rho0, Kind::Fluid), vw.push_back(Vec2::Zero());
                              } else {
                                p.add(x, m, rho0, Kind::Wall);
                                const bool over_cavity = i[0] >= 0 && i[0] < n;
                                const bool lid = i[1] >= n && (g.lid_corners_move || over_cavity);
                                vw.push_back(lid ? Vec2(g.U0, 0.0) : Vec2::Zero());
                              }
                            });
  const int f = p.add_vector("v_wall");
  p.vector(f) = vw;
  return f;
}

CavityGeometry cavity_geometry(const Params& prm, bool cylinder, double support) {
  CavityGeometry g;
  g.dx = get_real(prm, "dx");
  g.U0 = 1.0;
  g.layers = static_cast<int>(std::ceil(support / g.dx - 1e-9));
  g.cylinder_d = cylinder ? get_real(prm, "cylinder_d") : 0.0;
  g.lid_corners_move = get_string(prm, "lid_corners") == "moving";
  return g;
}

std::vector<ParamSpec> cavity_params(bool cylinder) {
  std::vector<ParamSpec> s = {
      {"Re", ParamType::Real, 1000.0, "Reynolds number U0 L / nu (U0 = L = 1)", 0.0, {}, true},
      {"dx", ParamType::Real, 0.01, "particle spacing (1/dx must be an integer)", 0.0, 0.25, true},
      {"dt",
       ParamType::Real,
       0.001,
       "time step (isph; wcsph_tvf takes its own dual-criteria steps)",
       0.0,
       {},
       true},
      {"t_end", ParamType::Real, 40.0, "end time unless steady earlier", 0.0, {}, true},
      {"steady_tol", ParamType::Real, 5e-4,
       "stop when the means of E_k over two consecutive windows differ by less than steady_tol "
       "times the last (0: run to t_end)",
       0.0, 1.0},
      {"steady_window",
       ParamType::Real,
       2.0,
       "length of the E_k averaging window (time)",
       0.0,
       {},
       true},
      {"history_interval",
       ParamType::Real,
       0.1,
       "time between samples of the E_k history (HDF5 history/)",
       0.0,
       {},
       true,
       {},
       false},
  };
  ParamSpec corners{
      "lid_corners",
      ParamType::String,
      std::string("moving"),
      "wall particles of the lid band above the side walls (2D: x < 0, x > 1; 3D: "
      "outside 0 < x, y < 1): moving with the lid, or resting (part of the side walls)",
      {},
      {},
      false,
      {"moving", "resting"}};
  corners.neutral_default = true; // added later: the jobs without it keep their keys
  s.push_back(corners);
  if (cylinder)
    s.push_back(
        {"cylinder_d", ParamType::Real, 0.5, "cylinder diameter / L (centred)", 0.0, 0.9, true});
  add_loop_params(s); // output_interval (cases/loop_params.hpp)
  return s;
}

namespace {

class Cavity final : public FlowCase<2> {
public:
  Cavity(const Params& prm, bool cylinder) : prm_(prm), cylinder_(cylinder), mon_(prm, "cavity") {
    Re_ = get_real(prm, "Re"), dx_ = get_real(prm, "dx");
  }

  Flow<2> build(Particles<2>& p) override {
    p_ = &p;
    const double support =
        kernel_support_factor(get_string(prm_, "kernel")) * (get_real(prm_, "h_over_dx") * dx_);
    g_ = cavity_geometry(prm_, cylinder_, support);
    Flow<2> f;
    f.v_wall = build_cavity(p, g_);
    for (auto k : p.kind)
      n_fluid_ += k == Kind::Fluid;
    f.rho0 = 1.0, f.U = g_.U0, f.L = 1.0, f.Re = Re_, f.dx = dx_;
    f.dt = get_real(prm_, "dt");
    return f;
  }
  void start(FlowScheme<2>& s) override { mon_.start(*p_, s); }
  double t_end() const override { return mon_.t_end(); }
  double speed_bound() const override { return 20.0 * g_.U0; }

  void before_step(FlowScheme<2>& s, const LoopState& at) override { mon_.before_step(s, at.t); }
  bool after_step(FlowScheme<2>& s, const LoopState& at, const StepStats& st) override {
    return mon_.after_step(*p_, s, at.t, st.dt);
  }

  void finish(FlowScheme<2>& s, const LoopState& at, RunResult& res) override {
    mon_.finish(*p_, s, at.t);
    s.wall_velocities_for_output();
    const double R = 0.5 * g_.cylinder_d;
    auto use = [&](std::size_t) { return true; };
    auto in_solid = [&](const Vec2& x) { return R > 0.0 && (x - Vec2(0.5, 0.5)).norm() < R; };
    const data::GhiaTable ghia = cylinder_ ? data::GhiaTable{} : data::ghia_table(Re_);
    const CavityProfiles prof = with_kernel<2>(s.kernel_name(), s.h(), [&](const auto& W) {
      return cavity_profile_metrics(*p_, W, use, in_solid, ghia, res);
    });
    res.add("ke", kinetic_energy(*p_));
    res.add("t_stop", at.t);
    res.add("steady", mon_.steady() ? 1.0 : 0.0);
    res.add("density_dev_max", mon_.density_dev_max());
    res.add("n_fluid", static_cast<double>(n_fluid_));
    res.add("fluid_outside", static_cast<double>(fluid_outside(R)));
    const CavityAttributes attrs{prm_, job_key_, {{"t_stop", at.t}}};
    write_cavity_h5(output_dir_, cylinder_, attrs, mon_.history_names(), mon_.history(), prof, *p_);
  }
  std::string summary(const LoopState& at) const override {
    return cavity_run_message(mon_.steady(), at.t, "");
  }

  std::vector<std::string> state_names() const override { return mon_.state_names(); }
  void save_state(StateArrays& out) const override { mon_.save_state(out); }
  void load_state(const StateArrays& in) override { mon_.load_state(in); }

  std::filesystem::path output_dir_;
  std::string job_key_;

private:
  const Params& prm_;
  bool cylinder_;
  CavityMonitor<2> mon_;
  double Re_, dx_;
  CavityGeometry g_;
  Particles<2>* p_ = nullptr;
  std::size_t n_fluid_ = 0;

  // Fluid particles that have left the fluid domain (x or y outside [0, 1], or inside the
  // cylinder of radius R): particles that went through a wall.
  std::size_t fluid_outside(double R) const {
    std::size_t k = 0;
    for (std::size_t i = 0; i < p_->size(); ++i) {
      if (p_->kind[i] != Kind::Fluid)
        continue;
      const Vec2& x = p_->r[i];
      const bool out = x.x() < 0.0 || x.x() > 1.0 || x.y() < 0.0 || x.y() > 1.0;
      k += out || (R > 0.0 && (x - Vec2(0.5, 0.5)).norm() < R);
    }
    return k;
  }
};

} // namespace

std::string cavity_run_message(bool steady, double t, const std::string& resumed) {
  std::string m = steady ? "steady at t = " + std::to_string(t) : "reached t_end";
  return resumed.empty() ? m : m + "; " + resumed;
}

void write_cavity_h5(const std::filesystem::path& output_dir, bool cylinder,
                     const CavityAttributes& attrs, const std::vector<std::string>& history_names,
                     const std::vector<std::vector<double>>& history, const CavityProfiles& prof,
                     const Particles<2>& p) {
  if (output_dir.empty())
    return;
  io::H5Writer w(output_dir /
                 (std::string(cylinder ? "cavity_cylinder" : "lid_driven_cavity") + ".h5"));
  io::write_job_attributes(w, cylinder ? "cavity_cylinder" : "lid_driven_cavity", attrs.params,
                           attrs.job_key);
  for (const auto& [k, v] : attrs.number)
    w.attribute(k, v);
  w.write_columns("history", history_names, history);
  w.write_columns("profile_x0.5", {"y", "ux"}, {prof.y_line, prof.ux_line});
  w.write_columns("profile_y0.5", {"x", "uy"}, {prof.x_line, prof.uy_line});
  io::write_fluid_fields(w, p, true);
  w.close();
}

std::optional<std::string> cavity_dx_check(const Params& prm) {
  const double dx = get_real(prm, "dx");
  const long n = std::lround(1.0 / dx);
  if (n >= 4 && std::abs(static_cast<double>(n) * dx - 1.0) <= 1e-9)
    return std::nullopt;
  char buf[160];
  const long m = std::max(4L, n);
  std::snprintf(buf, sizeof buf, "dx = %g: 1/dx must be an integer >= 4 (e.g. dx = 1/%ld = %g)", dx,
                m, 1.0 / static_cast<double>(m));
  return std::string(buf);
}

JobSize size_cavity(const Params& prm, bool cylinder) {
  Cavity c(prm, cylinder);
  return size_flow_case<2>(c, prm, "isph");
}

RunResult run_cavity(const Params& prm, const RunContext& ctx, bool cylinder) {
  Cavity c(prm, cylinder);
  c.output_dir_ = ctx.output_dir, c.job_key_ = ctx.job_key;
  return run_flow_case<2>(c, prm, ctx, "isph");
}

} // namespace sph
