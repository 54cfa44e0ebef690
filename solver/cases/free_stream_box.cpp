// Case "free_stream_box": a uniform free stream through an empty 2D domain with open boundaries,
// run with the scheme "wcsph_tvf": the test bed of the open-boundary pieces
// (boundaries/open_boundary.hpp, boundaries/free_stream_domain.hpp; issue 19 section 1).
//
// Units: U = 1, rho0 = 1, length unit 1 (mu = rho0 U / Re), times in 1/U.
// Domain: fluid in [0, L] x [0, H] (domain_length, domain_height) on the cell-centred lattice of
// spacing dx, u = (U, 0) and rho = rho0 everywhere at t = 0; with perturb > 0 the initial fluid is
// shifted at random (the disturbance must leave through the open boundaries). Inflow: the emitter
// buffer of buffer_layers columns upstream of x = 0 moving at (U, 0) (density rho0, pressure 0, or
// with inlet_pressure = "extrapolated" the Shepard average of the fluid pressures around);
// outflow: the disposer buffer downstream of x = L (velocity and density frozen, pressure 0),
// deleted buffer_layers columns on; top and bottom: free surfaces with the Lagrangian free-stream
// boundary condition of Zhang et al. 2023 (surface indicator, near-surface density rule,
// velocity correction towards U), fluid beyond lateral_margin outside them deleted.
// The exact solution is the initial state: u = (U, 0), rho = rho0, p = 0 for all time, H / dx
// particles emitted and disposed per dx / U.
// Metrics (over the window t >= settle_fraction t_end, every advection step, fluid particles):
//   vel_err_max     max |u_i - (U, 0)| / U
//   vy_max          max |v_y,i| / U
//   rho_err_max     max |rho_i - rho0| / rho0
//   vel_err_rms_end, rho_err_rms_end  RMS over the fluid at t_end
//   n_fluid_0, n_fluid_min, n_fluid_max, n_fluid_band  ((max - min) / n_fluid_0 over the window)
//   n_total_band    the same for every particle (buffers included), over the initial total
//   flux_in, flux_out    emitted mass and mass crossing x = L per unit time over the window
//   flux_imbalance       (flux_in - flux_out) / flux_in
//   flux_in_rel_err      flux_in / (rho0 U H) - 1
//   mass_lost            fluid mass deleted beyond the lateral margin over the run
//   surface_fraction_end share of the fluid on the free surface at t_end
//   flow_throughs        t_end U / L
// Time loop: the shared one (cases/time_loop.hpp); the disposer and the emitter act before each
// step (then FlowScheme::particles_changed), the errors are measured after it. Checkpoints: the
// particles (count and kinds change), the masses and the window's extrema and counters
// (fsb/state); resumes bit for bit (tests/runner/test_checkpoint.cpp).
#include "boundaries/free_stream_domain.hpp"
#include "cases/case.hpp"
#include "cases/time_loop.hpp"
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "schemes/wcsph_tvf/wcsph_tvf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sph {
namespace {

using V2 = Vec<2>;

class FreeStreamBox final : public FlowCase<2> {
public:
  FreeStreamBox(const Params& prm, const RunContext&) : prm_(prm) {
    t_end_ = get_real(prm, "t_end");
    t_settle_ = get_real(prm, "settle_fraction") * t_end_;
    dx_ = get_real(prm, "dx");
    nx_ = static_cast<int>(std::lround(get_real(prm, "domain_length") / dx_));
    ny_ = static_cast<int>(std::lround(get_real(prm, "domain_height") / dx_));
    L_ = nx_ * dx_, H_ = ny_ * dx_;
  }

  Flow<2> build(Particles<2>& p) override {
    p_ = &p;
    open_boundary::FreeStreamDomain<2>::Config c;
    c.n = {nx_, ny_}, c.dx = dx_, c.rho0 = rho0;
    c.h = get_real(prm_, "h_over_dx") * dx_;
    c.layers = static_cast<int>(get_int(prm_, "buffer_layers"));
    c.lateral_margin = get_real(prm_, "lateral_margin");
    c.u_in = [](const V2&, double) { return V2(U, 0.0); };
    c.extrapolate_inlet_pressure = get_string(prm_, "inlet_pressure") == "extrapolated";
    dom_ = std::make_unique<open_boundary::FreeStreamDomain<2>>(c);
    dom_->fill(p, [](const V2&) { return true; });
    // The disturbed start: the initial fluid (not the inlet buffer) shifted at random.
    const double a = get_real(prm_, "perturb");
    UniformRandom rnd(static_cast<std::uint64_t>(get_int(prm_, "seed")));
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid && a > 0.0)
        for (int d = 0; d < 2; ++d)
          p.r[i][d] += (rnd() - 0.5) * a * dx_;
    Flow<2> f;
    dom_->attach(p, f);
    f.rho0 = rho0, f.U = U, f.L = 1.0, f.Re = get_real(prm_, "Re"), f.dx = dx_;
    n0_ = count_fluid();
    nt0_ = static_cast<double>(p.size());
    return f;
  }
  double t_end() const override { return t_end_; }
  double speed_bound() const override { return get_real(prm_, "speed_bound") * U; }

  void before_step(FlowScheme<2>& s, const LoopState& at) override {
    if (dom_->before_step(*p_, at.t + 0.5 * s.stable_dt()))
      s.particles_changed();
  }

  bool after_step(FlowScheme<2>&, const LoopState& at, const StepStats&) override {
    const Particles<2>& p = *p_;
    if (at.t < t_settle_)
      return false;
    if (!settled_) { // the window starts: the masses so far
      settled_ = true;
      m_in0_ = dom_->mass_in(), m_out0_ = dom_->mass_out(), t0_ = at.t;
      n_min_ = n_max_ = count_fluid();
      nt_min_ = nt_max_ = static_cast<double>(p.size());
    }
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.kind[i] != Kind::Fluid)
        continue;
      vel_err_max_ = std::max(vel_err_max_, (p.v[i] - V2(U, 0.0)).norm() / U);
      vy_max_ = std::max(vy_max_, std::abs(p.v[i][1]) / U);
      rho_err_max_ = std::max(rho_err_max_, std::abs(p.rho[i] - rho0) / rho0);
    }
    const double n = count_fluid(), nt = static_cast<double>(p.size());
    n_min_ = std::min(n_min_, n), n_max_ = std::max(n_max_, n);
    nt_min_ = std::min(nt_min_, nt), nt_max_ = std::max(nt_max_, nt);
    return false;
  }

  void finish(FlowScheme<2>&, const LoopState& at, RunResult& res) override {
    const Particles<2>& p = *p_;
    double e2 = 0.0, r2 = 0.0, nf = 0.0, ns = 0.0;
    const int ind = p.find_scalar("surface_indicator");
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid) {
        e2 += (p.v[i] - V2(U, 0.0)).squaredNorm(), r2 += std::pow(p.rho[i] - rho0, 2);
        nf += 1.0, ns += p.scalar(ind)[i] != 0.0;
      }
    res.add("vel_err_max", vel_err_max_);
    res.add("vy_max", vy_max_);
    res.add("rho_err_max", rho_err_max_);
    res.add("vel_err_rms_end", std::sqrt(e2 / nf) / U);
    res.add("rho_err_rms_end", std::sqrt(r2 / nf) / rho0);
    res.add("n_fluid_0", n0_);
    res.add("n_fluid_min", n_min_);
    res.add("n_fluid_max", n_max_);
    res.add("n_fluid_band", (n_max_ - n_min_) / n0_);
    res.add("n_total_band", (nt_max_ - nt_min_) / nt0_);
    const double T = at.t - t0_;
    if (settled_ && T > 0.0) {
      const double in = (dom_->mass_in() - m_in0_) / T, out = (dom_->mass_out() - m_out0_) / T;
      res.add("flux_in", in);
      res.add("flux_out", out);
      res.add("flux_imbalance", (in - out) / in);
      res.add("flux_in_rel_err", in / (rho0 * U * H_) - 1.0);
    }
    res.add("mass_lost", dom_->mass_lost());
    res.add("surface_fraction_end", ns / nf);
    res.add("flow_throughs", at.t * U / L_);
  }

  std::vector<std::string> state_names() const override {
    auto n = dom_->state_names("fsb");
    n.push_back("fsb/state");
    return n;
  }
  void save_state(StateArrays& out) const override {
    dom_->save_state(out, "fsb");
    out["fsb/state"] = {vel_err_max_, vy_max_, rho_err_max_,         n_min_,  n_max_, m_in0_,
                        m_out0_,      t0_,     settled_ ? 1.0 : 0.0, nt_min_, nt_max_};
  }
  void load_state(const StateArrays& in) override {
    dom_->load_state(in, "fsb");
    const auto& a = in.at("fsb/state");
    io::expect_state_size(a, 11, "free_stream_box: checkpoint array fsb/state");
    vel_err_max_ = a[0], vy_max_ = a[1], rho_err_max_ = a[2], n_min_ = a[3], n_max_ = a[4];
    m_in0_ = a[5], m_out0_ = a[6], t0_ = a[7], settled_ = a[8] != 0.0;
    nt_min_ = a[9], nt_max_ = a[10];
  }

private:
  static constexpr double U = 1.0, rho0 = 1.0;
  Params prm_;
  double t_end_ = 0.0, t_settle_ = 0.0, dx_ = 0.0, L_ = 0.0, H_ = 0.0;
  int nx_ = 0, ny_ = 0;
  Particles<2>* p_ = nullptr;
  std::unique_ptr<open_boundary::FreeStreamDomain<2>> dom_;
  double n0_ = 0.0, n_min_ = 0.0, n_max_ = 0.0, nt0_ = 0.0, nt_min_ = 0.0, nt_max_ = 0.0;
  double vel_err_max_ = 0.0, vy_max_ = 0.0, rho_err_max_ = 0.0;
  double m_in0_ = 0.0, m_out0_ = 0.0, t0_ = 0.0;
  bool settled_ = false;

  double count_fluid() const {
    double n = 0.0;
    for (const Kind k : p_->kind)
      n += k == Kind::Fluid;
    return n;
  }
};

} // namespace

static ParamSpec inlet_pressure_spec() {
  ParamSpec s{"inlet_pressure", ParamType::String, std::string("reference"),
              "pressure of the inlet buffer: reference (0, SPHinXsys' emitter) or extrapolated "
              "(Shepard average of the fluid pressures around)"};
  s.choices = {"reference", "extrapolated"};
  return s;
}

CaseInfo make_free_stream_box_case() {
  CaseInfo c;
  c.name = "free_stream_box";
  c.description = "uniform free stream through an empty 2D domain: emitter inflow, disposer "
                  "outflow, Lagrangian free-stream sides (Zhang et al. 2023, JCP 490, 112303)";
  c.schemes = {"wcsph_tvf"};
  c.params = {
      {"dx", ParamType::Real, 0.1, "particle spacing (length unit: the box's reference length)",
       1e-4, 1.0},
      {"domain_length", ParamType::Real, 4.0, "fluid domain length L (inlet to outlet)", 0.1, 1e4},
      {"domain_height", ParamType::Real, 2.0, "fluid domain height H", 0.1, 1e4},
      {"Re", ParamType::Real, 100.0, "Reynolds number U * 1 / nu", 0.0, 1e6, true},
      {"buffer_layers", ParamType::Int, std::int64_t{4},
       "lattice columns of the inflow and outflow buffers (>= kernel support / dx)", 1.0, 100.0},
      inlet_pressure_spec(),
      {"lateral_margin", ParamType::Real, 1.0,
       "fluid farther than this outside the top and bottom is deleted", 0.0, 1e4},
      {"perturb", ParamType::Real, 0.0,
       "initial fluid shifted at random by up to +-perturb/2 dx per coordinate (the inlet "
       "buffer stays a lattice)",
       0.0, 1.0},
      {"seed", ParamType::Int, std::int64_t{1}, "random seed of the perturbed start", 0.0, 1e9},
      {"t_end", ParamType::Real, 40.0, "simulated time in 1/U", 0.0, 1e6, true},
      {"settle_fraction", ParamType::Real, 0.0,
       "the error, count and flux window is t >= settle_fraction * t_end", 0.0, 0.99},
      {"speed_bound", ParamType::Real, 5.0, "diverged when max |u| exceeds this many U", 1.0, 1e6},
  };
  add_loop_params(c.params); // output_interval (cases/loop_params.hpp)
  c.size = [](const Params& prm) {
    const RunContext none;
    FreeStreamBox c(prm, none);
    return size_flow_case<2>(c, prm, "wcsph_tvf");
  };
  c.run = [](const Params& prm, const RunContext& ctx) {
    FreeStreamBox b(prm, ctx);
    return run_flow_case<2>(b, prm, ctx, "wcsph_tvf");
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_free_stream_box_case()); // core/registry.hpp
} // namespace

} // namespace sph
