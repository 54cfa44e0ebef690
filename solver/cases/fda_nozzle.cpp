// Case "fda_nozzle": the FDA benchmark nozzle of seed 002 (Wang, Haidn & Hu 2024, section 4.6,
// Figs. 14-17), in the sudden-expansion orientation at throat Reynolds number 500, on the shared
// time loop with the scheme "wcsph_tvf"; compared with the benchmark's PIV (Hariharan et al.,
// J. Biomech. Eng. 133 (2011) 041002; solver/data/fda_piv_re500.hpp, studies/reference/
// fda_piv_re500_*.csv).
//
// Geometry (Stewart et al., Cardiovasc. Eng. Technol. 3 (2012) 139, Fig. 1; SI units, x the axis,
// the flow towards +x, x = 0 the sudden expansion as in the PIV files): an inlet pipe of radius
// 6 mm, a cone of 10 degree half-angle (length 4 mm / tan 10 deg = 22.685 mm) to the throat of
// radius 2 mm and length 40 mm, the sudden expansion back to radius 6 mm, an outlet pipe.
// upstream_length of inlet pipe before the cone, downstream_length of outlet pipe. Particles on
// body-fitted rings (core/axisymmetric_duct.hpp), slices anchored at the expansion (x = 0 is a
// slice boundary, so is the throat's start when 40 mm / dx is an integer), walls one kernel
// support thick, at rest (no-slip by the scheme's wall treatment), each with the wall's normal
// into the fluid at its nearest point of the wall line (for wall_dissipation = normal).
// Fluid: rho0 = 1056 kg/m^3, mu = 0.0035 Pa s (the benchmark's blood analogue); the throat's mean
// velocity U_t = Re mu / (rho0 D_t) (0.4143 m/s at Re = 500), the flow rate Q = U_t pi R_t^2
// (5.206e-6 m^3/s, the PIV files' value). Reference speed of the scheme U = 2 U_t (the throat's
// Poiseuille peak: c0 = c0_factor U, the time-step criteria), length D_t, Re_ref = 2 Re.
// Inflow: the emitter (boundaries/open_boundary.hpp) over the inlet's rings, buffer_layers slices
// upstream of x_in, velocity u = 2 U_in (1 - (rho^2 + dr^2/4) / R^2) f(t) along x, U_in = Q /
// (pi R^2): the Poiseuille profile averaged over each ring's annulus, so that the emitted flux is Q
// f(t) exactly on the rings; f(t) = (1 - cos(pi t / ramp_time)) / 2 for t < ramp_time, else 1 (the
// seed's smooth start). Inlet buffer pressure: the Shepard average of the fluid's (a zero normal
// gradient). Outflow: the disposer at x_out (pressure 0, deleted buffer_layers slices on), its
// buffer filled from the start (so the last fluid slices have a full support) and moving with the
// Shepard average of the fluid's velocity around each buffer particle (a zero normal gradient;
// open_boundary::BufferVelocity), since the outflow is not known in advance. Start: at rest.
//
// Metrics (at t_end; velocities by Shepard interpolation with the scheme's kernel over fluid and
// wall particles, averaged over the four azimuths 0, 90, 180, 270 degrees; errors normalised by
// U_t; the PIV stations and sections inside (x_in, x_out)):
//   u_centre_at_z_<z>    centreline axial velocity at the PIV stations (m/s)
//   centreline_rms_err, centreline_max_err    against the PIV mean of the five data sets
//   u_centre_throat, u_centre_throat_rel_err  at z = -0.008 (the last station in the throat)
//   profile_rms_err_at_z_<z>, profile_rms_err  the axial velocity across the sections (RMS over
//                        the PIV points at r = 0, 0.25 mm, ...; all sections together)
//   flow_rate_in, flow_rate_out    emitted volume and volume crossing x_out per unit time over the
//                        window t >= t_end - flux_window (m^3/s); flow_imbalance (in - out) / in;
//                        flow_rate_in_rel_err in / Q - 1
//   inflow_rate (m^3/s), inflow_rate_rel_err   the flow rate the inlet's rows impose at t_end
//   (areas times prescribed
//                        velocity) over Q f(t_end), - 1
//   flow_rate_rel_err_at_z_<z>     Q through the planes z = x_in + 10 mm, -0.020 (mid-throat),
//                        +0.020 and +0.060: the fluid's sum V_i u_x,i over a slab of 4 dx around
//                        each, over 4 dx, over Q - 1
//   fluid_volume, throat_volume (m^3) and their _rel_err   the initial fluid's volume (sum
//                        m / rho0) in the lumen and in the throat's slices, against pi R^2 L of
//                        the geometry
//   n_fluid_0, ke (kinetic energy at t_end, J), and the loop's costs.
// HDF5 (<output_dir>/fda_nozzle.h5): centreline/{z,u} on 401 points, root attributes: the job's
// parameters and key (io/job_attributes.hpp).
// Checkpoints: the particles (counts and kinds change), the open boundaries' counters and the
// window's start (fda/state).
#include "boundaries/open_boundary.hpp"
#include "cases/case.hpp"
#include "cases/time_loop.hpp"
#include "core/axisymmetric_duct.hpp"
#include "core/kernels/kernel.hpp"
#include "data/fda_piv_re500.hpp"
#include "diagnostics/profiles.hpp"
#include "io/hdf5.hpp"
#include "io/job_attributes.hpp"
#include "schemes/wcsph_tvf/wcsph_tvf.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <variant>

namespace sph {
namespace {

using V3 = Vec<3>;

// The benchmark's nozzle (Stewart et al. 2012), m.
constexpr double R_pipe = 0.006, R_throat = 0.002, L_throat = 0.040;
const double L_cone = (R_pipe - R_throat) / std::tan(10.0 * std::numbers::pi / 180.0);
constexpr double rho_f = 1056.0, mu_f = 0.0035;
constexpr double z_throat_station = -0.008;

// The planes of the flow-rate metrics: 10 mm after the inlet x_in, mid-throat, 20 and 60 mm after
// the expansion.
std::array<double, 4> flux_planes(double x_in) {
  return {x_in + 0.010, -0.020, 0.020, 0.060};
}

std::string station_name(const char* prefix, double z) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s%.3f", prefix, z);
  return buf;
}

class FdaNozzle final : public FlowCase<3> {
public:
  FdaNozzle(const Params& prm, const RunContext& ctx)
      : prm_(prm), ctx_(ctx),
        duct_({-L_throat - L_cone, -L_throat, 0.0, 0.0}, {R_pipe, R_throat, R_throat, R_pipe}) {
    dx_ = get_real(prm, "dx");
    const double Re = get_real(prm, "Re_throat");
    U_t_ = Re * mu_f / (rho_f * 2.0 * R_throat);
    Q_ = U_t_ * std::numbers::pi * R_throat * R_throat;
    x_in_ = -dx_ * std::round((get_real(prm, "upstream_length") + L_cone + L_throat) / dx_);
    x_out_ = dx_ * std::round(get_real(prm, "downstream_length") / dx_);
    layers_ = static_cast<int>(get_int(prm, "buffer_layers"));
    ramp_ = get_real(prm, "ramp_time");
    t_end_ = get_real(prm, "t_end");
    t_window_ = t_end_ - get_real(prm, "flux_window");
  }

  Flow<3> build(Particles<3>& p) override {
    p_ = &p;
    const double support =
        kernel_support_factor(get_string(prm_, "kernel")) * (get_real(prm_, "h_over_dx") * dx_);
    const double wall = std::ceil(support / dx_ - 1e-9) * dx_;
    // Walls over the buffers too; fluid in [x_in, x_out).
    const int n_in = static_cast<int>(std::lround((0.0 - x_in_) / dx_));
    const int n_out = static_cast<int>(std::lround(x_out_ / dx_));
    const int n_buf = layers_ + static_cast<int>(std::ceil(wall / dx_));
    const double x_lo = x_in_ - n_buf * dx_;
    const int zk = open_boundary::zone_field(p);
    const double x_end = x_out_ + layers_ * dx_;
    const int nk = p.add_vector("normal");
    for (const auto& q : duct_.particles(x_lo, n_buf + n_in + n_out + n_buf, dx_, wall)) {
      const double x = q.r.x();
      const bool outlet = q.fluid && x > x_out_ && x < x_end;
      if (q.fluid && !outlet && !(x > x_in_ && x < x_out_))
        continue; // the inlet buffer's slices are the emitter's
      const Kind kind = outlet ? Kind::Buffer : q.fluid ? Kind::Fluid : Kind::Wall;
      const std::size_t k = p.add(q.r, rho_f * q.V, rho_f, kind);
      if (outlet)
        p.scalar(zk)[k] = 2.0;
      if (kind == Kind::Wall)
        p.vector(nk)[k] = duct_.wall_normal(q.r);
      if (kind == Kind::Fluid) {
        vol_fluid_ += q.V, ++n_fluid_;
        if (q.r.x() > -L_throat && q.r.x() < 0.0)
          vol_throat_ += q.V;
      }
    }
    next_id_ = static_cast<std::int64_t>(p.size());
    // The inflow over the inlet's rings.
    typename open_boundary::Emitter<3>::Config ec;
    ec.x_in = x_in_, ec.layers = layers_, ec.dx = dx_, ec.rho0 = rho_f, ec.zone = 1;
    for (const auto& q : duct_.section(x_in_ - 0.5 * dx_, dx_))
      ec.section.push_back({q.r, q.V});
    const double dr = duct_.ring_spacing(x_in_ - 0.5 * dx_, dx_);
    const double U_in = Q_ / (std::numbers::pi * R_pipe * R_pipe);
    ec.u_in = [this, dr, U_in](const V3& r, double t) {
      const double rho2 = r.y() * r.y() + r.z() * r.z(), f = ramp_factor(t);
      return V3(2.0 * U_in * (1.0 - (rho2 + 0.25 * dr * dr) / (R_pipe * R_pipe)) * f, 0.0, 0.0);
    };
    ec.extrapolate_pressure = true;
    emitter_ = std::make_unique<open_boundary::Emitter<3>>(ec);
    emitter_->fill(p, 0.0, next_id_);
    typename open_boundary::Disposer<3>::Config dc;
    dc.x_out = x_out_, dc.layers = layers_, dc.dx = dx_, dc.zone = 2;
    disposer_ = std::make_unique<open_boundary::Disposer<3>>(dc);

    Flow<3> f;
    f.rho0 = rho_f, f.U = 2.0 * U_t_, f.L = 2.0 * R_throat,
    f.Re = 2.0 * get_real(prm_, "Re_throat");
    f.dx = dx_;
    f.normal = nk; // the walls' normals, into the fluid (wall_dissipation = normal)
    // Whenever the scheme updates pressures: the inlet buffer's the fluid's Shepard average, the
    // outlet buffer's velocity the fluid's (its pressure is the disposer's p = 0).
    f.buffer_pressure = [](Particles<3>& q, const NeighborList<3>& nl) {
      const int zk = open_boundary::zone_field(q);
      auto zone = [&](std::size_t i) {
        return q.kind[i] == Kind::Buffer ? static_cast<int>(q.scalar(zk)[i]) : 0;
      };
      auto inlet = [&](std::size_t i) { return zone(i) == 1; };
      auto outlet = [&](std::size_t i) { return zone(i) == 2; };
      open_boundary::BufferPressure<3, decltype(inlet)> op{q.kind, q.p, inlet, 0.0};
      interact(nl, op, inlet);
      open_boundary::BufferVelocity<3> ov{q.kind, q.v};
      interact(nl, ov, outlet);
    };
    return f;
  }
  double t_end() const override { return t_end_; }
  double speed_bound() const override { return get_real(prm_, "speed_bound") * 2.0 * U_t_; }

  void before_step(FlowScheme<3>& s, const LoopState& at) override {
    bool changed = disposer_->update(*p_);
    changed |= emitter_->update(*p_, at.t + 0.5 * s.stable_dt(), next_id_) > 0;
    if (changed)
      s.particles_changed();
  }
  bool after_step(FlowScheme<3>&, const LoopState& at, const StepStats&) override {
    if (!in_window_ && at.t >= t_window_) {
      in_window_ = true;
      t0_ = at.t, m_in0_ = emitter_->mass_in(), m_out0_ = disposer_->mass_out();
    }
    return false;
  }

  void finish(FlowScheme<3>& s, const LoopState& at, RunResult& res) override {
    s.wall_velocities_for_output();
    const Particles<3>& p = *p_;
    // Sample points: centreline stations, profile points (four azimuths each), the fine
    // centreline.
    std::vector<V3> pts;
    std::vector<double> st_z, st_u;
    for (const auto& st : fda_piv::centreline)
      if (inside(st.z))
        st_z.push_back(st.z), st_u.push_back(st.u), pts.emplace_back(st.z, 0.0, 0.0);
    const std::size_t prof0 = pts.size();
    std::vector<fda_piv::ProfilePoint> prof;
    for (const auto& q : fda_piv::profiles)
      if (inside(q.z)) {
        prof.push_back(q);
        for (int a = 0; a < 4; ++a) {
          const double phi = a * 0.5 * std::numbers::pi;
          pts.emplace_back(q.z, q.r * std::cos(phi), q.r * std::sin(phi));
        }
      }
    const std::size_t fine0 = pts.size();
    constexpr int n_fine = 401;
    for (int k = 0; k < n_fine; ++k)
      pts.emplace_back(x_in_ + (x_out_ - x_in_) * k / (n_fine - 1.0), 0.0, 0.0);
    const auto u = with_kernel<3>(s.kernel_name(), s.h(), [&](const auto& W) {
      return shepard_sample<3>(p, W, pts, [&](std::size_t j) { return p.kind[j] != Kind::Buffer; });
    });

    double c2 = 0.0, cmax = 0.0;
    for (std::size_t k = 0; k < st_z.size(); ++k) {
      const double uk = u[k].x(), e = (uk - st_u[k]) / U_t_;
      res.add(station_name("u_centre_at_z_", st_z[k]), uk);
      c2 += e * e, cmax = std::max(cmax, std::abs(e));
      if (std::abs(st_z[k] - z_throat_station) < 1e-9) {
        res.add("u_centre_throat", uk);
        res.add("u_centre_throat_rel_err", uk / st_u[k] - 1.0);
      }
    }
    if (!st_z.empty()) {
      res.add("centreline_rms_err", std::sqrt(c2 / st_z.size()));
      res.add("centreline_max_err", cmax);
    }
    std::map<double, std::pair<double, int>> by_section;
    double p2 = 0.0;
    for (std::size_t k = 0; k < prof.size(); ++k) {
      double ux = 0.0;
      for (int a = 0; a < 4; ++a)
        ux += 0.25 * u[prof0 + 4 * k + a].x();
      const double e = (ux - prof[k].u) / U_t_;
      auto& [sum, n] = by_section[prof[k].z];
      sum += e * e, ++n, p2 += e * e;
    }
    for (const auto& [z, sn] : by_section)
      res.add(station_name("profile_rms_err_at_z_", z), std::sqrt(sn.first / sn.second));
    if (!prof.empty())
      res.add("profile_rms_err", std::sqrt(p2 / prof.size()));
    // Flow rates through planes: the fluid's volume flux averaged over a slab of four slices
    // around each, sum_i V_i u_x,i / (4 dx) (the particles' own velocities: a Shepard sample next
    // to the no-slip wall's mirrored velocities would bias a coarse section low).
    for (const double z : flux_planes(x_in_)) {
      if (!inside(z - 2.0 * dx_) || !inside(z + 2.0 * dx_))
        continue;
      double q = 0.0;
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Fluid && std::abs(p.r[i].x() - z) < 2.0 * dx_)
          q += p.V[i] * p.v[i].x();
      res.add(station_name("flow_rate_rel_err_at_z_", z), q / (4.0 * dx_) / Q_ - 1.0);
    }
    // The flow rate the inlet imposes: its rows' areas times their prescribed velocity.
    double q_rows = 0.0;
    for (const auto& row : emitter_->config().section)
      q_rows += row.V / dx_ * emitter_->config().u_in(row.r, at.t).x();
    res.add("inflow_rate", q_rows);
    if (ramp_factor(at.t) > 0.0)
      res.add("inflow_rate_rel_err", q_rows / (Q_ * ramp_factor(at.t)) - 1.0);
    const double T = at.t - t0_;
    if (in_window_ && T > 0.0) {
      const double in = (emitter_->mass_in() - m_in0_) / (rho_f * T);
      const double out = (disposer_->mass_out() - m_out0_) / (rho_f * T);
      res.add("flow_rate_in", in);
      res.add("flow_rate_out", out);
      res.add("flow_imbalance", (in - out) / in);
      res.add("flow_rate_in_rel_err", in / Q_ - 1.0);
    }
    res.add("throat_volume", vol_throat_);
    res.add("fluid_volume", vol_fluid_);
    res.add("fluid_volume_rel_err", vol_fluid_ / lumen_volume() - 1.0);
    res.add("throat_volume_rel_err",
            vol_throat_ / (std::numbers::pi * R_throat * R_throat * L_throat) - 1.0);
    res.add("n_fluid_0", static_cast<double>(n_fluid_));
    res.add("ke", kinetic_energy(p));
    if (!ctx_.output_dir.empty()) {
      std::vector<double> zl, ul;
      for (int k = 0; k < n_fine; ++k)
        zl.push_back(pts[fine0 + k].x()), ul.push_back(u[fine0 + k].x());
      io::H5Writer w(ctx_.output_dir / "fda_nozzle.h5");
      io::write_job_attributes(w, "fda_nozzle", prm_, ctx_.job_key);
      w.write_columns("centreline", {"z", "u"}, {zl, ul});
      w.close();
    }
  }

  std::vector<std::string> state_names() const override { return {"fda/state"}; }
  void save_state(StateArrays& out) const override {
    out["fda/state"] = {emitter_->mass_in(),
                        disposer_->mass_out(),
                        disposer_->mass_lost(),
                        static_cast<double>(next_id_),
                        in_window_ ? 1.0 : 0.0,
                        t0_,
                        m_in0_,
                        m_out0_};
  }
  void load_state(const StateArrays& in) override {
    const auto& a = in.at("fda/state");
    io::expect_state_size(a, 8, "fda_nozzle: checkpoint array fda/state");
    emitter_->set_mass_in(a[0]);
    disposer_->set_masses(a[1], a[2]);
    next_id_ = static_cast<std::int64_t>(a[3]);
    in_window_ = a[4] != 0.0, t0_ = a[5], m_in0_ = a[6], m_out0_ = a[7];
  }

private:
  Params prm_;
  RunContext ctx_;
  AxisymmetricDuct duct_;
  double dx_ = 0.0, U_t_ = 0.0, Q_ = 0.0, x_in_ = 0.0, x_out_ = 0.0, ramp_ = 0.0;
  double t_end_ = 0.0, t_window_ = 0.0;
  int layers_ = 4;
  Particles<3>* p_ = nullptr;
  std::unique_ptr<open_boundary::Emitter<3>> emitter_;
  std::unique_ptr<open_boundary::Disposer<3>> disposer_;
  std::int64_t next_id_ = 0;
  double vol_fluid_ = 0.0, vol_throat_ = 0.0;
  std::size_t n_fluid_ = 0;
  bool in_window_ = false;
  double t0_ = 0.0, m_in0_ = 0.0, m_out0_ = 0.0;

  bool inside(double z) const { return z > x_in_ && z < x_out_; }
  // The smooth start f(t) of the inflow.
  double ramp_factor(double t) const {
    return t < ramp_ ? 0.5 * (1.0 - std::cos(std::numbers::pi * t / ramp_)) : 1.0;
  }
  // pi R^2 L of the pipes and the throat, the cone's frustum, between x_in and x_out.
  double lumen_volume() const {
    const double pi = std::numbers::pi, x_c = -L_throat - L_cone;
    return pi * R_pipe * R_pipe * ((x_c - x_in_) + x_out_) +
           pi / 3.0 * L_cone * (R_pipe * R_pipe + R_pipe * R_throat + R_throat * R_throat) +
           pi * R_throat * R_throat * L_throat;
  }
};

} // namespace

CaseInfo make_fda_nozzle_case() {
  CaseInfo c;
  c.name = "fda_nozzle";
  c.description = "FDA benchmark nozzle, sudden expansion, 3D (Wang, Haidn & Hu 2024, section "
                  "4.6; PIV of Hariharan et al. 2011)";
  c.schemes = {"wcsph_tvf"};
  c.params = {
      {"dx", ParamType::Real, 0.0004, "particle spacing (m; the throat is 4 mm across)", 5e-5,
       0.002},
      {"Re_throat", ParamType::Real, 500.0,
       "throat Reynolds number rho0 U_t D_t / mu (sets the flow rate)", 1.0, 1e4, true},
      {"upstream_length", ParamType::Real, 0.024, "inlet pipe before the cone (m)", 0.0, 1.0},
      {"downstream_length", ParamType::Real, 0.086, "outlet pipe after the sudden expansion (m)",
       0.005, 1.0},
      {"buffer_layers", ParamType::Int, std::int64_t{4},
       "slices of the inflow and outflow buffers (>= kernel support / dx)", 1.0, 100.0},
      {"ramp_time", ParamType::Real, 0.5, "smooth start of the inflow (s)", 0.0, 100.0},
      {"t_end", ParamType::Real, 2.0, "simulated time (s)", 0.0, 1e4, true},
      {"flux_window", ParamType::Real, 0.2,
       "the in/out flow rates are averaged over t >= t_end - flux_window (s)", 0.0, 1e4},
      {"speed_bound", ParamType::Real, 5.0,
       "diverged when max |u| exceeds this many times the throat's Poiseuille peak 2 U_t", 1.0,
       1e6},
  };
  add_loop_params(c.params); // output_interval (cases/loop_params.hpp)
  // The metrics of the default domain (a shorter one leaves out the stations, sections and planes
  // outside it).
  auto default_of = [&](const std::string& name) {
    for (const auto& spec : c.params)
      if (spec.name == name)
        return std::get<double>(spec.default_value);
    throw std::logic_error("fda_nozzle: no parameter " + name);
  };
  const double x_in0 = -(default_of("upstream_length") + L_cone + L_throat);
  const double x_out0 = default_of("downstream_length");
  for (const auto& st : fda_piv::centreline)
    if (st.z > x_in0 && st.z < x_out0)
      c.metrics.push_back({station_name("u_centre_at_z_", st.z),
                           "centreline axial velocity at this PIV station (m/s)"});
  std::vector<double> sections;
  for (const auto& q : fda_piv::profiles)
    if (q.z > x_in0 && q.z < x_out0 && (sections.empty() || sections.back() != q.z))
      sections.push_back(q.z);
  for (const double z : sections)
    c.metrics.push_back({station_name("profile_rms_err_at_z_", z),
                         "RMS over the PIV points of this section of (u_x - PIV) / U_t"});
  for (const double z : flux_planes(x_in0))
    c.metrics.push_back({station_name("flow_rate_rel_err_at_z_", z),
                         "volume flux through this plane (slab of 4 dx) / Q - 1"});
  c.metrics.insert(
      c.metrics.end(),
      {
          {"centreline_rms_err", "RMS over the PIV stations of (u_centre - PIV mean) / U_t"},
          {"centreline_max_err", "largest |u_centre - PIV mean| / U_t over the stations"},
          {"u_centre_throat", "centreline velocity at z = -0.008 m, the throat's last station"},
          {"u_centre_throat_rel_err", "u_centre_throat / PIV mean - 1"},
          {"profile_rms_err", "RMS of (u_x - PIV) / U_t over every section's points"},
          {"inflow_rate", "flow rate the inlet's rows impose at t_end (m^3/s)"},
          {"inflow_rate_rel_err", "inflow_rate / (Q f(t_end)) - 1"},
          {"flow_rate_in", "emitted volume per unit time over the flux window (m^3/s)"},
          {"flow_rate_out", "volume crossing the outlet per unit time over the window (m^3/s)"},
          {"flow_imbalance", "(flow_rate_in - flow_rate_out) / flow_rate_in"},
          {"flow_rate_in_rel_err", "flow_rate_in / Q - 1"},
          {"throat_volume", "initial fluid volume in the throat's slices (m^3)"},
          {"throat_volume_rel_err", "throat_volume / (pi R_t^2 L_t) - 1"},
          {"fluid_volume", "initial fluid volume in the lumen (m^3)"},
          {"fluid_volume_rel_err", "fluid_volume / the lumen's volume - 1"},
          {"n_fluid_0", "initial fluid particles"},
          {"ke", "kinetic energy of the fluid at t_end (J)"},
      });
  c.datasets = {{"centreline", "z (m), u (m/s): the centreline axial velocity on 401 points"}};
  c.size = [](const Params& prm) {
    const RunContext none;
    FdaNozzle n(prm, none);
    return size_flow_case<3>(n, prm, "wcsph_tvf");
  };
  c.run = [](const Params& prm, const RunContext& ctx) {
    FdaNozzle n(prm, ctx);
    return run_flow_case<3>(n, prm, ctx, "wcsph_tvf");
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_fda_nozzle_case()); // core/registry.hpp
} // namespace

} // namespace sph
