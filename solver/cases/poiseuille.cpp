// Case "poiseuille": transient plane Poiseuille flow, the start-up of a channel flow from rest
// (Morris, Fox & Zhu 1997, J. Comput. Phys. 136, 214-226, section 4.1 and Fig. 4), run with
// scheme "wcsph_tvf" (the default) or "isph". Written as the worked example of
// docs/adding_a_case.md: one file, registered beside its class.
//
// Set-up (2D, lengths in units of the channel width L = 1, speeds in units of the steady
// centreline speed u_max = 1): fluid between two walls at y = 0 and y = L, periodic along x, at
// rest at t = 0, driven by a uniform body acceleration F along x. Fluid particles on the
// cell-centred lattice ((i + 1/2) dx, (j + 1/2) dx), dx = L / n_y, 0 <= j < n_y; wall particles on
// the same lattice in ceil(support / dx) rows below y = 0 and above y = L, at rest (no-slip by the
// scheme's wall velocity). The period along x is n_x dx with n_x = max(n_y / 2, the smallest count
// that holds 3 kernel supports): the flow does not depend on x. m = rho0 dx^2, rho0 = 1.
// nu = u_max L / Re, F = 8 nu u_max / L^2 (so that the steady centreline speed is u_max). Morris
// et al. take L = 1e-3 m, nu = 1e-6 m^2/s, F = 2e-4 m/s^2: u_max = 2.5e-5 m/s, Re = 0.025 (the
// default), and L^2 / nu = 1 s.
//
// Reference: the series solution of the start-up (Morris et al. 1997, eq. 21),
//   u_x(y, t) = F / (2 nu) y (L - y)
//             - sum_{n >= 0} 4 F L^2 / (nu pi^3 (2n+1)^3) sin(pi y (2n+1) / L)
//                            exp(-(2n+1)^2 pi^2 nu t / L^2),
// u_y = 0 (poiseuille_velocity below; tests/solver/test_case_poiseuille.cpp checks it).
//
// Measured, at the first step that reaches each of Morris et al.'s profile times t = 0.0225,
// 0.045, 0.1125 and 0.225 L^2 / nu (samples 1-4, Fig. 4) and at t_end, on the fluid particles
// against the series at their own y and the step's t:
//   ux_rms_err_K    sqrt(mean_i (u_x,i - u_x(y_i, t))^2) / u_max     (K = 1..4, end)
//   ux_max_err_K    max_i |u_x,i - u_x(y_i, t)| / u_max
//   uy_rms_end      sqrt(mean_i u_y,i^2) / u_max at t_end (0 exactly)
//   ux_rms_err_max  the largest ux_rms_err over the samples taken
//   centre_err_end  sum_i u_x,i / sum_i u_x(y_i, t_end) - 1 over the particles within dx of
//                   y = L / 2 (the centre rows): the sign tells a flow too fast (> 0) from too slow
// A sample later than t_end is not taken (its metrics are absent). With an output directory,
// <output_dir>/poiseuille.h5 holds, per sample, the profile binned by lattice row (profile_K:
// y, ux (row mean), ux_exact) with its time as attribute t_K, and the final fluid fields.
// Checkpoints carry the samples taken so far.
#include "cases/case.hpp"
#include "cases/time_loop.hpp"
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "io/hdf5.hpp"
#include "io/job_attributes.hpp"
#include "io/particle_fields.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace sph {

// The series solution above: u_x at height y (0 <= y <= L) and time t of the start-up from rest
// under the body acceleration F, kinematic viscosity nu. Terms are summed until they fall below
// 1e-17 of the steady centreline speed (at t = 0, where the series converges slowest, 200 000
// terms: an error below 1e-11 of it).
double poiseuille_velocity(double y, double t, double nu, double F, double L) {
  constexpr double pi = std::numbers::pi;
  const double steady = F / (2.0 * nu) * y * (L - y), u_max = F * L * L / (8.0 * nu);
  double s = 0.0;
  for (int n = 0; n < 200000; ++n) {
    const double k = 2.0 * n + 1.0;
    const double a = 4.0 * F * L * L / (nu * pi * pi * pi * k * k * k) *
                     std::exp(-k * k * pi * pi * nu * t / (L * L));
    if (a < 1e-17 * u_max)
      break;
    s += a * std::sin(pi * y * k / L);
  }
  return steady - s;
}

namespace {

// Morris et al.'s profile times of Fig. 4, in units of L^2 / nu.
constexpr double sample_times[] = {0.0225, 0.045, 0.1125, 0.225};
constexpr int n_samples = 4;

class Poiseuille final : public FlowCase<2> {
public:
  explicit Poiseuille(const Params& prm) : prm_(prm) {
    n_y_ = static_cast<int>(get_int(prm, "n_y"));
    Re_ = get_real(prm, "Re");
    nu_ = U * L / Re_;
    F_ = 8.0 * nu_ * U / (L * L);
    t_visc_ = L * L / nu_;
    t_end_ = get_real(prm, "t_end_visc") * t_visc_;
    dx_ = L / n_y_;
  }

  Flow<2> build(Particles<2>& p) override {
    p_ = &p;
    const double h = get_real(prm_, "h_over_dx") * dx_;
    const double support = kernel_support_factor(get_string(prm_, "kernel")) * h;
    const int layers = static_cast<int>(std::ceil(support / dx_ - 1e-9));
    const int n_x = std::max(n_y_ / 2, static_cast<int>(std::ceil(3.0 * support / dx_)) + 1);
    for_each_lattice_point<2>({0, -layers}, {n_x, n_y_ + layers}, dx_,
                              [&](const Vec2& x, const std::array<int, 2>& i) {
                                const bool fluid = i[1] >= 0 && i[1] < n_y_;
                                p.add(x, rho0 * dx_ * dx_, rho0, fluid ? Kind::Fluid : Kind::Wall);
                              });
    Flow<2> f;
    f.v_wall = p.add_vector("v_wall"); // the walls are at rest (zero)
    f.box.lo = Vec2(0.0, -layers * dx_);
    f.box.hi = Vec2(n_x * dx_, L + layers * dx_);
    f.box.periodic = {true, false};
    f.rho0 = rho0, f.U = U, f.L = L, f.Re = Re_, f.dx = dx_;
    f.dt = get_real(prm_, "dt_factor") * h * h / nu_; // isph's fixed step
    return f;
  }
  // The drive: the body acceleration F along x.
  void start(FlowScheme<2>& s) override { s.set_body_acceleration(Vec2(F_, 0.0)); }
  double t_end() const override { return t_end_; }
  double speed_bound() const override { return 10.0 * U; }

  bool after_step(FlowScheme<2>&, const LoopState& at, const StepStats&) override {
    if (next_ < n_samples && at.t >= sample_times[next_] * t_visc_ * (1.0 - 1e-12))
      take_sample(at.t), ++next_;
    return false;
  }

  void finish(FlowScheme<2>&, const LoopState& at, RunResult& res) override {
    take_sample(at.t);
    double worst = 0.0;
    for (std::size_t k = 0; k < samples_.size(); ++k) {
      res.add("ux_rms_err_" + tag(k), samples_[k].rms);
      res.add("ux_max_err_" + tag(k), samples_[k].max);
      worst = std::max(worst, samples_[k].rms);
    }
    const Sample& e = samples_.back();
    res.add("ux_rms_err_max", worst);
    res.add("uy_rms_end", e.uy_rms);
    res.add("centre_err_end", e.centre);
    res.add("t_end_visc", at.t / t_visc_);
    res.add("n_fluid", static_cast<double>(e.n));
    if (!output_dir_.empty()) {
      io::H5Writer w(output_dir_ / "poiseuille.h5");
      io::write_job_attributes(w, "poiseuille", prm_, job_key_);
      std::vector<double> y(n_y_), ux_exact(n_y_);
      for (int j = 0; j < n_y_; ++j)
        y[j] = (j + 0.5) * dx_;
      for (std::size_t k = 0; k < samples_.size(); ++k) {
        const Sample& s = samples_[k];
        for (int j = 0; j < n_y_; ++j)
          ux_exact[j] = poiseuille_velocity(y[j], s.t, nu_, F_, L);
        w.write_columns("profile_" + tag(k), {"y", "ux", "ux_exact"}, {y, s.ux, ux_exact});
        w.attribute("t_" + tag(k), s.t);
      }
      io::write_fluid_fields(w, *p_);
      w.close();
    }
  }

  // Checkpoints: the samples taken so far (numbers, then the binned profile).
  std::vector<std::string> state_names() const override { return {"poiseuille/samples"}; }
  void save_state(StateArrays& out) const override {
    std::vector<double> a{static_cast<double>(samples_.size())};
    for (const Sample& s : samples_) {
      a.insert(a.end(), {s.t, s.rms, s.max, s.uy_rms, s.centre, static_cast<double>(s.n)});
      a.insert(a.end(), s.ux.begin(), s.ux.end());
    }
    out["poiseuille/samples"] = a;
  }
  void load_state(const StateArrays& in) override {
    const auto& a = in.at("poiseuille/samples");
    const std::size_t taken = a.empty() ? 0 : static_cast<std::size_t>(a[0]);
    io::expect_state_size(a, 1 + taken * (6 + static_cast<std::size_t>(n_y_)),
                          "checkpoint array poiseuille/samples");
    samples_.assign(taken, Sample{});
    const double* q = a.data() + 1;
    for (Sample& s : samples_) {
      s.t = q[0], s.rms = q[1], s.max = q[2], s.uy_rms = q[3], s.centre = q[4];
      s.n = static_cast<std::size_t>(q[5]);
      s.ux.assign(q + 6, q + 6 + n_y_);
      q += 6 + n_y_;
    }
    next_ = static_cast<int>(taken);
  }

  std::filesystem::path output_dir_;
  std::string job_key_;

private:
  static constexpr double L = 1.0, U = 1.0, rho0 = 1.0; // channel width, u_max, density
  const Params& prm_;
  int n_y_;
  double Re_, nu_, F_, t_visc_, t_end_, dx_;
  Particles<2>* p_ = nullptr;

  struct Sample {
    double t = 0.0, rms = 0.0, max = 0.0, uy_rms = 0.0, centre = 0.0;
    std::size_t n = 0;
    std::vector<double> ux; // per lattice row j (centre (j + 1/2) dx): mean u_x of its particles
  };
  std::vector<Sample> samples_;
  int next_ = 0; // the next of Morris et al.'s sample times

  // Metric and dataset suffix of sample k: 1..4, the last one (at t_end) "end".
  std::string tag(std::size_t k) const {
    return k + 1 == samples_.size() ? "end" : std::to_string(k + 1);
  }

  void take_sample(double t) {
    Sample s;
    s.t = t;
    std::vector<double> sum(n_y_, 0.0);
    std::vector<int> count(n_y_, 0);
    double e2 = 0.0, v2 = 0.0, centre = 0.0, centre_exact = 0.0;
    for (std::size_t i = 0; i < p_->size(); ++i) {
      if (p_->kind[i] != Kind::Fluid)
        continue;
      const double y = p_->r[i].y(), ux = p_->v[i].x();
      const double ue = poiseuille_velocity(std::clamp(y, 0.0, L), t, nu_, F_, L), e = ux - ue;
      e2 += e * e, v2 += p_->v[i].y() * p_->v[i].y(), ++s.n;
      s.max = std::max(s.max, std::abs(e));
      const int row = std::clamp(static_cast<int>(std::floor(y / dx_)), 0, n_y_ - 1);
      sum[row] += ux, ++count[row];
      if (std::abs(y - 0.5 * L) < dx_)
        centre += ux, centre_exact += ue;
    }
    const double n = static_cast<double>(std::max<std::size_t>(s.n, 1));
    s.rms = std::sqrt(e2 / n) / U, s.max /= U, s.uy_rms = std::sqrt(v2 / n) / U;
    s.centre = centre_exact > 0.0 ? centre / centre_exact - 1.0 : 0.0;
    for (int j = 0; j < n_y_; ++j)
      s.ux.push_back(count[j] ? sum[j] / count[j] : 0.0);
    samples_.push_back(std::move(s));
  }
};

} // namespace

CaseInfo make_poiseuille_case() {
  CaseInfo c;
  c.name = "poiseuille";
  c.description = "2D start-up of plane Poiseuille flow against the series solution (Morris, "
                  "Fox & Zhu 1997, section 4.1)";
  c.schemes = {"wcsph_tvf", "isph"};
  c.params = {
      {"n_y", ParamType::Int, std::int64_t{40}, "particles across the channel (dx = L / n_y)", 8.0,
       2000.0},
      {"Re",
       ParamType::Real,
       0.025,
       "Reynolds number u_max L / nu (Morris et al.: 0.025)",
       0.0,
       {},
       true},
      {"t_end_visc",
       ParamType::Real,
       1.0,
       "end time in units of the viscous time L^2 / nu",
       0.0,
       {},
       true},
      {"dt_factor", ParamType::Real, 0.1,
       "isph's fixed step dt = dt_factor h^2 / nu (wcsph_tvf takes its own dual-criteria steps)",
       0.0, 1.0, true},
  };
  add_loop_params(c.params); // output_interval (cases/loop_params.hpp)
  for (int k = 0; k < n_samples; ++k) {
    const std::string at =
        " at t = " + message_number(sample_times[k]) + " L^2/nu (Morris et al. Fig. 4)";
    c.metrics.push_back(
        {"ux_rms_err_" + std::to_string(k + 1), "RMS of u_x - series over the fluid / u_max" + at});
    c.metrics.push_back({"ux_max_err_" + std::to_string(k + 1),
                         "largest |u_x - series| over the fluid / u_max" + at});
  }
  c.metrics.insert(
      c.metrics.end(),
      {
          {"ux_rms_err_end", "RMS of u_x - series over the fluid / u_max at t_end"},
          {"ux_max_err_end", "largest |u_x - series| / u_max at t_end"},
          {"ux_rms_err_max", "largest ux_rms_err over the samples taken"},
          {"uy_rms_end", "RMS of u_y / u_max at t_end (exactly 0)"},
          {"centre_err_end", "u_x of the centre rows / series - 1 at t_end (> 0: too fast)"},
          {"t_end_visc", "time reached, in units of L^2 / nu"},
          {"n_fluid", "fluid particles"},
      });
  c.datasets = {
      {"profile_K", "K = 1..4, end: per lattice row y, mean ux, ux_exact (the series); "
                    "attribute t_K its time"},
      {"fields", "fluid particles at t_end: x, y, ux, uy, p"},
  };
  c.size = [](const Params& prm) {
    Poiseuille c(prm);
    return size_flow_case<2>(c, prm, "wcsph_tvf");
  };
  c.run = [](const Params& prm, const RunContext& ctx) {
    Poiseuille c(prm);
    c.output_dir_ = ctx.output_dir, c.job_key_ = ctx.job_key;
    return run_flow_case<2>(c, prm, ctx, "wcsph_tvf");
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_poiseuille_case()); // core/registry.hpp
} // namespace

} // namespace sph
