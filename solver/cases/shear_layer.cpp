// Case "shear_layer": the impulsively started shear layer of seed 003 (Parshikov et al.), sections
// 3.1-3.2 (numerical viscosity of the contact scheme), 5.1 (zeta sweep, liquid lead) and 5.2
// (paraffin | glycerol), run with scheme "contact" (solver/schemes/contact/contact.hpp).
//
// Set-up: a lattice of nx x ny (x nz) particles of size D0 (the paper: 80 x 40 x 4, D0 = 10 nm,
// an 800 x 400 x 40 nm box). x (axis 0) is across the flow with slip walls at x = +-nx D0 / 2, y
// along the flow and z are periodic. At t = 0, U_y = +U0 for x > 0 and -U0 for x < 0, rho = rho0,
// P = 0. Left (x < 0) and right layers may be different materials (Table 1 of seed 003, in
// materials.hpp).
//
// Periodic depth: the cell list needs a periodic axis of at least 3 search radii; the paper's 4
// layers in z are less than that, so nz (and ny) are raised to the smallest count that is
// enough (metrics nz_used, ny_used). The initial state and the equations are invariant under a
// shift by D0 in z, so every z layer carries the same solution and the depth changes nothing but
// the cost.
//
// Measurement (diagnostics/erf_fit.hpp): at 5 times t_k = (0.6, 0.7, 0.8, 0.9, 1.0) t_end the
// particle velocities U_y(x) are fitted by least squares with the erf solution of seed 003 eq.
// (10) (with its images in the slip walls, which matter only once the layer reaches them):
//   eta_fit         rho0 times the mean of the fitted nu_k (Pa s); with eta = 0 and zeta = 0 it is
//                   the scheme's numerical viscosity eta_num (the paper's method, section 3.2)
//   eta_fit_spread  (max_k nu_k - min_k nu_k) / mean_k nu_k: departure from self-similarity
//   fit_rms         RMS residual of the fit at t_end / U0 (how erf-like the profile is)
//   profile_err     RMS over particles of (U_y - u_phys(x, t_end)) / U0, u_phys the solution with
//                   the physical viscosity only
// Two fluids: nu_left, nu_right are fitted jointly (eta_fit_left, eta_fit_right) with the
// composite-medium solution; profile_err uses the same solution with the physical viscosities.
// Parameter impedance: a checked copy of rho0 c0 (the x axis of the eta_num-against-Z figure);
// with material = custom it may set c0 instead.
// Self-similarity (Fig. 6b): with profile_times = "t_1 t_2 ..." (s, ascending, <= t_end) the mean
// U_y of each lattice column is sampled at the first step at or after each t_k; the profiles are
// compared on xi = x sqrt(t_1 / t_k) (the erf solution depends on x / sqrt(t) only):
//   selfsim_err     max over k > 1 of the RMS over xi of (U_k(xi) - U_1(xi)) / U0, xi within
//                   the walls at every t_k (the profiles interpolated linearly between columns)
// and written to <output_dir>/shear_layer.h5, columns similarity/{xi, u_phys, u_t1, u_t2, ...}
// (u_phys: the physical-viscosity solution at t_1).
// Cost (besides the time loop's): wall_s, wall_per_step_s, n_fluid, n_ghost, neighbors_mean.
// Runs on the shared time loop (cases/time_loop.hpp) with scheme contact; the slip walls are
// Flow::slip_walls. Divergence: a density deviation above 50 % (or a speed above 10 (c0 + U0)).
// Checkpoints: every particle field (ghosts included), the scheme's search count and cell radius,
// the fits made so far and this case's sums. A resumed job continues bit for bit (tested).
#include "cases/loop_params.hpp"
#include "cases/materials.hpp"
#include "cases/time_loop.hpp"
#include "core/lattice.hpp"
#include "diagnostics/erf_fit.hpp"
#include "io/job_attributes.hpp"
#include "schemes/contact/scheme_info.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sph {
namespace {

struct Side {
  double rho0, c0, eta;
};

Side resolve_side(const Params& prm, const std::string& key) {
  Side s{-1.0, -1.0, -1.0};
  if (key != "custom") {
    const Material& m = material_or_throw(key, "shear_layer");
    s = {m.rho0, m.c0, m.eta};
  }
  if (get_real(prm, "rho0") >= 0.0)
    s.rho0 = get_real(prm, "rho0");
  if (get_real(prm, "c0") >= 0.0)
    s.c0 = get_real(prm, "c0");
  if (get_real(prm, "eta") >= 0.0)
    s.eta = get_real(prm, "eta");
  const double Z = get_real(prm, "impedance");
  if (Z > 0.0) {
    if (key == "custom" && get_real(prm, "c0") < 0.0 && s.rho0 > 0.0)
      s.c0 = Z / s.rho0;
    else if (!(std::abs(Z - s.rho0 * s.c0) <= 1e-3 * s.rho0 * s.c0))
      throw std::invalid_argument("shear_layer: impedance = " + std::to_string(Z) +
                                  " differs from rho0 c0 = " + std::to_string(s.rho0 * s.c0) +
                                  " of material '" + key + "' by more than 0.1%");
  }
  if (!(s.rho0 > 0.0) || !(s.c0 > 0.0) || !(s.eta >= 0.0))
    throw std::invalid_argument(
        "shear_layer: material 'custom' needs rho0 > 0, c0 > 0 (or impedance) and eta >= 0");
  return s;
}

template <int D>
class ShearLayerCase final : public FlowCase<D> {
public:
  ShearLayerCase(const Params& prm, const RunContext& ctx) : prm_(prm), ctx_(ctx) {
    const std::string mat = get_string(prm, "material");
    const std::string ml =
        get_string(prm, "material_left").empty() ? mat : get_string(prm, "material_left");
    const std::string mr =
        get_string(prm, "material_right").empty() ? mat : get_string(prm, "material_right");
    L_ = resolve_side(prm, ml), R_ = resolve_side(prm, mr);
    two_ = ml != mr;
    U0_ = get_real(prm, "U0"), D0_ = get_real(prm, "D0");
    t_end_ = get_real(prm, "t_end");
    if (t_end_ <= 0.0)
      t_end_ = 1000.0 * D0_ / std::max(L_.c0, R_.c0);
    std::istringstream in(get_string(prm, "profile_times"));
    std::string w;
    while (in >> w) {
      std::size_t used = 0;
      double t = -1.0;
      try {
        t = std::stod(w, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != w.size() || !(t > 0.0) || t > t_end_ * (1.0 + 1e-12) ||
          (!prof_t_.empty() && !(t > prof_t_.back())))
        throw std::invalid_argument(
            "shear_layer: profile_times must be ascending times in (0, t_end] separated by "
            "spaces, got '" +
            w + "'");
      prof_t_.push_back(t);
    }
  }

  Flow<D> build(Particles<D>& p) override {
    p_ = &p;
    // Periodic axes must hold 3 search radii; allow 5% growth of the particle size.
    const double Rs = contact::search_radius(prm_, 1.05 * D0_);
    const int nmin = static_cast<int>(std::ceil(3.0 * Rs / D0_));
    const int nx = static_cast<int>(get_int(prm_, "nx"));
    ny_ = std::max<int>(static_cast<int>(get_int(prm_, "ny")), nmin);
    nz_ = D == 3 ? std::max<int>(static_cast<int>(get_int(prm_, "nz")), nmin) : 1;
    half_ = 0.5 * nx * D0_;

    const contact::Fields f = contact::Fields::add_to(p);
    std::array<int, D> lo{}, hi{};
    hi[0] = nx, hi[1] = ny_;
    if constexpr (D == 3)
      hi[2] = nz_;
    const double vol = std::pow(D0_, D);
    for_each_lattice_point<D>(lo, hi, D0_, [&](Vec<D> x, const std::array<int, D>&) {
      x[0] -= half_;
      x[1] -= 0.5 * ny_ * D0_;
      if constexpr (D == 3)
        x[2] -= 0.5 * nz_ * D0_;
      const Side& s = x[0] < 0.0 ? L_ : R_;
      const std::size_t i = p.add(x, s.rho0 * vol, s.rho0);
      p.v[i][1] = x[0] < 0.0 ? -U0_ : U0_;
      p.scalar(f.rho0)[i] = s.rho0;
      p.scalar(f.c0)[i] = s.c0;
      p.scalar(f.eta)[i] = s.eta;
    });
    n_fluid_ = p.size();
    nx_ = nx;

    Flow<D> flow;
    flow.box.lo[0] = -half_ - 2.0 * Rs, flow.box.hi[0] = half_ + 2.0 * Rs;
    flow.box.lo[1] = -0.5 * ny_ * D0_, flow.box.hi[1] = 0.5 * ny_ * D0_;
    flow.box.periodic[1] = true;
    if constexpr (D == 3) {
      flow.box.lo[2] = -0.5 * nz_ * D0_, flow.box.hi[2] = 0.5 * nz_ * D0_;
      flow.box.periodic[2] = true;
    }
    flow.slip_walls = {SlipWall{0, -half_, +1}, SlipWall{0, half_, -1}};
    flow.rho0 = L_.rho0, flow.U = U0_, flow.L = nx * D0_, flow.dx = D0_;
    return flow;
  }
  double t_end() const override { return t_end_; }
  // Not finite or ten times the fastest sound speed: broken (the density test below comes first).
  double speed_bound() const override { return 10.0 * (std::max(L_.c0, R_.c0) + U0_); }

  // Diverged when a density deviates from its material's rho0 by more than 50 %; the erf fits at
  // the five times t_k.
  bool after_step(FlowScheme<D>&, const LoopState& at, const StepStats& st) override {
    const Particles<D>& p = *p_;
    dt_sum_ += st.dt;
    contact::check_density_deviation(p, max_drho_, 0.5, at.steps);
    while (next_ < 5 && at.t >= fit_at[next_] * t_end_ * (1.0 - 1e-12)) {
      sample();
      if (two_) {
        const ErfFit ft = fit_shear_layer2(sl(), xs_, us_, at.t, L_.rho0, R_.rho0);
        nul_k_.push_back(ft.nu_left), nur_k_.push_back(ft.nu_right);
        fit_rms_ = ft.rms;
      } else {
        const ErfFit ft = fit_shear_layer(sl(), xs_, us_, at.t);
        nu_k_.push_back(ft.nu);
        fit_rms_ = ft.rms;
      }
      ++next_;
    }
    // prof_at_ holds one sampled time per requested time reached so far
    while (prof_at_.size() < prof_t_.size() && at.t >= prof_t_[prof_at_.size()] * (1.0 - 1e-12)) {
      column_profile();
      prof_at_.push_back(at.t);
    }
    return false;
  }

  void finish(FlowScheme<D>& s, const LoopState& at, RunResult& res) override {
    const Particles<D>& p = *p_;
    auto spread = [](const std::vector<double>& v) {
      double lo = v[0], hi = v[0], sum = 0.0;
      for (double x : v)
        lo = std::min(lo, x), hi = std::max(hi, x), sum += x;
      return (hi - lo) / (sum / v.size());
    };
    auto mean = [](const std::vector<double>& v) {
      double sum = 0.0;
      for (double x : v)
        sum += x;
      return sum / v.size();
    };
    // Profile error against the physical-viscosity solution at t_end.
    sample();
    const double nuL = L_.eta / L_.rho0, nuR = R_.eta / R_.rho0;
    double err2 = 0.0;
    for (std::size_t k = 0; k < xs_.size(); ++k) {
      const double ue = two_ ? shear_layer_u2(sl(), xs_[k], at.t, nuL, L_.rho0, nuR, R_.rho0)
                             : shear_layer_u(sl(), xs_[k], at.t, nuL);
      err2 += (us_[k] - ue) * (us_[k] - ue);
    }
    if (two_) {
      res.add("eta_fit_left", L_.rho0 * mean(nul_k_));
      res.add("eta_fit_right", R_.rho0 * mean(nur_k_));
      res.add("eta_fit_spread", std::max(spread(nul_k_), spread(nur_k_)));
    } else {
      res.add("eta_fit", L_.rho0 * mean(nu_k_));
      res.add("eta_fit_spread", spread(nu_k_));
    }
    res.add("profile_err", std::sqrt(err2 / xs_.size()) / U0_);
    res.add("fit_rms", fit_rms_);
    if (!two_) {
      res.add("eta_phys", L_.eta);
      res.add("Z", L_.rho0 * L_.c0);
      res.add("eta_num_ref",
              contact::eta_num_of(contact::options_from(prm_), D0_, L_.rho0 * L_.c0));
    } else {
      res.add("eta_phys_left", L_.eta);
      res.add("eta_phys_right", R_.eta);
    }
    res.add("t_end", t_end_);
    res.add("max_density_dev", max_drho_);
    res.add("dt_mean", dt_sum_ / at.steps);
    res.add("wall_s", at.wall_s);
    res.add("wall_per_step_s", at.wall_s / at.steps);
    res.add("n_fluid", static_cast<double>(n_fluid_));
    res.add("n_ghost", static_cast<double>(p.size() - n_fluid_)); // the slip walls' mirrors
    res.add("ny_used", ny_);
    res.add("nz_used", nz_);
    double pairs = 0.0;
    const auto& nl = s.neighbors();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid)
        pairs += nl.offset[i + 1] - nl.offset[i];
    res.add("neighbors_mean", pairs / n_fluid_);
    if (!prof_at_.empty())
      similarity(res);
  }

  // The fits made so far and this case's sums.
  std::vector<std::string> state_names() const override {
    return {"shear_layer/nu",   "shear_layer/nu_left",   "shear_layer/nu_right",
            "shear_layer/sums", "shear_layer/profile_t", "shear_layer/profiles"};
  }
  void save_state(StateArrays& out) const override {
    out["shear_layer/profile_t"] = prof_at_;
    out["shear_layer/profiles"] = prof_u_;
    out["shear_layer/nu"] = nu_k_;
    out["shear_layer/nu_left"] = nul_k_;
    out["shear_layer/nu_right"] = nur_k_;
    out["shear_layer/sums"] = {dt_sum_, max_drho_, fit_rms_, static_cast<double>(next_)};
  }
  void load_state(const StateArrays& in) override {
    nu_k_ = in.at("shear_layer/nu");
    nul_k_ = in.at("shear_layer/nu_left");
    nur_k_ = in.at("shear_layer/nu_right");
    const auto& a = in.at("shear_layer/sums");
    io::expect_state_size(a, 4, "shear_layer: checkpoint array shear_layer/sums");
    dt_sum_ = a[0], max_drho_ = a[1], fit_rms_ = a[2], next_ = static_cast<int>(a[3]);
    prof_at_ = in.at("shear_layer/profile_t");
    prof_u_ = in.at("shear_layer/profiles");
    if (prof_u_.size() != prof_at_.size() * static_cast<std::size_t>(nx_))
      throw std::runtime_error("shear_layer: checkpoint profiles do not match nx");
  }

private:
  static constexpr double fit_at[5] = {0.6, 0.7, 0.8, 0.9, 1.0};
  Params prm_;
  RunContext ctx_;
  Side L_{}, R_{};
  bool two_ = false;
  double U0_ = 0.0, D0_ = 0.0, t_end_ = 0.0, half_ = 0.0;
  int ny_ = 0, nz_ = 0;
  std::size_t n_fluid_ = 0;
  Particles<D>* p_ = nullptr;
  std::vector<double> xs_, us_, nu_k_, nul_k_, nur_k_;
  double dt_sum_ = 0.0, max_drho_ = 0.0, fit_rms_ = 0.0;
  int next_ = 0, nx_ = 0;
  std::vector<double> prof_t_, prof_at_, prof_u_; // requested and sampled times, nx_ per sample

  ShearLayer sl() const { return {U0_, two_ ? 0.0 : half_, 3}; }
  // Mean U_y of the fluid particles of each lattice column (width D0), appended to prof_u_.
  void column_profile() {
    std::vector<double> sum(nx_, 0.0), n(nx_, 0.0);
    for (std::size_t i = 0; i < p_->size(); ++i)
      if (p_->kind[i] == Kind::Fluid) {
        const int b =
            std::clamp(static_cast<int>(std::floor((p_->r[i][0] + half_) / D0_)), 0, nx_ - 1);
        sum[b] += p_->v[i][1], n[b] += 1.0;
      }
    for (int b = 0; b < nx_; ++b)
      prof_u_.push_back(n[b] > 0.0 ? sum[b] / n[b] : 0.0);
  }
  // Profile k at position x (linear between column centres, constant beyond the outer ones).
  double profile_at(std::size_t k, double x) const {
    const double* u = prof_u_.data() + k * nx_;
    const double s = (x + half_) / D0_ - 0.5;
    if (s <= 0.0)
      return u[0];
    if (s >= nx_ - 1)
      return u[nx_ - 1];
    const int b = static_cast<int>(s);
    return u[b] + (s - b) * (u[b + 1] - u[b]);
  }
  // selfsim_err and the similarity columns (file comment).
  void similarity(RunResult& res) const {
    const double t1 = prof_at_.front(), tl = prof_at_.back();
    const double xi_max = half_ * std::sqrt(t1 / tl) - D0_;
    std::vector<std::vector<double>> cols(2 + prof_at_.size());
    for (int b = 0; b < nx_; ++b) {
      const double xi = -half_ + (b + 0.5) * D0_;
      if (std::abs(xi) > xi_max)
        continue;
      cols[0].push_back(xi);
      const double nuL = L_.eta / L_.rho0, nuR = R_.eta / R_.rho0;
      cols[1].push_back(two_ ? shear_layer_u2(sl(), xi, t1, nuL, L_.rho0, nuR, R_.rho0)
                             : shear_layer_u(sl(), xi, t1, nuL));
      for (std::size_t k = 0; k < prof_at_.size(); ++k)
        cols[2 + k].push_back(profile_at(k, xi * std::sqrt(prof_at_[k] / t1)));
    }
    double worst = 0.0;
    for (std::size_t k = 1; k < prof_at_.size(); ++k) {
      double e2 = 0.0;
      for (std::size_t m = 0; m < cols[0].size(); ++m)
        e2 += std::pow(cols[2 + k][m] - cols[2][m], 2);
      worst = std::max(worst, std::sqrt(e2 / cols[0].size()) / U0_);
    }
    res.add("selfsim_err", worst);
    if (auto h5 = io::open_job_output(ctx_, "shear_layer", prm_)) {
      std::vector<std::string> names{"xi", "u_phys"};
      for (std::size_t k = 0; k < prof_at_.size(); ++k)
        names.push_back("u_t" + std::to_string(k + 1));
      h5->write_columns("similarity", names, cols);
      h5->close();
    }
  }
  void sample() {
    xs_.clear(), us_.clear();
    for (std::size_t i = 0; i < p_->size(); ++i)
      if (p_->kind[i] == Kind::Fluid)
        xs_.push_back(p_->r[i][0]), us_.push_back(p_->v[i][1]);
  }
};

template <int D>
RunResult run_shear_layer(const Params& prm, const RunContext& ctx) {
  ShearLayerCase<D> c(prm, ctx);
  return run_flow_case<D>(c, prm, ctx, "contact");
}

} // namespace

CaseInfo make_shear_layer_case() {
  CaseInfo c;
  c.name = "shear_layer";
  c.description = "Shear layer of two sliding layers vs the erf solution; numerical viscosity of "
                  "contact SPH (Parshikov et al. 2023, sections 3 and 5.1-5.2)";
  c.schemes = {"contact"};
  std::vector<std::string> mats = material_keys();
  mats.push_back("custom");
  std::vector<std::string> sides = mats;
  sides.insert(sides.begin(), "");
  c.params = {
      {"material",
       ParamType::String,
       std::string("lead"),
       "liquid of both layers: a Table 1 material of Parshikov et al. 2023, or custom (rho0, c0, "
       "eta)",
       {},
       {},
       false,
       mats},
      {"material_left",
       ParamType::String,
       std::string(""),
       "liquid of the layer x < 0 (empty: material)",
       {},
       {},
       false,
       sides},
      {"material_right",
       ParamType::String,
       std::string(""),
       "liquid of the layer x > 0 (empty: material)",
       {},
       {},
       false,
       sides},
      {"rho0",
       ParamType::Real,
       -1.0,
       "reference density, kg/m^3 (< 0: from the material)",
       -1.0,
       {}},
      {"c0", ParamType::Real, -1.0, "sound speed, m/s (< 0: from the material)", -1.0, {}},
      {"eta",
       ParamType::Real,
       -1.0,
       "physical dynamic viscosity, Pa s (< 0: from the material; 0: inviscid)",
       -1.0,
       {}},
      {"impedance",
       ParamType::Real,
       -1.0,
       "acoustic impedance rho0 c0, kg/(m^2 s) (< 0: from the material). With a Table 1 material "
       "it must equal rho0 c0 within 0.1% (a checked label that figures can plot against); with "
       "custom and no c0 it sets c0 = impedance / rho0",
       -1.0,
       {}},
      {"U0",
       ParamType::Real,
       500.0,
       "layer speed, m/s (+U0 for x > 0, -U0 for x < 0)",
       0.0,
       {},
       true},
      {"D0", ParamType::Real, 1e-8, "particle size, m", 0.0, {}, true},
      {"t_end", ParamType::Real, 0.0, "end time, s (0: 1000 D0 / c0)", 0.0, {}},
      {"dim", ParamType::Int, std::int64_t{3}, "space dimension (the paper's box is 3D)", 2.0, 3.0},
      {"nx", ParamType::Int, std::int64_t{80}, "particles across the flow (between the walls)", 4.0,
       100000.0},
      {"ny", ParamType::Int, std::int64_t{40}, "particles along the flow (periodic)", 1.0,
       100000.0},
      {"nz", ParamType::Int, std::int64_t{4}, "particles in depth (3D, periodic)", 1.0, 100000.0},
  };
  ParamSpec times{"profile_times", ParamType::String, std::string(""),
                  "times (s, ascending, <= t_end, separated by spaces) of the U_y(x) profiles of "
                  "the self-similarity check, Fig. 6b (empty: none)"};
  times.neutral_default = true; // added later: the jobs without it keep their keys
  c.params.push_back(times);
  add_loop_params(c.params); // output_interval (cases/loop_params.hpp)
  c.run = [](const Params& prm, const RunContext& ctx) {
    return get_int(prm, "dim") == 3 ? run_shear_layer<3>(prm, ctx) : run_shear_layer<2>(prm, ctx);
  };
  c.size = [](const Params& prm) {
    if (get_int(prm, "dim") == 3) {
      const RunContext none;
      ShearLayerCase<3> c(prm, none);
      return size_flow_case<3>(c, prm, "contact");
    }
    const RunContext none;
    ShearLayerCase<2> c(prm, none);
    return size_flow_case<2>(c, prm, "contact");
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_shear_layer_case()); // core/registry.hpp
} // namespace

} // namespace sph
