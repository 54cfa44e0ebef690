// Case "taylor_green": the 2D viscous Taylor-Green vortex of seed 002 (Wang, Haidn & Hu,
// section 4.1; Taylor & Green 1937), run with scheme "wcsph_tvf" (schemes/wcsph_tvf/).
//
// Set-up as SPHinXsys' test_2d_taylor_green (../shared/notes/tvf_equations.md, section 6):
// unit square [0, 1]^2, periodic in x and y, n_side^2 particles on the cell-centred lattice
// ((i + 1/2) dx, (j + 1/2) dx), dx = 1/n_side, m = rho0 dx^2, rho0 = 1, U = 1, mu = rho0 U L / Re,
// c0 = c0_factor U. Initial velocity u = -cos(2 pi x) sin(2 pi y), v = sin(2 pi x) cos(2 pi y),
// rho = rho0 (p = 0). With perturb > 0 every coordinate is shifted by (Rn - 0.5) perturb dx
// (Rn uniform in [0, 1), random seed `seed`; core/lattice.hpp), the velocity taken at the shifted
// position.
//
// Analytic solution: u(t) = e^{bt} u(0), b = -8 pi^2 / Re; |v|max(t) = e^{bt};
// E_k(t) = E_k(0) e^{2bt} (E_k(0) = 1/4 on the lattice).
//
// Metrics (all from this run):
//   ke_rate             slope of the least-squares line of ln E_k(t) over all advection steps
//   ke_rate_rel_err     |ke_rate - (-16 pi^2 / Re)| / (16 pi^2 / Re)
//   ke_rel_err_end      |E_k(t_end) / (E_k(0) e^{-16 pi^2 t_end / Re}) - 1|
//   ke_ratio_end        E_k(t_end) / (E_k(0) e^{-16 pi^2 t_end / Re}), signed: below 1 the run
//                       has lost energy, above 1 it has dissipated too little
//   umax_rel_err_end    ||v|max(t_end) / e^{b t_end} - 1|
//   l1_vel_err_end      mean_i ||v_i| - |v_exact(r_i)|| / mean_i |v_exact(r_i)| (PySPH's "l1")
//   tv_ratio_max        max over advection steps of max_i |Delta r^tvf_i| / Dt over max_i |v_i|:
//                       the over-correction indicator of seed 002, Fig. 1 (> 1: over-correction);
//                       Dt is the advection criterion's step (the last steps are shortened to
//                       land on t_end, which must not inflate a shift that does not scale with Dt)
//   sumW_spread_end     (max_i - min_i) sum_j W_ij / sigma0 at t_end, sigma0 the lattice value:
//                       uniformity of the particle distribution (0 on a perfect lattice)
//   sumW_rms_end        RMS of (sum_j W_ij / sigma0 - 1) at t_end
//   sumW_spread_max     largest sumW spread over the run
//   advection_steps, acoustic_steps, wall_s, time_per_particle_step_s (wall over particles x
//   acoustic sub-steps), time_per_particle_adv_step_s, n_particles
// With an output directory, <output_dir>/taylor_green.h5 holds the per-step series
// (series/t, ke, ke_exact, umax, umax_exact, tv_max, tv_ratio, sumW_spread), final fields and the
// job's typed parameters and key as root attributes (io/job_attributes.hpp).
// With a checkpoint directory the run saves its whole state every N steps / M seconds and on
// cancellation, and resumes from it bit for bit (tests/solver/test_wcsph_tvf.cpp).
#include "cases/case.hpp"
#include "cases/time_loop.hpp"
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "diagnostics/profiles.hpp"
#include "io/hdf5.hpp"
#include "io/job_attributes.hpp"
#include "io/particle_fields.hpp"
#include "schemes/wcsph_tvf/wcsph_tvf.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <omp.h>
#include <stdexcept>

namespace sph {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

Vec2 tgv_velocity(const Vec2& x, double factor) {
  return factor * Vec2(-std::cos(two_pi * x[0]) * std::sin(two_pi * x[1]),
                       std::sin(two_pi * x[0]) * std::cos(two_pi * x[1]));
}

class TaylorGreen final : public FlowCase<2> {
public:
  explicit TaylorGreen(const Params& prm) : prm_(prm) {
    n_ = static_cast<int>(get_int(prm, "n_side"));
    Re_ = get_real(prm, "Re"), t_end_ = get_real(prm, "t_end");
    b_ = -8.0 * std::numbers::pi * std::numbers::pi / Re_;
  }

  Flow<2> build(Particles<2>& p) override {
    p_ = &p;
    const double dx = L / n_, perturb = get_real(prm_, "perturb");
    const double support =
        kernel_support_factor(get_string(prm_, "kernel")) * (get_real(prm_, "h_over_dx") * dx);
    if (3.0 * support > L)
      throw std::invalid_argument("taylor_green: n_side = " + std::to_string(n_) +
                                  " is too small: the periodic box must hold 3 kernel supports");
    p.reserve(static_cast<std::size_t>(n_) * n_);
    UniformRandom rn(static_cast<std::uint64_t>(get_int(prm_, "seed")));
    for_each_lattice_point<2>({0, 0}, {n_, n_}, dx, [&](Vec2 x, const std::array<int, 2>&) {
      if (perturb > 0.0)
        for (int a = 0; a < 2; ++a)
          x[a] += (rn() - 0.5) * perturb * dx;
      const std::size_t i = p.add(x, rho0 * dx * dx, rho0);
      p.v[i] = tgv_velocity(x, U);
    });
    Flow<2> f;
    f.box.lo = Vec2::Zero(), f.box.hi = Vec2::Constant(L);
    f.box.periodic = {true, true};
    f.rho0 = rho0, f.U = U, f.L = L, f.Re = Re_, f.dx = dx;
    return f;
  }
  void start(FlowScheme<2>& s) override {
    // W(0) and sigma0 (sum_j W_ij on the perfect lattice) of the scheme's kernel, once.
    with_kernel<2>(s.kernel_name(), s.h(), [&](const auto& W) {
      W0_ = W.W(0.0);
      sigma0_ = wcsph_tvf::lattice_number_density<2>(W, L / n_);
    });
    ke0_ = kinetic_energy(*p_); // every particle is fluid
    s_ = {{0.0}, {ke0_}, {ke0_}, {umax()}, {U}, {0.0}, {0.0}, {0.0}};
  }
  double t_end() const override { return t_end_; }
  double speed_bound() const override { return 10.0 * U; }

  // The uniformity of the configuration the step starts from (what the step's density summation
  // measures: sum_j W_ij on the neighbour list built at the end of the previous step).
  void before_step(FlowScheme<2>& s, const LoopState&) override {
    double rms = 0.0;
    sumw_stats(number_density(s), spread_, rms);
  }
  bool after_step(FlowScheme<2>&, const LoopState& at, const StepStats& st) override {
    const double t = at.t, ke = kinetic_energy(*p_), um = umax(), spread = spread_;
    spread_max_ = std::max(spread_max_, spread);
    const double ratio = st.v_max > 0.0 ? st.tv_max / st.v_max : 0.0;
    tv_ratio_max_ = std::max(tv_ratio_max_, ratio);
    const double row[] = {
        t, ke, ke0_ * std::exp(2.0 * b_ * t), um, U * std::exp(b_ * t), st.tv_max, ratio, spread};
    for (std::size_t k = 0; k < s_.size(); ++k)
      s_[k].push_back(row[k]);
    return false;
  }

  void finish(FlowScheme<2>& s, const LoopState& at, RunResult& res) override {
    const double t = at.t;
    const auto& s_t = s_[0];
    const auto& s_ke = s_[1];
    // Least-squares slope of ln E_k against t.
    double st = 0.0, sy = 0.0, stt = 0.0, sty = 0.0;
    const double m = static_cast<double>(s_t.size());
    for (std::size_t k = 0; k < s_t.size(); ++k) {
      const double y = std::log(s_ke[k]);
      st += s_t[k], sy += y, stt += s_t[k] * s_t[k], sty += s_t[k] * y;
    }
    const double rate = (m * sty - st * sy) / (m * stt - st * st);
    const double rate_ex = 2.0 * b_;

    // Final distribution: sum_j W_ij at t_end on the neighbour list of the final positions.
    double spread_end = 0.0, rms_end = 0.0;
    sumw_stats(number_density(s), spread_end, rms_end);
    spread_max_ = std::max(spread_max_, spread_end);
    double l1 = 0.0, l1_ref = 0.0;
    const double fac = U * std::exp(b_ * t);
    for (std::size_t i = 0; i < p_->size(); ++i) {
      const double ve = tgv_velocity(p_->r[i], fac).norm();
      l1 += std::abs(p_->v[i].norm() - ve), l1_ref += ve;
    }
    const double ke_end = s_ke.back(), um_end = s_[3].back();
    const double wall = std::chrono::duration<double>(clock::now() - t0_).count();
    const double N = static_cast<double>(p_->size()), steps = static_cast<double>(at.steps);
    res.add("ke_rate_rel_err", std::abs(rate - rate_ex) / std::abs(rate_ex));
    const double ke_ratio = ke_end / (ke0_ * std::exp(2.0 * b_ * t));
    res.add("ke_rel_err_end", std::abs(ke_ratio - 1.0));
    res.add("ke_ratio_end", ke_ratio);
    res.add("umax_rel_err_end", std::abs(um_end / std::exp(b_ * t) - 1.0));
    res.add("l1_vel_err_end", l1 / l1_ref);
    res.add("tv_ratio_max", tv_ratio_max_);
    res.add("sumW_spread_end", spread_end);
    res.add("sumW_rms_end", rms_end);
    res.add("sumW_spread_max", spread_max_);
    res.add("ke_rate", rate);
    res.add("ke_rate_exact", rate_ex);
    res.add("ke_end", ke_end);
    res.add("umax_end", um_end);
    res.add("t_end", t);
    res.add("advection_steps", steps);
    res.add("wall_s", wall);
    res.add("time_per_particle_adv_step_s", wall / (N * steps));
    if (!output_dir_.empty()) {
      io::H5Writer w(output_dir_ / "taylor_green.h5");
      io::write_job_attributes(w, "taylor_green", prm_, job_key_); // typed, with the job key
      w.write_columns("series", names(), s_);
      io::write_fluid_fields(w, *p_); // every particle is fluid
      w.close();
    }
  }

  std::vector<std::string> state_names() const override {
    std::vector<std::string> n{"tg/loop"};
    for (const auto& x : names())
      n.push_back("tg/series/" + x);
    return n;
  }
  void save_state(StateArrays& out) const override {
    out["tg/loop"] = {tv_ratio_max_, spread_max_};
    for (std::size_t k = 0; k < s_.size(); ++k)
      out["tg/series/" + names()[k]] = s_[k];
  }
  void load_state(const StateArrays& in) override {
    const auto& a = in.at("tg/loop");
    io::expect_state_size(a, 2, "checkpoint array tg/loop");
    tv_ratio_max_ = a[0], spread_max_ = a[1];
    for (std::size_t k = 0; k < s_.size(); ++k)
      s_[k] = in.at("tg/series/" + names()[k]);
  }

  std::filesystem::path output_dir_;
  std::string job_key_;

private:
  using clock = std::chrono::steady_clock;
  static constexpr double L = 1.0, U = 1.0, rho0 = 1.0;
  const Params& prm_;
  int n_;
  double Re_, t_end_, b_;
  Particles<2>* p_ = nullptr;
  double ke0_ = 0.0, tv_ratio_max_ = 0.0, spread_max_ = 0.0, spread_ = 0.0;
  double W0_ = 0.0, sigma0_ = 1.0;
  std::vector<double> sw_;             // number_density's buffer
  std::vector<std::vector<double>> s_; // the series, named by names()
  clock::time_point t0_ = clock::now();

  static const std::vector<std::string>& names() {
    static const std::vector<std::string> n{"t",          "ke",     "ke_exact", "umax",
                                            "umax_exact", "tv_max", "tv_ratio", "sumW_spread"};
    return n;
  }
  double umax() const {
    double v = 0.0;
    for (std::size_t i = 0; i < p_->size(); ++i)
      v = std::max(v, p_->v[i].norm());
    return v;
  }
  // Sum_j W_ij (self term included) of every particle on the scheme's current neighbour list
  // (into a buffer kept across steps).
  const std::vector<double>& number_density(const FlowScheme<2>& s) {
    const auto& nl = s.neighbors();
    sw_.resize(p_->size());
    for (std::size_t i = 0; i < p_->size(); ++i) {
      double w = W0_;
      for (std::uint32_t k = nl.offset[i]; k < nl.offset[i + 1]; ++k)
        w += nl.W[k];
      sw_[i] = w;
    }
    return sw_;
  }
  // Spread and RMS of sum_j W_ij / sigma0 - 1 over the particles, sigma0 the perfect lattice's.
  void sumw_stats(const std::vector<double>& w, double& spread, double& rms) const {
    double lo = 1e300, hi = -1e300, sq = 0.0;
    for (double x : w) {
      const double y = x / sigma0_;
      lo = std::min(lo, y), hi = std::max(hi, y), sq += (y - 1.0) * (y - 1.0);
    }
    spread = hi - lo;
    rms = std::sqrt(sq / static_cast<double>(w.size()));
  }
};

} // namespace

CaseInfo make_taylor_green_case() {
  CaseInfo c;
  c.name = "taylor_green";
  c.description = "2D Taylor-Green vortex, unit periodic square: kinetic-energy decay and "
                  "transport-velocity over-correction (Wang, Haidn & Hu 2024, section 4.1)";
  c.schemes = {"wcsph_tvf"};
  c.params = {
      {"n_side", ParamType::Int, std::int64_t{100}, "particles per side (dx = 1 / n_side)", 8.0,
       4000.0},
      {"Re", ParamType::Real, 100.0, "Reynolds number U L / nu (U = L = 1)", 0.0, {}, true},
      {"t_end", ParamType::Real, 5.0, "end time", 0.0, {}, true},
      {"perturb", ParamType::Real, 0.0,
       "random shift of the initial lattice, fraction of dx (0: perfect lattice)", 0.0, 1.0},
      {"seed", ParamType::Int, std::int64_t{1}, "random seed of the perturbation", 0.0, {}},
  };
  add_loop_params(c.params); // output_interval (cases/loop_params.hpp)
  c.metrics = {
      {"ke_rate_rel_err",
       "relative error of the fitted kinetic-energy decay rate against -16 pi^2 / Re"},
      {"ke_rel_err_end", "|E_k / E_k,exact - 1| at t_end"},
      {"ke_ratio_end", "E_k / E_k,exact at t_end (< 1: energy lost, > 1: too little dissipated)"},
      {"umax_rel_err_end", "|max |v| / its analytic value - 1| at t_end"},
      {"l1_vel_err_end", "sum_i ||v_i| - |v_exact(r_i)|| / sum_i |v_exact(r_i)| at t_end"},
      {"tv_ratio_max",
       "largest transport-velocity magnitude over the flow's max |v| (> 1: over-correction)"},
      {"sumW_spread_end", "max - min of sum_j W_ij over sigma0 (the lattice's) at t_end"},
      {"sumW_rms_end", "RMS deviation of sum_j W_ij / sigma0 from 1 at t_end"},
      {"sumW_spread_max", "largest sumW spread over the run"},
      {"ke_rate", "fitted decay rate of ln E_k"},
      {"ke_rate_exact", "analytic decay rate -16 pi^2 / Re (U = L = 1)"},
      {"ke_end", "kinetic energy at t_end"},
      {"umax_end", "max |v| at t_end"},
      {"t_end", "simulated time reached"},
      {"advection_steps", "advection steps (eq. 10's step)"},
      {"wall_s", "wall seconds of the time loop"},
      {"time_per_particle_adv_step_s", "wall seconds per particle and advection step"},
  };
  c.datasets = {
      {"series", "per sample: t, ke, ke_exact, umax, umax_exact, tv_max, tv_ratio, sumW_spread"},
      {"fields", "particles at t_end: x, y, ux, uy, p (the vortex in ParaView: docs/fields.md)"},
  };
  c.size = [](const Params& prm) {
    TaylorGreen c(prm);
    return size_flow_case<2>(c, prm, "wcsph_tvf");
  };
  c.run = [](const Params& prm, const RunContext& ctx) {
    TaylorGreen tg(prm);
    tg.output_dir_ = ctx.output_dir, tg.job_key_ = ctx.job_key;
    return run_flow_case<2>(tg, prm, ctx, "wcsph_tvf");
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_taylor_green_case()); // core/registry.hpp
} // namespace

} // namespace sph
