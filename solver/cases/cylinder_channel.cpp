// Case "cylinder_channel": 2D flow past a circular cylinder in a channel (seed 004, Kolukisa,
// Ozbulut & Yildiz 2021, section 3 and Figure 1), run with the ALSPH scheme (schemes/alsph).
//
// Units: D = 1, U = 1, rho = 1, nu = 1 / Re; times in D/U.
// Geometry: channel [0, L] x [0, H], L = channel_length D (14), H = channel_height D (13),
// cylinder centre (upstream_length D, H/2) (L_U = 4 D). Fluid starts on a Cartesian lattice of
// spacing dx = D / D_over_dx with u = (U, 0), p = 0, outside the cylinder.
// Boundaries:
//   top/bottom  free-slip mirror ghosts (Figure 2), regenerated every step within one support;
//   inlet       buffer zone x in [-L_b, 0) of L_b >= 6h (whole lattice columns) moving at U; a
//               buffer particle crossing x = 0 becomes fluid and a new one enters at x - L_b;
//               buffer pressure = Shepard average of the neighbouring fluid pressures;
//   outlet      fluid crossing x = L becomes outlet buffer: velocity frozen (its normal component
//               preserved) until it leaves x = L + L_b; buffer pressure p = 0 (reference);
//   cylinder    fixed particles on radial rings at spacing dx (radii R - (k + 1/2) dx, ring k with
//               round(2 pi r_k / dx) particles) down to two kernel supports deep (the rings a
//               fluid particle sees then have complete supports, so their V_i = 1/sum W is right;
//               deeper particles never meet fluid), u = 0, pressure from eq. (20)
//               (see schemes/alsph/alsph.hpp).
// Forces (section 3): the fluid's force on the cylinder, the reaction of the fluid-body pair forces
// (the scheme's force_on_walls, schemes/alsph/alsph.cpp), which needs no pressures deeper inside
// the cylinder than one support.
// C_D = 2 F_x / (rho U^2 D), C_L = 2 F_y / (rho U^2 D); C_p(theta) = 2 (p - p_0) / (rho U^2) on the
// outer cylinder ring, theta from the upstream stagnation point, counter-clockwise,
// p_0 = mean pressure of the fluid with x < D/2 (the "instantaneous mean inlet pressure").
//
// Symmetry breaking: the set-up is mirror-symmetric about y = H/2 and the solver keeps that
// symmetry to round-off, so shedding would start only after O(100) D/U; the initial fluid velocity
// gets a transverse component perturbation * U * exp(-|x - x_c - (D, 0)|^2 / D^2) (parameter
// `perturbation`, default 0.05; 0 for the symmetric start). The periodic state does not depend on
// it; only the onset time does.
// Start: impulsive by default (u = U everywhere at t = 0, also next to the no-slip cylinder); with
// `ramp_time` T > 0 the fluid starts at rest and the inlet velocity rises as
// U_in(t) = U (1 - cos(pi t / T)) / 2 for t < T, the fluid driven by the uniform body force
// dU_in/dt (an incompressible channel accelerates as a whole: without it the inlet buffer runs
// into resting fluid and piles up). The nudge is added as before.
// Metrics (averages over t >= settle_fraction t_end): cd_mean (eq. 21), cl_rms (eq. 23), St = f D/U
// of C_L (zero crossings; st_cycles periods; St_spectral from the periodogram peak), cd_amplitude,
// cl_amplitude (half peak-to-peak), div_mean (mean over steps of the mean |div u| over fluid),
// div_max_mean, iterations_mean, converged_fraction (steps meeting eq. 13 before max_iterations),
// t_diverged (only for a diverged run), costs: wall_s, cpu_s (process CPU), steps, n_particles
// (the largest count, ghosts and buffers included),
// and per particle in CPU microseconds: iteration_cpu_us_per_particle (one inner iteration),
// search_cpu_us_per_particle (a fresh neighbour search: cells, pairs, kernel values, V, Gamma),
// search_over_iteration (their ratio), refresh_cpu_us_per_particle (algorithm 1's per-iteration
// pair refresh, included in the iteration), shifting_cpu_us_per_particle, cpu_us_per_particle_step
// (everything).
// Averages: when the lift after t_settle holds >= 2 whole periods (upward zero crossings), cd_mean,
// cl_rms, the amplitudes are taken over exactly those periods (t_average = their length).
// St is recorded only when at least one period was found; st_period_cv is the spread of the
// periods relative to their mean (small for periodic shedding).
// HDF5 (<output_dir>/cylinder_channel.h5): series/{t,cd,cl,div_mean,div_max,iterations}, one
// sample per `sample_interval` (mean of the steps in the interval),
// cp/{theta,cp_mean}.
// Runs on the shared time loop (cases/time_loop.hpp) with scheme alsph: the top and bottom walls
// are Flow::slip_walls (the scheme's mirror ghosts, regenerated every step), the buffer pressure
// is Flow::buffer_pressure, outflow, inflow and the smooth start's drive are before_step, forces
// and series after_step. Checkpoints: the particles as they end a step (their count changes:
// inflow, outflow, ghosts), the series, the averaging sums, the scheme's timers and counters. A
// resumed job continues bit for bit (tested).
#include "boundaries/open_boundary.hpp"
#include "cases/loop_params.hpp"
#include "cases/shedding.hpp"
#include "cases/time_loop.hpp"
#include "core/kernels/quintic_spline.hpp"
#include "io/hdf5.hpp"
#include "io/job_attributes.hpp"
#include "operators/interact.hpp"
#include "schemes/alsph/scheme_info.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <stdexcept>

namespace sph {
namespace {

constexpr int D = 2;
using V2 = Vec<2>;

class CylinderChannelCase final : public FlowCase<2> {
public:
  CylinderChannelCase(const Params& prm, const RunContext& ctx) : prm_(prm), ctx_(ctx) {
    Re_ = get_real(prm, "Re");
    dx_ = 1.0 / get_real(prm, "D_over_dx");
    h_ = alsph::smoothing_length(prm, dx_);
    dt_ = get_real(prm, "dt_star") * dx_; // dt U / dx, U = 1
    t_end_ = get_real(prm, "t_end");
    t_settle_ = get_real(prm, "settle_fraction") * t_end_;
    ramp_time_ = get_real(prm, "ramp_time");
    nx_ = static_cast<int>(std::lround(get_real(prm, "channel_length") / dx_));
    ny_ = static_cast<int>(std::lround(get_real(prm, "channel_height") / dx_));
    L_ = nx_ * dx_, H_ = ny_ * dx_;
    c_ = V2(get_real(prm, "upstream_length"), 0.5 * H_);
    support_ = QuinticSpline<D>(h_).support();
    nb_ = static_cast<int>(std::ceil(6.0 * h_ / dx_ - 1e-9));
    Lb_ = nb_ * dx_;
    if (c_[0] - R < 2.0 * support_ || c_[0] + R > L_ - 2.0 * support_ ||
        R + 2 * support_ > 0.5 * H_)
      throw std::invalid_argument("cylinder_channel: the cylinder must lie two supports inside");
    sample_interval_ = std::max(get_real(prm, "sample_interval"), dt_);
    next_sample_ = sample_interval_;
  }

  Flow<2> build(Particles<2>& p) override {
    p_ = &p;
    const double perturbation = get_real(prm_, "perturbation");
    normal_ = p.add_vector("normal");
    // Body rings, outer ring first: its particles are ids [0, n_ring0).
    for (int k = 0;; ++k) {
      const double rk = R - (k + 0.5) * dx_;
      if (rk <= 0.25 * dx_ || (k + 0.5) * dx_ > 2.0 * support_)
        break;
      const int n = std::max(1, static_cast<int>(std::lround(2.0 * std::numbers::pi * rk / dx_)));
      for (int a = 0; a < n; ++a) {
        const double th = (a + 0.5) * 2.0 * std::numbers::pi / n; // from the upstream point
        const V2 nrm(-std::cos(th), std::sin(th));
        const std::size_t i = add(c_ + rk * nrm, Kind::Body, V2::Zero());
        p.vector(normal_)[i] = nrm;
        if (k == 0)
          theta0_.push_back(th);
      }
    }
    for (int j = 0; j < ny_; ++j) {
      for (int i = -nb_; i < nx_; ++i) {
        const V2 x((i + 0.5) * dx_, (j + 0.5) * dx_);
        if ((x - c_).norm() < R)
          continue;
        // Symmetry breaking (see header): a transverse nudge centred one D behind the cylinder.
        const V2 w = x - c_ - V2(1.0, 0.0);
        add(x, i < 0 ? Kind::Buffer : Kind::Fluid,
            V2(inflow_speed(0.0), i < 0 ? 0.0 : perturbation * U * std::exp(-w.squaredNorm())));
      }
    }
    cp_sum_.assign(theta0_.size(), 0.0);

    Flow<2> flow; // the box is not periodic: the cell list follows the particles
    flow.rho0 = rho, flow.U = U, flow.L = 1.0, flow.Re = Re_, flow.dx = dx_, flow.dt = dt_;
    flow.normal = normal_;
    flow.slip_walls = {SlipWall{1, 0.0, +1}, SlipWall{1, H_, -1}}; // bottom, top
    // Buffer pressure (boundaries/open_boundary.hpp): inlet (x < 0) the Shepard average of the
    // fluid neighbours' pressures; outlet p = 0.
    flow.buffer_pressure = [](Particles<2>& q, const NeighborList<2>& list) {
      auto inlet = [&](std::size_t i) { return q.r[i][0] < 0.0; };
      open_boundary::BufferPressure<D, decltype(inlet)> op{q.kind, q.p, inlet, 0.0};
      interact(list, op, [&](std::size_t i) { return q.kind[i] == Kind::Buffer; });
    };
    return flow;
  }
  double t_end() const override { return t_end_; }
  double speed_bound() const override { return get_real(prm_, "speed_bound") * U; }

  // Outflow, inflow and the smooth start's drive.
  void before_step(FlowScheme<2>& s, const LoopState& at) override {
    Particles<2>& p = *p_;
    const double t = at.t;
    // Particles that left the outlet buffer.
    keep_.assign(p.size(), 1);
    bool any = false;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.r[i][0] >= L_ + Lb_)
        keep_[i] = 0, any = true;
    if (any)
      p.keep_only(keep_);
    // Inlet: buffer particles crossing x = 0 become fluid, a new one enters L_b upstream.
    // Outlet: fluid crossing x = L becomes buffer (velocity frozen from now on).
    const std::size_t n0 = p.size();
    for (std::size_t i = 0; i < n0; ++i) {
      if (p.kind[i] == Kind::Buffer && p.r[i][0] >= 0.0 && p.r[i][0] < 0.5 * L_) {
        p.kind[i] = Kind::Fluid;
        const std::size_t k =
            add(V2(p.r[i][0] - Lb_, p.r[i][1]), Kind::Buffer, V2(inflow_speed(t + dt_), 0.0));
        p.p[k] = p.p[i];
      } else if (p.kind[i] == Kind::Fluid && p.r[i][0] >= L_) {
        p.kind[i] = Kind::Buffer;
      }
    }
    if (t < ramp_time_) // smooth start: the inlet buffer moves at this step's inflow speed
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Buffer && p.r[i][0] < 0.0)
          p.v[i] = V2(inflow_speed(t + dt_), 0.0);
    // Smooth start: the whole channel accelerates with the inlet (a uniform body force equal to
    // the inflow's acceleration at mid-step; the cylinder feels it through the pressure).
    s.set_body_acceleration(t < ramp_time_
                                ? V2(0.5 * U * std::numbers::pi / ramp_time_ *
                                         std::sin(std::numbers::pi * (t + 0.5 * dt_) / ramp_time_),
                                     0.0)
                                : V2::Zero());
  }

  // Forces, pressure coefficient, series; diverged on NaN, a particle out of the channel or a
  // force that is not finite.
  bool after_step(FlowScheme<2>& s, const LoopState& at, const StepStats&) override {
    const Particles<2>& p = *p_;
    const double t = at.t;
    const V2 F = s.force_on_walls();
    double div_mean = 0.0, div_max = 0.0, iterations = 0.0;
    for (const auto& [name, value] : s.probes())
      (name == "div_mean" ? div_mean : name == "div_max" ? div_max : iterations) = value;
    double p0 = 0.0;
    long n_in = 0;
    bool bad = false;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.kind[i] != Kind::Fluid)
        continue;
      if (p.r[i][0] < 0.5)
        p0 += p.p[i], ++n_in;
      if (!std::isfinite(p.p[i]) || !std::isfinite(p.v[i][0]) || !std::isfinite(p.v[i][1]) ||
          std::abs(p.r[i][1] - 0.5 * H_) > 0.5 * H_ + support_ || p.r[i][0] < -Lb_ - support_)
        bad = true;
    }
    p0 = n_in ? p0 / n_in : 0.0;
    const double q = 0.5 * rho * U * U * 1.0;
    bin_.t += t, bin_.cd += F[0] / q, bin_.cl += F[1] / q, bin_.div += div_mean;
    bin_.divmax += div_max, bin_.it += iterations, ++bin_.n;
    if (t >= next_sample_ - 1e-9 * dt_ || s.finished(t, t_end_)) {
      flush_bin();
      while (next_sample_ <= t + 1e-9 * dt_)
        next_sample_ += sample_interval_;
    }
    if (t >= t_settle_) {
      div_sum_ += div_mean, divmax_sum_ += div_max, ++settled_steps_;
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Body && static_cast<std::size_t>(p.id[i]) < theta0_.size())
          cp_sum_[p.id[i]] += dt_ * (p.p[i] - p0) / q;
      cp_time_ += dt_;
    }
    if (bad)
      throw std::runtime_error("NaN or particle out of the channel");
    if (!std::isfinite(F[0]) || !std::isfinite(F[1]))
      throw std::runtime_error("force not finite");
    return false;
  }

  void finish(FlowScheme<2>&, const LoopState& at, RunResult& res) override {
    if (bin_.n > 0)
      flush_bin();
    const double t_avg = averaging_start();
    // Shedding frequency and force coefficients after the settling time (cases/shedding.hpp).
    const AveragingWindow w = add_shedding_metrics(ts_, cds_, cls_, t_avg, 1.0 / U, res);
    // Mean over the steps after the settling time of the mean |div u| over the fluid (section 3).
    if (settled_steps_ > 0) {
      res.add("div_mean", div_sum_ / settled_steps_);
      res.add("div_max_mean", divmax_sum_ / settled_steps_);
    }
    res.add("t_average", w.whole_periods ? w.t1 - w.t0 : at.t - w.t0);
    common_metrics(at, res);
    write_h5("done");
  }
  // Flow metrics only for a run that reached t_end: averages over a blow-up mean nothing.
  void diverged(FlowScheme<2>&, const LoopState& at, RunResult& res) override {
    if (bin_.n > 0) // the partial interval
      flush_bin();
    res.add("t_diverged", at.t);
    common_metrics(at, res);
    write_h5("diverged");
  }

  std::vector<std::string> state_names() const override {
    std::vector<std::string> n;
    for (const char* k : series_names)
      n.push_back(std::string("cylinder_channel/series/") + k);
    n.push_back("cylinder_channel/cp_sum");
    n.push_back("cylinder_channel/sums");
    return n;
  }
  void save_state(StateArrays& out) const override {
    const auto ser = series();
    for (std::size_t k = 0; k < ser.size(); ++k)
      out[std::string("cylinder_channel/series/") + series_names[k]] = *ser[k];
    out["cylinder_channel/cp_sum"] = cp_sum_;
    out["cylinder_channel/sums"] = {bin_.t,
                                    bin_.cd,
                                    bin_.cl,
                                    bin_.div,
                                    bin_.divmax,
                                    bin_.it,
                                    static_cast<double>(bin_.n),
                                    next_sample_,
                                    div_sum_,
                                    divmax_sum_,
                                    static_cast<double>(settled_steps_),
                                    cp_time_,
                                    static_cast<double>(next_id_)};
  }
  void load_state(const StateArrays& in) override {
    const auto ser = series();
    for (std::size_t k = 0; k < ser.size(); ++k)
      *ser[k] = in.at(std::string("cylinder_channel/series/") + series_names[k]);
    cp_sum_ = in.at("cylinder_channel/cp_sum");
    const auto& a = in.at("cylinder_channel/sums");
    io::expect_state_size(a, 13, "cylinder_channel: checkpoint array cylinder_channel/sums");
    bin_ = Bin{a[0], a[1], a[2], a[3], a[4], a[5], static_cast<int>(a[6])};
    next_sample_ = a[7], div_sum_ = a[8], divmax_sum_ = a[9];
    settled_steps_ = static_cast<long>(a[10]), cp_time_ = a[11];
    next_id_ = static_cast<std::int64_t>(a[12]);
  }

private:
  static constexpr double R = 0.5, U = 1.0, rho = 1.0; // D = 1
  static constexpr const char* series_names[6] = {"t",        "cd",      "cl",
                                                  "div_mean", "div_max", "iterations"};
  Params prm_;
  RunContext ctx_;
  double Re_ = 0.0, dx_ = 0.0, h_ = 0.0, dt_ = 0.0, t_end_ = 0.0, t_settle_ = 0.0;
  double ramp_time_ = 0.0, L_ = 0.0, H_ = 0.0, support_ = 0.0, Lb_ = 0.0;
  int nx_ = 0, ny_ = 0, nb_ = 0, normal_ = -1;
  V2 c_ = V2::Zero();
  Particles<2>* p_ = nullptr;
  std::int64_t next_id_ = 0;
  std::vector<double> theta0_;
  std::vector<char> keep_;

  // Time series, one sample per sample_interval: each sample is the mean over the steps of its
  // interval (a box filter: the step-to-step force noise of SPH averages out instead of aliasing).
  std::vector<double> ts_, cds_, cls_, divs_, divmax_, iters_;
  struct Bin {
    double t = 0, cd = 0, cl = 0, div = 0, divmax = 0, it = 0;
    int n = 0;
  } bin_;
  double sample_interval_ = 0.0, next_sample_ = 0.0;
  // Per-step sums after the settling time (div_mean, div_max_mean average every step).
  double div_sum_ = 0.0, divmax_sum_ = 0.0, cp_time_ = 0.0;
  long settled_steps_ = 0;
  std::vector<double> cp_sum_;

  std::array<const std::vector<double>*, 6> series() const {
    return {&ts_, &cds_, &cls_, &divs_, &divmax_, &iters_};
  }
  std::array<std::vector<double>*, 6> series() {
    return {&ts_, &cds_, &cls_, &divs_, &divmax_, &iters_};
  }
  double inflow_speed(double time) const {
    return time < ramp_time_ ? 0.5 * U * (1.0 - std::cos(std::numbers::pi * time / ramp_time_)) : U;
  }
  std::size_t add(const V2& x, Kind k, const V2& v) {
    const std::size_t i = p_->add(x, rho * dx_ * dx_, rho, k);
    p_->v[i] = v;
    p_->id[i] = next_id_++;
    return i;
  }
  void flush_bin() {
    const double w = 1.0 / bin_.n;
    ts_.push_back(bin_.t * w), cds_.push_back(bin_.cd * w), cls_.push_back(bin_.cl * w);
    divs_.push_back(bin_.div * w), divmax_.push_back(bin_.divmax * w);
    iters_.push_back(bin_.it * w);
    bin_ = Bin{};
  }
  double averaging_start() const { return std::min(t_settle_, ts_.empty() ? 0.0 : ts_.back()); }
  void common_metrics(const LoopState& at, RunResult& res) const {
    res.add("wall_s", at.wall_s);
    res.add("t_end_reached", at.t);
    res.add("dt", dt_);
  }
  void write_h5(const char* status) const {
    if (ctx_.output_dir.empty())
      return;
    std::filesystem::create_directories(ctx_.output_dir);
    io::H5Writer w(ctx_.output_dir / "cylinder_channel.h5");
    w.write_columns("series", {"t", "cd", "cl", "div_mean", "div_max", "iterations"},
                    {ts_, cds_, cls_, divs_, divmax_, iters_});
    std::vector<double> cp_mean(theta0_.size(), 0.0);
    for (std::size_t k = 0; k < theta0_.size(); ++k)
      cp_mean[k] = cp_time_ > 0 ? cp_sum_[k] / cp_time_ : 0.0;
    w.write("cp/theta", theta0_);
    w.write("cp/cp_mean", cp_mean);
    io::write_job_attributes(w, "cylinder_channel", prm_, ctx_.job_key); // typed, job key
    w.attribute("t_settle", averaging_start());
    w.attribute("status", status);
    w.close();
  }
};

RunResult run_cylinder_channel(const Params& prm, const RunContext& ctx) {
  CylinderChannelCase c(prm, ctx);
  return run_flow_case<2>(c, prm, ctx, "alsph");
}

} // namespace

CaseInfo make_cylinder_channel_case() {
  CaseInfo c;
  c.name = "cylinder_channel";
  c.description = "2D flow past a cylinder in a channel, C_D, C_L, St (Kolukisa, Ozbulut & "
                  "Yildiz 2021, Symmetry 13:472, section 3)";
  c.schemes = {"alsph"};
  c.params = {
      {"Re", ParamType::Real, 200.0, "Reynolds number U D / nu", 0.0, 1e5, true},
      {"D_over_dx", ParamType::Real, 20.0, "particles per cylinder diameter D / dx", 4.0, 400.0},
      {"dt_star", ParamType::Real, 5.08e-3, "dimensionless time step dt U / dx", 0.0, 10.0, true},
      {"t_end", ParamType::Real, 100.0, "simulated time in D / U", 0.0, 1e5, true},
      {"settle_fraction", ParamType::Real, 0.5, "averages and St use t >= settle_fraction * t_end",
       0.0, 0.99},
      {"channel_length", ParamType::Real, 14.0, "channel length L in D", 2.0, 1000.0},
      {"channel_height", ParamType::Real, 13.0, "channel height H in D", 2.0, 1000.0},
      {"upstream_length", ParamType::Real, 4.0, "cylinder centre to inlet L_U in D", 1.0, 1000.0},
      {"h_over_dx", ParamType::Real, 1.2, "smoothing length h / dx (quintic kernel, support 3h)",
       0.5, 3.0},
      {"perturbation", ParamType::Real, 0.05,
       "initial transverse velocity nudge behind the cylinder, in U (breaks the symmetry)", 0.0,
       1.0},
      {"ramp_time", ParamType::Real, 0.0,
       "smooth start: fluid at rest, inlet speed U (1 - cos(pi t / T)) / 2 up to T (in D/U; 0: "
       "impulsive start, u = U everywhere)",
       0.0, 1e4},
      {"speed_bound", ParamType::Real, 10.0, "diverged when max |u| exceeds this many U", 1.0, 1e6},
      {"sample_interval", ParamType::Real, 0.02,
       "time series sample interval in D/U (each sample averages the steps of its interval)", 0.0,
       1e3},
  };
  add_loop_params(c.params); // output_interval (cases/loop_params.hpp)
  c.run = [](const Params& prm, const RunContext& ctx) { return run_cylinder_channel(prm, ctx); };
  c.size = [](const Params& prm) {
    const RunContext none;
    CylinderChannelCase c(prm, none);
    return size_flow_case<2>(c, prm, "alsph");
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_cylinder_channel_case()); // core/registry.hpp
} // namespace

} // namespace sph
