// Case "spreading_drop": a cylindrical (2D) drop spreading on a rigid floor under gravity, without
// surface tension, run with scheme "contact" with and without the numerical-viscosity correction
// zeta: seed 003 (Parshikov et al.) section 5.6 and Fig. 12, where it is qualitative ("the less
// viscous droplet spreads faster"); here it is also a viscometer, read from the late spreading
// rate with the similarity solution of a viscous gravity current (diagnostics/gravity_current.hpp,
// Huppert 1982).
//
// Set-up: a disc of radius R = R_over_D0 D0 on a square lattice of spacing D0 (the paper's
// particle size D = 1e-8 m is the default), at rest, touching a no-slip floor at y = 0 (Wall
// particles at rest, a layer one search radius thick, |x| < floor_half_width R). The paper gives
// neither R nor g, and real gravity would make nothing move in the time an acoustic step allows at
// this size; so g is set by a gravitational Reynolds number Re_g = U_g R / nu (nu = eta / rho0,
// the physical viscosity) with U_g = sqrt(g R): g = (Re_g nu / R)^2 / R, time unit t_g = R / U_g.
// With the default water at D0 = 10 nm the numerical viscosity (eq. 37: 1.33 mPa s, about 1.6 in
// 2D) is about that of water (1.0 mPa s), the paper's point of choosing this size.
//
// Measurement, every sample_interval t_g:
//   half width a(t) = (max_i x_i - min_i x_i) / 2 + D0 / 2 over the fluid, height (max_i y_i +
//   D0 / 2); both in R into the HDF5 series and the metrics half_width_over_R (at t_end and at
//   t_end / 2: half_width_over_R_mid) and height_over_R.
//   The viscometer: a least-squares line through a^5 against t over [fit_from t_end, t_end]; its
//   slope is (10/9) (Q/B)^3 g / nu_eff by the thin-film similarity solution (gravity_current.hpp,
//   eq. 1), Q = the drop's area (N_fluid D0^2). Metrics: eta_spread = rho0 nu_eff (Pa s),
//   eta_spread_over_eta, eta_model = eta + (1 - zeta) eta_num_ref (what the correction aims at),
//   eta_num_ref (eq. 37 or the given eta_num), fit_r2, fit_points. The solution holds only for a
//   thin (height << a), slow current: aspect_end = height / a and Re_front_end =
//   (da/dt) height / nu_eff at t_end say how far the run is from it.
// Cost (besides the time loop's): wall_s, n_fluid, n_solid. Divergence: a density deviation
// above 10 % or a speed above 100 U_g.
// HDF5 (<output_dir>/spreading_drop.h5): series/{t, t_over_tg, half_width_over_R, height_over_R},
// the job's parameters, the fluid fields at t_end. Checkpoints carry the series.
#include "cases/loop_params.hpp"
#include "cases/materials.hpp"
#include "cases/time_loop.hpp"
#include "core/lattice.hpp"
#include "diagnostics/gravity_current.hpp"
#include "io/job_attributes.hpp"
#include "io/particle_fields.hpp"
#include "schemes/contact/scheme_info.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sph {

namespace {

class SpreadingDropCase final : public FlowCase<2> {
public:
  SpreadingDropCase(const Params& prm, const RunContext& ctx) : prm_(prm), ctx_(ctx) {
    const Material& mat = material_or_throw(get_string(prm, "material"), "spreading_drop");
    rho0_ = mat.rho0, c0_ = mat.c0;
    eta_ = liquid_viscosity(get_real(prm, "eta"), mat, "spreading_drop");
    D0_ = get_real(prm, "D0");
    n_R_ = static_cast<int>(get_int(prm, "R_over_D0"));
    R_ = n_R_ * D0_;
    const double nu = eta_ / rho0_;
    U_g_ = get_real(prm, "Re_g") * nu / R_;
    g_ = U_g_ * U_g_ / R_;
    t_g_ = R_ / U_g_;
    t_end_ = get_real(prm, "t_end_g") * t_g_;
    dt_sample_ = get_real(prm, "sample_interval") * t_g_;
    fit_from_ = get_real(prm, "fit_from");
  }

  Flow<2> build(Particles<2>& p) override {
    p_ = &p;
    const double Rs = contact::search_radius(prm_, 1.05 * D0_);
    const contact::Fields f = contact::Fields::add_to(p);
    const int n_floor = static_cast<int>(std::ceil(1.05 * Rs / D0_));
    const int half = static_cast<int>(std::ceil(get_real(prm_, "floor_half_width") * n_R_));
    x_edge_ = half * D0_;
    auto add = [&](const Vec<2>& x, Kind k) {
      const std::size_t i = p.add(x, rho0_ * D0_ * D0_, rho0_, k);
      p.scalar(f.rho0)[i] = rho0_;
      p.scalar(f.c0)[i] = c0_;
      p.scalar(f.eta)[i] = eta_;
    };
    for_each_lattice_point<2>({-half, -n_floor}, {half, 0}, D0_,
                              [&](const Vec<2>& x, const auto&) { add(x, Kind::Wall); });
    const Vec<2> centre(0.0, R_);
    for_each_lattice_point<2>({-n_R_ - 1, 0}, {n_R_ + 1, 2 * n_R_ + 1}, D0_,
                              [&](const Vec<2>& x, const auto&) {
                                if ((x - centre).norm() < R_)
                                  add(x, Kind::Fluid), ++n_fluid_;
                              });
    n_solid_ = p.size() - n_fluid_;
    Q_ = n_fluid_ * D0_ * D0_;

    Flow<2> flow;
    flow.box.lo = Vec<2>(-x_edge_, -n_floor * D0_);
    flow.box.hi = Vec<2>(x_edge_, 2.0 * R_ + D0_);
    flow.box.periodic = {false, false};
    flow.rho0 = rho0_, flow.dx = D0_, flow.L = R_, flow.U = U_g_;
    return flow;
  }
  void start(FlowScheme<2>& s) override {
    s.set_body_acceleration(Vec<2>(0.0, -g_));
    sample(0.0);
  }
  double t_end() const override { return t_end_; }
  double speed_bound() const override { return 100.0 * U_g_; }

  bool after_step(FlowScheme<2>&, const LoopState& at, const StepStats&) override {
    if (at.steps % 100 == 0)
      contact::check_density_deviation(*p_, max_drho_, 0.1, at.steps);
    if (at.t >= static_cast<double>(ts_.size()) * dt_sample_ * (1.0 - 1e-12))
      sample(at.t); // the last sample, at t_end, is finish()'s
    return false;
  }

  void finish(FlowScheme<2>&, const LoopState& at, RunResult& res) override {
    if (ts_.empty() || ts_.back() < at.t * (1.0 - 1e-12))
      sample(at.t);
    const double a_end = a_.back(), h_end = h_.back();
    res.add("half_width_over_R", a_end / R_);
    res.add("height_over_R", h_end / R_);
    res.add("half_width_over_R_mid", value_at(a_, 0.5 * at.t) / R_);
    // The viscometer: a^5 against t over the fit window.
    std::vector<double> a5(a_.size());
    for (std::size_t k = 0; k < a_.size(); ++k)
      a5[k] = std::pow(a_[k], 5);
    const LineFit fit = fit_line(ts_, a5, fit_from_ * at.t);
    const contact::Options o = contact::options_from(prm_);
    const double eta_num = contact::eta_num_of(o, D0_, rho0_ * c0_);
    res.add("eta_phys", eta_);
    res.add("eta_num_ref", eta_num);
    res.add("eta_model", eta_ + (1.0 - o.zeta) * eta_num);
    res.add("fit_points", static_cast<double>(fit.n));
    if (fit.n >= 3 && fit.b > 0.0) {
      const double nu_eff = gravity_current_viscosity(Q_, g_, fit.b);
      res.add("eta_spread", rho0_ * nu_eff);
      res.add("eta_spread_over_eta", rho0_ * nu_eff / eta_);
      res.add("fit_r2", fit.r2);
      const double da_dt = fit.b / (5.0 * std::pow(a_end, 4));
      res.add("Re_front_end", da_dt * h_end / nu_eff);
    }
    res.add("aspect_end", h_end / a_end);
    res.add("g", g_);
    res.add("t_g", t_g_);
    res.add("U_g", U_g_);
    res.add("t_end", t_end_);
    res.add("max_density_dev", max_drho_);
    res.add("reached_floor_edge", a_end + 2.0 * D0_ >= x_edge_ ? 1.0 : 0.0);
    res.add("wall_s", at.wall_s);
    res.add("n_fluid", static_cast<double>(n_fluid_));
    res.add("n_solid", static_cast<double>(n_solid_));

    if (auto h5 = io::open_job_output(ctx_, "spreading_drop", prm_)) {
      std::vector<double> tt(ts_.size()), aa(a_.size()), hh(h_.size());
      for (std::size_t k = 0; k < ts_.size(); ++k)
        tt[k] = ts_[k] / t_g_, aa[k] = a_[k] / R_, hh[k] = h_[k] / R_;
      h5->write_columns("series", {"t", "t_over_tg", "half_width_over_R", "height_over_R"},
                        {ts_, tt, aa, hh});
      io::write_fluid_fields(*h5, *p_);
      h5->close();
    }
  }

  std::vector<std::string> state_names() const override {
    return {"drop/t", "drop/a", "drop/h", "drop/misc"};
  }
  void save_state(StateArrays& out) const override {
    out["drop/t"] = ts_, out["drop/a"] = a_, out["drop/h"] = h_;
    out["drop/misc"] = {max_drho_};
  }
  void load_state(const StateArrays& in) override {
    ts_ = in.at("drop/t"), a_ = in.at("drop/a"), h_ = in.at("drop/h");
    const auto& m = in.at("drop/misc");
    io::expect_state_size(m, 1, "spreading_drop: checkpoint array drop/misc");
    if (a_.size() != ts_.size() || h_.size() != ts_.size())
      throw std::runtime_error("spreading_drop: checkpoint series of different lengths");
    max_drho_ = m[0];
  }

private:
  Params prm_;
  RunContext ctx_;
  Particles<2>* p_ = nullptr;
  double rho0_ = 0.0, c0_ = 0.0, eta_ = 0.0, D0_ = 0.0, R_ = 0.0, U_g_ = 0.0, g_ = 0.0;
  double t_g_ = 0.0, t_end_ = 0.0, dt_sample_ = 0.0, fit_from_ = 0.5, x_edge_ = 0.0, Q_ = 0.0;
  double max_drho_ = 0.0;
  int n_R_ = 0;
  std::size_t n_fluid_ = 0, n_solid_ = 0;
  std::vector<double> ts_, a_, h_;

  void sample(double t) {
    double xl = std::numeric_limits<double>::max(), xr = -xl, yt = -xl;
    for (std::size_t i = 0; i < p_->size(); ++i)
      if (p_->kind[i] == Kind::Fluid) {
        xl = std::min(xl, p_->r[i][0]), xr = std::max(xr, p_->r[i][0]);
        yt = std::max(yt, p_->r[i][1]);
      }
    ts_.push_back(t);
    a_.push_back(0.5 * (xr - xl) + 0.5 * D0_);
    h_.push_back(yt + 0.5 * D0_);
  }
  // The sample of series f at the first sample time >= t.
  double value_at(const std::vector<double>& f, double t) const {
    for (std::size_t k = 0; k < ts_.size(); ++k)
      if (ts_[k] >= t * (1.0 - 1e-12))
        return f[k];
    return f.back();
  }
};

RunResult run_spreading_drop(const Params& prm, const RunContext& ctx) {
  SpreadingDropCase c(prm, ctx);
  return run_flow_case<2>(c, prm, ctx, "contact");
}

} // namespace

CaseInfo make_spreading_drop_case() {
  CaseInfo c;
  c.name = "spreading_drop";
  c.description =
      "2D drop spreading on a no-slip floor under gravity, contact SPH with and "
      "without zeta (Parshikov et al. 2023, 5.6, Fig. 12); a viscometer by Huppert's (1982) "
      "similarity solution";
  c.schemes = {"contact"};
  c.params = {
      {"material",
       ParamType::String,
       std::string("water"),
       "liquid: a Table 1 material of Parshikov et al. 2023 (rho0, c0, eta)",
       {},
       {},
       false,
       material_keys()},
      {"eta", ParamType::Real, -1.0, "dynamic viscosity, Pa s (< 0: the material's)", -1.0, {}},
      {"D0",
       ParamType::Real,
       1e-8,
       "particle size (lattice spacing), m (the paper: 1e-8)",
       0.0,
       {},
       true},
      {"R_over_D0", ParamType::Int, std::int64_t{20}, "drop radius in particle sizes", 3.0,
       10000.0},
      {"Re_g",
       ParamType::Real,
       5.0,
       "gravitational Reynolds number sqrt(g R) R / nu, nu the physical viscosity (sets g)",
       0.0,
       {},
       true},
      {"t_end_g", ParamType::Real, 20.0, "end time in units of t_g = R / sqrt(g R)", 0.0, {}, true},
      {"sample_interval",
       ParamType::Real,
       0.1,
       "time between samples of the drop's shape, in t_g",
       0.0,
       {},
       true},
      {"fit_from", ParamType::Real, 0.5,
       "the viscometer's fit window starts at fit_from t_end (a^5 against t)", 0.0, 1.0},
      {"floor_half_width", ParamType::Real, 6.0, "half length of the floor, in R", 1.0, 1000.0},
  };
  add_loop_params(c.params); // output_interval (cases/loop_params.hpp)
  c.run = [](const Params& prm, const RunContext& ctx) { return run_spreading_drop(prm, ctx); };
  c.size = [](const Params& prm) {
    const RunContext none;
    SpreadingDropCase c(prm, none);
    return size_flow_case<2>(c, prm, "contact");
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_spreading_drop_case()); // core/registry.hpp
} // namespace

} // namespace sph
