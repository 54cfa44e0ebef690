// Case "cantilever": a 2D elastic beam clamped at one end, under its own weight, run with scheme
// "elastic_solid" (schemes/solid/; docs/solid.md): static deflection and first bending mode
// against Euler-Bernoulli beam theory, energy and momentum checks. The validation of the solid on
// which the FSI beam of issue 18 (Turek & Hron FSI2, seed 002 section 4.3) will be built.
//
// Set-up: beam [0, L] x [-H/2, H/2] of particles on the cell-centred lattice of spacing
// dx = H / H_over_dx (x = (i + 1/2) dx, y = -H/2 + (j + 1/2) dx), mass rho0 dx^2, kind Solid;
// the clamp: the lattice continued to x < 0 over ceil(support / dx) columns (support = the
// kernel's radius, so that no Solid particle near x = 0 misses a neighbour), kind Wall, held at
// rest by the scheme. Material: Young's modulus E, Poisson ratio nu, density rho0 (2D: plane
// strain). Load: gravity g in -y, applied suddenly at t = 0 on the beam at rest (own weight);
// optionally an initial velocity v_tip phi(x / L) / phi(1) in y, phi the first cantilever mode.
// The suddenly applied weight makes the tip oscillate about the static deflection at the first
// bending frequency, so one run gives both:
//   tip displacement: mean over the tip column (x = L - dx/2) of y - y0, sampled every
//   T_EB / 400 (T_EB the beam-theory period below);
//   tip_frequency       from the upward zero crossings of the mean-removed tip displacement
//                       (diagnostics/signal.hpp), over every whole period in [0, t_end]
//   tip_deflection      - time mean of the tip displacement over those whole periods (the static
//                       deflection; over all samples when less than one period was run)
// Beam theory (Euler-Bernoulli, plane strain: E' = E / (1 - nu^2), I = H^3 / 12 per unit depth,
// q = rho0 g H, A = H):
//   w(x) = q x^2 (6 L^2 - 4 L x + x^2) / (24 E' I)   (w(L) = q L^4 / (8 E' I)), taken at the tip
//                                                   column x = L - dx/2
//   omega_1 = 1.8751^2 sqrt(E' I / (rho0 A L^4)),    f_EB = omega_1 / (2 pi)
// Metrics: tip_deflection, deflection_eb, deflection_ratio (g > 0), tip_frequency,
// tip_frequency_spectral (periodogram peak), frequency_eb, frequency_ratio, tip_amplitude,
// periods; energy_drift = (E(t_end) - E(0)) / max_t E_el and energy_drift_max = max_t |E - E(0)| /
// max_t E_el, E = kinetic + elastic + gravitational (sum m g (y - y0)); internal_force_rel_max,
// internal_torque_rel_max: max over samples of |sum_i m_i a_i| / sum_i m_i |a_i| (and the torque
// sum over sum |x_i| m_i |a_i|), the internal forces over every particle, clamp included (round-off
// when momentum is conserved); n_solid, clamp_layers, dx, L_over_H.
// With an output directory, cantilever.h5 holds the series (t, tip_x, tip_y, kinetic, elastic,
// gravity, energy) and the job's typed parameters and key (io/job_attributes.hpp).
#include "cases/case.hpp"
#include "cases/time_loop.hpp"
#include "core/kernels/kernel.hpp"
#include "diagnostics/signal.hpp"
#include "io/hdf5.hpp"
#include "io/job_attributes.hpp"
#include "schemes/solid/elastic_solid.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace sph {
namespace {

constexpr double beta1 = 1.8751040687119611; // first root of cos b cosh b = -1

// First cantilever mode shape (clamped at xi = 0, free at xi = 1), phi(1) = 2.
double mode1(double xi) {
  const double b = beta1, s = (std::cosh(b) + std::cos(b)) / (std::sinh(b) + std::sin(b));
  return std::cosh(b * xi) - std::cos(b * xi) - s * (std::sinh(b * xi) - std::sin(b * xi));
}

struct Geometry {
  double L, H, dx;
  int nL, nH;
};

Geometry geometry(const Params& prm) {
  Geometry g;
  g.L = get_real(prm, "L"), g.H = get_real(prm, "H");
  g.nH = static_cast<int>(get_int(prm, "H_over_dx"));
  g.dx = g.H / g.nH;
  g.nL = static_cast<int>(std::lround(g.L / g.dx));
  return g;
}

class Cantilever final : public FlowCase<2> {
public:
  explicit Cantilever(const Params& prm) : prm_(prm), geo_(geometry(prm)) {
    E_ = get_real(prm, "E"), nu_ = get_real(prm, "nu"), rho0_ = get_real(prm, "rho0");
    g_ = get_real(prm, "g"), v_tip_ = get_real(prm, "v_tip"), t_end_ = get_real(prm, "t_end");
    const solid::Elastic el{E_, nu_};
    c_p_ = el.c_p(rho0_);
    const double Ep = el.plane_strain_E(), I = geo_.H * geo_.H * geo_.H / 12.0, A = geo_.H;
    omega_eb_ = beta1 * beta1 * std::sqrt(Ep * I / (rho0_ * A * std::pow(geo_.L, 4)));
    const double x = (geo_.nL - 0.5) * geo_.dx, L = geo_.L, q = rho0_ * g_ * geo_.H;
    w_eb_ = q * x * x * (6.0 * L * L - 4.0 * L * x + x * x) / (24.0 * Ep * I);
    sample_dt_ = 2.0 * std::numbers::pi / omega_eb_ / 400.0;
  }

  Flow<2> build(Particles<2>& p) override {
    p_ = &p;
    const double dx = geo_.dx;
    const double support =
        kernel_support_factor(get_string(prm_, "kernel")) * get_real(prm_, "h_over_dx") * dx;
    clamp_ = static_cast<int>(std::ceil(support / dx - 1e-9));
    for (int j = 0; j < geo_.nH; ++j)
      for (int i = -clamp_; i < geo_.nL; ++i) {
        const Vec2 x((i + 0.5) * dx, -0.5 * geo_.H + (j + 0.5) * dx);
        const std::size_t k = p.add(x, rho0_ * dx * dx, rho0_, i < 0 ? Kind::Wall : Kind::Solid);
        if (i >= 0 && v_tip_ != 0.0)
          p.v[k] = Vec2(0.0, v_tip_ * mode1(x[0] / geo_.L) / mode1(1.0));
      }
    Flow<2> f;
    f.rho0 = rho0_, f.dx = dx, f.L = geo_.L, f.U = c_p_;
    f.youngs_modulus = E_, f.poisson_ratio = nu_;
    return f;
  }

  // After the scheme's init (which sorted the particles once for good): the tip column, the
  // reference positions, gravity, the first sample.
  void start(FlowScheme<2>& s) override {
    const double x_tip = (geo_.nL - 0.5) * geo_.dx;
    r0_ = p_->r;
    tip_.clear();
    for (std::size_t i = 0; i < p_->size(); ++i) {
      if (p_->kind[i] == Kind::Solid)
        ++n_solid_;
      if (p_->kind[i] == Kind::Solid && std::abs(p_->r[i][0] - x_tip) < 0.25 * geo_.dx)
        tip_.push_back(i);
    }
    s.set_body_acceleration(Vec2(0.0, -g_));
    sample(s, 0.0);
  }
  double t_end() const override { return t_end_; }
  double speed_bound() const override { return c_p_; } // a solid moving at its sound speed broke

  bool after_step(FlowScheme<2>& s, const LoopState& at, const StepStats&) override {
    if (at.t >= next_sample_ * (1.0 - 1e-12) || at.t >= t_end_ * (1.0 - 1e-12))
      sample(s, at.t);
    return false;
  }

  void finish(FlowScheme<2>&, const LoopState&, RunResult& res) override {
    const auto& t = s_[0];
    const auto& tip_y = s_[2];
    const diag::Frequency fz = diag::zero_crossing_frequency(t, tip_y);
    const diag::Frequency fs = diag::spectral_peak_frequency(t, tip_y);
    double t0 = t.front(), t1 = t.back();
    if (fz.cycles >= 1)
      t0 = fz.t_first, t1 = fz.t_last;
    const double mean = diag::time_mean(t, tip_y, t0, t1);
    double lo = 1e300, hi = -1e300;
    for (std::size_t k = 0; k < t.size(); ++k)
      if (t[k] >= t0 && t[k] <= t1)
        lo = std::min(lo, tip_y[k]), hi = std::max(hi, tip_y[k]);
    const double f_eb = omega_eb_ / (2.0 * std::numbers::pi);
    res.add("tip_deflection", -mean);
    if (g_ > 0.0) {
      res.add("deflection_eb", w_eb_);
      res.add("deflection_ratio", -mean / w_eb_);
    }
    res.add("tip_frequency", fz.f);
    res.add("tip_frequency_spectral", fs.f);
    res.add("frequency_eb", f_eb);
    res.add("frequency_ratio", fz.f / f_eb);
    res.add("periods", fz.cycles);
    res.add("tip_amplitude", 0.5 * (hi - lo));
    // Energy: E = kinetic + elastic + gravitational, against the largest elastic energy.
    const auto& e = s_[6];
    double el_max = 0.0, drift_max = 0.0;
    for (std::size_t k = 0; k < e.size(); ++k)
      el_max = std::max(el_max, s_[4][k]);
    const double ref = el_max > 0.0 ? el_max : 1.0;
    for (double x : e)
      drift_max = std::max(drift_max, std::abs(x - e.front()) / ref);
    res.add("energy_drift", (e.back() - e.front()) / ref);
    res.add("energy_drift_max", drift_max);
    res.add("internal_force_rel_max", force_max_);
    res.add("internal_torque_rel_max", torque_max_);
    res.add("n_solid", static_cast<double>(n_solid_));
    res.add("clamp_layers", clamp_);
    res.add("dx", geo_.dx);
    res.add("L_over_H", geo_.L / geo_.H);
    if (!output_dir_.empty()) {
      io::H5Writer w(output_dir_ / "cantilever.h5");
      io::write_job_attributes(w, "cantilever", prm_, job_key_);
      w.write_columns("series", names(), s_);
      w.close();
    }
  }

  std::vector<std::string> state_names() const override {
    std::vector<std::string> n{"cantilever/loop"};
    for (const auto& x : names())
      n.push_back("cantilever/series/" + x);
    return n;
  }
  void save_state(StateArrays& out) const override {
    out["cantilever/loop"] = {next_sample_, force_max_, torque_max_};
    for (std::size_t k = 0; k < s_.size(); ++k)
      out["cantilever/series/" + names()[k]] = s_[k];
  }
  void load_state(const StateArrays& in) override {
    const auto& a = in.at("cantilever/loop");
    io::expect_state_size(a, 3, "checkpoint array cantilever/loop");
    next_sample_ = a[0], force_max_ = a[1], torque_max_ = a[2];
    for (std::size_t k = 0; k < s_.size(); ++k)
      s_[k] = in.at("cantilever/series/" + names()[k]);
  }

  std::filesystem::path output_dir_;
  std::string job_key_;

private:
  const Params& prm_;
  Geometry geo_;
  double E_, nu_, rho0_, g_, v_tip_, t_end_, c_p_, omega_eb_, w_eb_, sample_dt_;
  int clamp_ = 0;
  long n_solid_ = 0;
  Particles<2>* p_ = nullptr;
  std::vector<Vec2> r0_;
  std::vector<std::size_t> tip_;
  double next_sample_ = 0.0, force_max_ = 0.0, torque_max_ = 0.0;
  std::vector<std::vector<double>> s_ = std::vector<std::vector<double>>(7);

  static const std::vector<std::string>& names() {
    static const std::vector<std::string> n{"t",       "tip_x",   "tip_y", "kinetic",
                                            "elastic", "gravity", "energy"};
    return n;
  }

  void sample(const FlowScheme<2>& s, double t) {
    next_sample_ = t + sample_dt_;
    Vec2 tip = Vec2::Zero();
    for (std::size_t i : tip_)
      tip += p_->r[i] - r0_[i];
    tip /= static_cast<double>(tip_.size());
    double ke = 0.0, el = 0.0, f = 0.0, fs = 0.0, tq = 0.0, ts = 0.0, pot = 0.0;
    for (const auto& [name, value] : s.probes()) {
      if (name == "kinetic_energy")
        ke = value;
      else if (name == "elastic_energy")
        el = value;
      else if (name == "internal_force")
        f = value;
      else if (name == "internal_force_scale")
        fs = value;
      else if (name == "internal_torque")
        tq = value;
      else if (name == "internal_torque_scale")
        ts = value;
    }
    for (std::size_t i = 0; i < p_->size(); ++i)
      if (p_->kind[i] == Kind::Solid)
        pot += p_->m[i] * g_ * (p_->r[i][1] - r0_[i][1]);
    if (fs > 0.0)
      force_max_ = std::max(force_max_, f / fs);
    if (ts > 0.0)
      torque_max_ = std::max(torque_max_, tq / ts);
    const double row[] = {t, tip[0], tip[1], ke, el, pot, ke + el + pot};
    for (std::size_t k = 0; k < s_.size(); ++k)
      s_[k].push_back(row[k]);
  }
};

} // namespace

CaseInfo make_cantilever_case() {
  CaseInfo c;
  c.name = "cantilever";
  c.description = "2D elastic cantilever under its own weight: static deflection and first-mode "
                  "frequency against Euler-Bernoulli (the solid of the FSI case, Wang, Haidn & Hu "
                  "2024 section 4.3)";
  c.schemes = {"elastic_solid"};
  c.params = {
      {"L", ParamType::Real, 0.35, "beam length (m)", 0.0, {}, true},
      {"H", ParamType::Real, 0.02, "beam thickness (m)", 0.0, {}, true},
      {"H_over_dx", ParamType::Int, std::int64_t{8}, "particles across the thickness, H / dx", 2.0,
       200.0},
      {"E", ParamType::Real, 1.4e6, "Young's modulus (Pa)", 0.0, {}, true},
      {"nu", ParamType::Real, 0.4, "Poisson ratio (2D: plane strain)", -0.99, 0.49},
      {"rho0", ParamType::Real, 1000.0, "density (kg/m^3)", 0.0, {}, true},
      {"g",
       ParamType::Real,
       0.05,
       "gravity in -y, applied at t = 0 (m/s^2; 0.05: tip deflection ~0.5 % of L)",
       0.0,
       {}},
      {"v_tip", ParamType::Real, 0.0, "initial tip velocity in y, first-mode shape (m/s)", {}, {}},
      {"t_end",
       ParamType::Real,
       3.0,
       "end time (s; the first period is ~0.93 s by default)",
       0.0,
       {},
       true},
  };
  add_loop_params(c.params); // output_interval (cases/loop_params.hpp)
  c.check = [](const Params& prm) -> std::optional<std::string> {
    const Geometry g = geometry(prm);
    if (std::abs(g.L / g.dx - g.nL) > 1e-6 * g.nL)
      return "cantilever: L / dx = L H_over_dx / H must be an integer (it is " +
             std::to_string(g.L / g.dx) + ")";
    if (g.nL < 2)
      return "cantilever: the beam needs at least 2 particles along L";
    return std::nullopt;
  };
  c.size = [](const Params& prm) {
    Cantilever cl(prm);
    return size_flow_case<2>(cl, prm, "elastic_solid");
  };
  c.run = [](const Params& prm, const RunContext& ctx) {
    Cantilever cl(prm);
    cl.output_dir_ = ctx.output_dir, cl.job_key_ = ctx.job_key;
    return run_flow_case<2>(cl, prm, ctx, "elastic_solid");
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_cantilever_case()); // core/registry.hpp
} // namespace

} // namespace sph
