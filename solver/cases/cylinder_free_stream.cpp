// Case "cylinder_free_stream": 2D flow past a circular cylinder in a free stream at Re = 100 (seed
// 002: Wang, Haidn & Hu, section 4.4 and Table 2, at a single resolution), run with the scheme
// "wcsph_tvf" (schemes/wcsph_tvf/).
//
// Units: D = 1, U = 1, rho0 = 1, mu = rho0 U D / Re, c0 = c0_factor U; times in D/U (the seed's
// set-up has D = 2: its t_end = 200 is 100 D/U here).
// Geometry: box [0, L] x [0, H], L = domain_length D, H = domain_height D (defaults 19 D x 16 D),
// cylinder centre (upstream_length D, H / 2) (9 D). Fluid on the cell-centred lattice of spacing
// dx = D / D_over_dx outside the cylinder; the cylinder is wall particles at rest (the scheme's
// walls: no-slip by 2 v_wall - v_i, wall pressure extrapolated) on rings of radii
// R - (k + 1/2) dx, round(2 pi r_k / dx) particles each, one kernel support deep.
// Free stream: the box is periodic in x and y; relaxation (sponge) zones pull the velocity towards
// the free stream U_inf(t) = (U(t), 0): at the right end, x in [L - L_s, L], L_s = sponge_length D,
// and along the top and bottom, within L_y = lateral_sponge_length D of y = 0 and y = H,
//   v_i <- U_inf + (v_i - U_inf) exp(-sigma xi^2 Dt),  sigma = sponge_rate U/D,
//   xi = max((x_i - (L - L_s)) / L_s, (|y_i - H/2| - (H/2 - L_y)) / L_y, 0),
// so the wake is erased before the fluid re-enters at x = 0 as a uniform stream.
// SPHinXsys' mr_free_stream_around_cylinder (the seed's set-up) uses a 38 x 16 box with D = 2
// (19 D x 8 D) with an emitter, a disposer and a far-field condition that lets fluid leave through
// the top and bottom. A periodic box cannot: the flow displaced by the cylinder stays within H,
// as between slip walls, so the default height is 16 D (at D/dx = 10: C_D 1.84 with H = 8 D,
// 1.68 with 16 D; docs/tvf.md).
// Open boundaries (boundary = "free_stream"; the default "periodic_sponge" is the box above):
// fluid in [0, L] x [0, H] outside the cylinder, an emitter upstream of x = 0 at U_inf(t), a
// disposer downstream of x = L and the Lagrangian free-stream boundary of Zhang et al. 2023 on the
// top and bottom (boundaries/free_stream_domain.hpp, as SPHinXsys' test_2d_free_stream_around_
// cylinder); no sponge zones, fluid farther than lateral_margin D outside H deleted. SPHinXsys'
// domain is 17 D x 8 D from its emitter with the cylinder 7 D downstream of it (D = 2: x in
// [-4, 30], y in [0, 16], centre (10, 8)): domain_length = 17, domain_height = 8,
// upstream_length = 7 here. With refinement_band b > 0 the band is emitted fine and its edges
// split and merge particles (boundaries/refinement.hpp): the level follows the position.
// Variable resolution (seed 002 section 4.4; refinement_band b > 0): the band |y - H/2| < b along
// the whole box (SPHinXsys' refinement region is such a band) holds particles of spacing
// dx = D / D_over_dx, the rest spacing 2 dx (one refinement level, as SPHinXsys); each particle
// keeps its mass rho0 dx_i^2 and smoothing length h_i = h_over_dx dx_i (schemes/wcsph_tvf:
// pair kernels with (h_i + h_j)/2, mass summation, TVF shift alpha h_i^2). In the periodic box
// there is no splitting or merging: particles that leave the band keep their size and the band
// re-enters at x = 0 as it left (boundary = free_stream: see above).
// Start: with ramp_time T > 0 the fluid starts at rest and U_inf(t) = U (1 - cos(pi t / T)) / 2
// for t < T (SPHinXsys: T = 2 with D = 2), the whole box driven by the uniform body acceleration
// dU_inf/dt; T = 0 starts impulsively (u = U everywhere). At t = T a transverse velocity nudge
// perturbation U exp(-|x - x_c - (D, 0)|^2 / D^2) breaks the mirror symmetry once (shedding then
// starts within a few tens of D/U instead of hundreds; the periodic state does not depend on it).
// Forces: F = the fluid's force on the wall particles, the reaction of the wall pairs' pressure,
// viscous and dissipation forces (wcsph_tvf::Scheme::force_on_walls), once per advection step;
// C_D = 2 F_x / (rho0 U^2 D), C_L = 2 F_y / (rho0 U^2 D) (seed 002 eq. 18).
// Metrics (after t >= settle_fraction t_end; cases/shedding.hpp): cd_mean, cl_rms, St (= f D / U of
// C_L, seed 002 section 4.4), St_spectral, st_cycles, st_period_cv, cd_amplitude, cl_amplitude
// (Table 2: "C_D +- amplitude", "C_L"), t_average; tv_ratio_max (max over the averaging time of
// the TVF shift over max |v|), sumW_spread_end (uniformity of the fluid at t_end, as the
// Taylor-Green case; fluid next to the cylinder counts its wall partners), costs: wall_s,
// advection_steps, acoustic_steps, time_per_particle_step_s, n_particles.
// HDF5 (<output_dir>/cylinder_free_stream.h5): series/{t,cd,cl} (one sample per sample_interval,
// each the mean of the advection steps in it) and fields/{x,y,ux,uy,p} at t_end; root attributes:
// the job's parameters typed, its key (io/job_attributes.hpp) and t_settle.
// Time loop: the shared one (cases/time_loop.hpp); the smooth start's body acceleration is set
// before each step, the sponge zones, the nudge, the force sample and the divergence test (max |u|
// after the sponge, a force not finite) follow each step. A diverged run reports t_stop.
// Checkpoints: particles, series (cfs/t, cd, cl, cdv), the partial sample bin and the case's
// scalars (cfs/loop), the scheme's state; resumes bit for bit (tests/runner/test_checkpoint.cpp).
#include "boundaries/free_stream_domain.hpp"
#include "cases/case.hpp"
#include "cases/shedding.hpp"
#include "cases/time_loop.hpp"
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "diagnostics/signal.hpp"
#include "io/job_attributes.hpp"
#include "io/particle_fields.hpp"
#include "schemes/wcsph_tvf/wcsph_tvf.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace sph {
namespace {

using V2 = Vec<2>;
constexpr double pi = std::numbers::pi;

class CylinderFreeStream final : public FlowCase<2> {
public:
  CylinderFreeStream(const Params& prm, const RunContext& ctx) : prm_(prm), ctx_(ctx) {
    Re_ = get_real(prm, "Re"), t_end_ = get_real(prm, "t_end");
    dx_ = 1.0 / get_real(prm, "D_over_dx");
    t_settle_ = get_real(prm, "settle_fraction") * t_end_;
    ramp_ = get_real(prm, "ramp_time"), nudge_ = get_real(prm, "perturbation");
    Ls_ = get_real(prm, "sponge_length"), sigma_ = get_real(prm, "sponge_rate");
    Ly_ = get_real(prm, "lateral_sponge_length");
    speed_bound_ = get_real(prm, "speed_bound");
    sample_interval_ = get_real(prm, "sample_interval");
    next_sample_ = sample_interval_;
    nudged_ = !(nudge_ > 0.0);
    open_ = get_string(prm, "boundary") == "free_stream";
  }

  Flow<2> build(Particles<2>& p) override {
    p_ = &p;
    const double dx = dx_;
    // Variable resolution: spacing dx within the band |y - H/2| < b, 2 dx outside (b > 0).
    const double band = get_real(prm_, "refinement_band");
    const double dxc = band > 0.0 ? 2.0 * dx : dx; // the coarse lattice
    const int nx = static_cast<int>(std::lround(get_real(prm_, "domain_length") / dxc));
    const int ny =
        band > 0.0 ? 2 * static_cast<int>(std::lround(get_real(prm_, "domain_height") / (2 * dxc)))
                   : static_cast<int>(std::lround(get_real(prm_, "domain_height") / dxc));
    const int nband = static_cast<int>(std::lround(band / dxc)); // band half-width in coarse rows
    L_ = nx * dxc, H_ = ny * dxc;
    c_ = V2(get_real(prm_, "upstream_length"), 0.5 * H_);
    x_sponge_ = L_ - Ls_;

    const double h = get_real(prm_, "h_over_dx") * dx;
    const double support = kernel_support_factor(get_string(prm_, "kernel")) * h;
    if (open_)
      return build_open(p, nx, ny, dxc, nband, h, support);
    if (band > 0.0 && (nband * dxc < R + support || nband * dxc > 0.5 * H_ - Ly_))
      throw std::invalid_argument(
          "cylinder_free_stream: refinement_band must hold the cylinder and a kernel support and "
          "stay outside the lateral sponge zones (0.5 + 2.6 / D_over_dx <= refinement_band <= "
          "domain_height / 2 - lateral_sponge_length)");
    if (c_[0] - R < 2.0 * support || c_[0] + R + D > x_sponge_ || R + D > 0.5 * H_ - Ly_)
      throw std::invalid_argument(
          "cylinder_free_stream: the cylinder must lie two kernel supports inside the box, one D "
          "ahead of the sponge zones (upstream_length + 1.5 <= domain_length - sponge_length, "
          "1.5 + lateral_sponge_length <= domain_height / 2)");

    const double m = rho0 * dx * dx;
    add_cylinder(p, support);
    const std::size_t n_wall = p.size();
    for_each_lattice_point<2>(
        {0, 0}, {nx, ny}, dxc, [&](const V2& x, const std::array<int, 2>& ij) {
          auto add = [&](const V2& y, double d) {
            if ((y - c_).norm() >= R)
              p.v[p.add(y, rho0 * d * d, rho0)] = V2(u_inf(0.0), 0.0);
          };
          if (band > 0.0 && std::abs(ij[1] + 0.5 - 0.5 * ny) < nband) // a coarse cell of the band
            for (int s = 0; s < 4; ++s)
              add(refinement::fine_point<2>(x, dxc, s), dx);
          else
            add(x, dxc);
        });
    Flow<2> f;
    f.v_wall = p.add_vector("v_wall"); // zero: the cylinder is at rest
    if (band > 0.0) {
      f.h = p.add_scalar("h");
      for (std::size_t i = 0; i < p.size(); ++i) // h = h_over_dx times the particle's spacing
        p.scalar(f.h)[i] = i < n_wall ? h : h * std::sqrt(p.m[i] / m);
    }
    f.box.lo = V2::Zero(), f.box.hi = V2(L_, H_);
    f.box.periodic = {true, true};
    f.rho0 = rho0, f.U = U, f.L = D, f.Re = Re_, f.dx = dx;
    return f;
  }
  double t_end() const override { return t_end_; }
  // The case's own test after the sponge zones (after_step).
  double speed_bound() const override { return std::numeric_limits<double>::infinity(); }

  // The smooth start: the whole box driven by dU_inf/dt; the open boundaries' emitter and
  // disposer.
  void before_step(FlowScheme<2>& s, const LoopState& at) override {
    if (open_ && dom_->before_step(*p_, at.t + 0.5 * s.stable_dt()))
      s.particles_changed();
    s.set_body_acceleration(V2(du_inf(at.t), 0.0));
  }
  bool after_step(FlowScheme<2>& s, const LoopState& at, const StepStats& info) override {
    Particles<2>& p = *p_;
    const double t = at.t;
    // Sponge zone: relax towards the free stream.
    const V2 vinf(u_inf(t), 0.0);
    double vmax = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.kind[i] != Kind::Fluid)
        continue;
      const double xi =
          open_ ? 0.0
                : std::max(
                      {(p.r[i][0] - x_sponge_) / Ls_,
                       Ly_ > 0.0 ? (std::abs(p.r[i][1] - 0.5 * H_) - (0.5 * H_ - Ly_)) / Ly_ : 0.0,
                       0.0});
      if (xi > 0.0)
        p.v[i] = vinf + std::exp(-sigma_ * xi * xi * info.dt) * (p.v[i] - vinf);
      const double v2 = p.v[i].squaredNorm();
      vmax = std::max(vmax, std::isfinite(v2) ? std::sqrt(v2) : 1e300);
    }
    if (!nudged_ && t >= ramp_) {
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Fluid)
          p.v[i][1] += nudge_ * U * std::exp(-(p.r[i] - c_ - V2(D, 0.0)).squaredNorm() / (D * D));
      nudged_ = true;
    }
    V2 Fv;
    const V2 F = s.force_on_walls(&Fv);
    if (vmax > speed_bound_ * U || !std::isfinite(F.squaredNorm()))
      throw std::runtime_error("max speed " + std::to_string(vmax));
    if (t >= t_settle_ && info.v_max > 0.0)
      tv_ratio_max_ = std::max(tv_ratio_max_, info.tv_max / info.v_max);
    bin_.t += t, bin_.cd += F[0] / q, bin_.cl += F[1] / q, bin_.cdv += Fv[0] / q, bin_.n += 1;
    if (t >= next_sample_ * (1.0 - 1e-12)) {
      flush_bin();
      while (next_sample_ <= t * (1.0 + 1e-12))
        next_sample_ += sample_interval_;
    }
    return false;
  }

  void finish(FlowScheme<2>& s, const LoopState& at, RunResult& res) override {
    const Particles<2>& p = *p_;
    if (bin_.n > 0)
      flush_bin();
    const double wall = wall_so_far();

    // The force series carry SPH particle noise (fluid particles sliding past the wall rings, the
    // acoustic modes of the box) at frequencies of ~1-3 U/D: the shedding metrics use the
    // Gaussian low-pass of the series (cl_rms_raw: the unfiltered lift's).
    const double sigma_f = get_real(prm_, "force_filter_sigma");
    const std::vector<double> cd_f = diag::gaussian_lowpass(ts_, cds_, sigma_f);
    const std::vector<double> cl_f = diag::gaussian_lowpass(ts_, cls_, sigma_f);
    const AveragingWindow w = add_shedding_metrics(ts_, cd_f, cl_f, t_settle_, D / U, res);
    res.add("t_average", w.t1 - w.t0);
    const double cl_raw = diag::time_rms(ts_, cls_, w.t0, w.t1);
    if (std::isfinite(cl_raw))
      res.add("cl_rms_raw", cl_raw);
    const double cd_viscous = diag::time_mean(ts_, cdvs_, w.t0, w.t1);
    if (std::isfinite(cd_viscous))
      res.add("cd_viscous_mean", cd_viscous);
    res.add("tv_ratio_max", tv_ratio_max_);
    {
      // Sum_j W_ij (self term included) on the neighbour list of the final positions, over
      // sigma0, its value on the perfect lattice of spacing dx.
      const auto& nl = s.neighbors();
      double W0 = 0.0, sigma0 = 0.0;
      with_kernel<2>(s.kernel_name(), s.h(), [&](const auto& W) {
        W0 = W.W(0.0);
        sigma0 = wcsph_tvf::lattice_number_density<2>(W, dx_);
      });
      double lo = 1e300, hi = -1e300;
      const int surf = p.find_scalar("surface_indicator"); // open boundaries: bulk fluid only
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Fluid && (surf < 0 || p.scalar(surf)[i] == 0.0)) {
          double sw = W0;
          for (std::uint32_t k = nl.offset[i]; k < nl.offset[i + 1]; ++k)
            sw += nl.W[k];
          lo = std::min(lo, sw), hi = std::max(hi, sw);
        }
      res.add("sumW_spread_end", (hi - lo) / sigma0);
    }
    std::size_t n_fluid = 0;
    for (const Kind k : p.kind)
      n_fluid += k == Kind::Fluid;
    res.add("advection_steps", static_cast<double>(at.steps));
    res.add("wall_s", wall);
    res.add("n_fluid", static_cast<double>(n_fluid));
    if (open_) {
      res.add("mass_lost", dom_->mass_lost());
      if (const auto* lv = dom_->levels()) { // cumulative: particles split, groups merged
        res.add("particle_splits", static_cast<double>(lv->splits()));
        res.add("particle_merges", static_cast<double>(lv->merges()));
      }
    }

    // The job's parameters typed and its key (io/job_attributes.hpp), and the settling time.
    if (auto h5 = io::open_job_output(ctx_, "cylinder_free_stream", prm_)) {
      h5->attribute("t_settle", t_settle_);
      h5->write_columns("series", {"t", "cd", "cl", "cd_viscous", "cd_filtered", "cl_filtered"},
                        {ts_, cds_, cls_, cdvs_, cd_f, cl_f});
      io::write_fluid_fields(*h5, p);
      h5->close();
    }
  }

  std::vector<std::string> state_names() const override {
    std::vector<std::string> n{"cfs/t", "cfs/cd", "cfs/cl", "cfs/cdv", "cfs/loop"};
    if (open_)
      for (auto& k : dom_->state_names("cfs"))
        n.push_back(k);
    return n;
  }
  void save_state(StateArrays& out) const override {
    if (open_)
      dom_->save_state(out, "cfs");
    out["cfs/t"] = ts_, out["cfs/cd"] = cds_, out["cfs/cl"] = cls_, out["cfs/cdv"] = cdvs_;
    out["cfs/loop"] = {bin_.t,       bin_.cd,      bin_.cl,       bin_.cdv,
                       bin_.n,       next_sample_, tv_ratio_max_, nudged_ ? 1.0 : 0.0,
                       wall_so_far()};
  }
  void load_state(const StateArrays& in) override {
    if (open_)
      dom_->load_state(in, "cfs");
    ts_ = in.at("cfs/t"), cds_ = in.at("cfs/cd"), cls_ = in.at("cfs/cl");
    cdvs_ = in.at("cfs/cdv");
    const auto& loop = in.at("cfs/loop");
    io::expect_state_size(loop, 9, "cylinder_free_stream: checkpoint loop state");
    bin_ = Bin{loop[0], loop[1], loop[2], loop[3], loop[4]};
    next_sample_ = loop[5], tv_ratio_max_ = loop[6], nudged_ = loop[7] != 0.0;
    wall_before_ = loop[8];
  }

private:
  using clock = std::chrono::steady_clock;
  static constexpr double D = 1.0, R = 0.5 * D, U = 1.0, rho0 = 1.0;
  static constexpr double q = 0.5 * rho0 * U * U * D;
  struct Bin {
    double t = 0, cd = 0, cl = 0, cdv = 0, n = 0;
  };

  const Params& prm_;
  const RunContext& ctx_;
  double Re_, t_end_, dx_, t_settle_, ramp_, nudge_, Ls_, sigma_, Ly_, speed_bound_;
  double sample_interval_;
  double L_ = 0.0, H_ = 0.0, x_sponge_ = 0.0;
  V2 c_ = V2::Zero();
  Particles<2>* p_ = nullptr;

  std::vector<double> ts_, cds_, cls_, cdvs_;
  Bin bin_;
  double next_sample_ = 0.0, tv_ratio_max_ = 0.0, wall_before_ = 0.0;
  bool nudged_ = true;
  bool open_ = false; // boundary = "free_stream"
  std::unique_ptr<open_boundary::FreeStreamDomain<2>> dom_;
  clock::time_point t_start_ = clock::now();

  // The cylinder rings (outermost first) as wall particles.
  void add_cylinder(Particles<2>& p, double support) const {
    const double dx = dx_, m = rho0 * dx * dx;
    for (int k = 0;; ++k) {
      const double rk = R - (k + 0.5) * dx;
      if (rk <= 0.25 * dx || (k + 0.5) * dx > support)
        break;
      const int n = std::max(1, static_cast<int>(std::lround(2.0 * pi * rk / dx)));
      for (int a = 0; a < n; ++a) {
        const double th = (a + 0.5) * 2.0 * pi / n;
        p.add(c_ + rk * V2(-std::cos(th), std::sin(th)), m, rho0, Kind::Wall);
      }
    }
  }

  // boundary = "free_stream": the cylinder, the fluid lattice of [0, L] x [0, H] outside it and
  // the open boundaries (boundaries/free_stream_domain.hpp).
  // nx x ny cells of the coarse spacing dxc (= dx_ without a band); the fine band holds nband
  // coarse rows each side of H / 2.
  Flow<2> build_open(Particles<2>& p, int nx, int ny, double dxc, int nband, double h,
                     double support) {
    if (nband > 0 && (nband * dxc < R + support || nband * dxc > 0.5 * H_ - dxc))
      throw std::invalid_argument(
          "cylinder_free_stream: refinement_band must hold the cylinder and a kernel support and "
          "leave a coarse row each side (0.5 + 2.6 / D_over_dx <= refinement_band <= "
          "domain_height / 2 - 2 / D_over_dx)");
    if (c_[0] - R < 2.0 * support || c_[0] + R + D > L_ || R + D > 0.5 * H_)
      throw std::invalid_argument("cylinder_free_stream: the cylinder must lie one D inside the "
                                  "open domain (upstream_length + 1.5 <= domain_length, "
                                  "domain_height >= 3)");
    add_cylinder(p, support);
    open_boundary::FreeStreamDomain<2>::Config c;
    c.n = {nx, ny}, c.dx = dxc, c.rho0 = rho0, c.h = h * dxc / dx_, c.band_rows = nband;
    c.layers = static_cast<int>(std::ceil(support / dx_ - 1e-9)) + 1;
    c.lateral_margin = get_real(prm_, "lateral_margin");
    c.u_in = [this](const V2&, double t) { return V2(u_inf(t), 0.0); };
    dom_ = std::make_unique<open_boundary::FreeStreamDomain<2>>(c);
    dom_->fill(p, [&](const V2& x) { return (x - c_).norm() >= R; });
    Flow<2> f;
    f.v_wall = p.add_vector("v_wall"); // zero: the cylinder is at rest
    dom_->attach(p, f);
    f.rho0 = rho0, f.U = U, f.L = D, f.Re = Re_, f.dx = dx_;
    return f;
  }

  double u_inf(double t) const {
    return t < ramp_ ? 0.5 * U * (1.0 - std::cos(pi * t / ramp_)) : U;
  }
  double du_inf(double t) const {
    return t < ramp_ ? 0.5 * U * pi / ramp_ * std::sin(pi * t / ramp_) : 0.0;
  }
  double wall_so_far() const {
    return wall_before_ + std::chrono::duration<double>(clock::now() - t_start_).count();
  }
  void flush_bin() {
    ts_.push_back(bin_.t / bin_.n), cds_.push_back(bin_.cd / bin_.n);
    cls_.push_back(bin_.cl / bin_.n);
    cdvs_.push_back(bin_.cdv / bin_.n);
    bin_ = Bin{};
  }
};

} // namespace

static ParamSpec boundary_spec() {
  ParamSpec s{"boundary", ParamType::String, std::string("periodic_sponge"),
              "periodic_sponge: periodic box with relaxation zones; free_stream: emitter inflow, "
              "disposer outflow, Lagrangian free-stream top and bottom (Zhang et al. 2023)"};
  s.choices = {"periodic_sponge", "free_stream"};
  s.neutral_default = true;
  return s;
}

CaseInfo make_cylinder_free_stream_case() {
  CaseInfo c;
  c.name = "cylinder_free_stream";
  c.description = "2D flow past a cylinder in a free stream (periodic box with a sponge zone), "
                  "C_D, C_L, St (Wang, Haidn & Hu 2024, section 4.4, Table 2)";
  c.schemes = {"wcsph_tvf"};
  c.params = {
      {"Re", ParamType::Real, 100.0, "Reynolds number U D / nu", 0.0, 1e4, true},
      {"D_over_dx", ParamType::Real, 10.0, "particles per cylinder diameter D / dx", 4.0, 200.0},
      {"t_end", ParamType::Real, 100.0, "simulated time in D / U", 0.0, 1e5, true},
      {"settle_fraction", ParamType::Real, 0.5, "averages and St use t >= settle_fraction * t_end",
       0.0, 0.99},
      {"domain_length", ParamType::Real, 19.0, "periodic box length L in D (sponge included)", 4.0,
       1000.0},
      {"domain_height", ParamType::Real, 16.0, "periodic box height H in D", 2.0, 1000.0},
      {"upstream_length", ParamType::Real, 9.0,
       "x of the cylinder centre from the box's left end, in D", 1.0, 1000.0},
      {"sponge_length", ParamType::Real, 3.0,
       "relaxation zone towards the free stream at the box's right end, in D", 0.5, 1000.0},
      {"sponge_rate", ParamType::Real, 5.0,
       "relaxation rate at the end of the sponge zone, in U / D (rises as xi^2 across it)", 0.0,
       1e4},
      {"lateral_sponge_length", ParamType::Real, 1.0,
       "relaxation zones towards the free stream along the top and bottom, in D (0: none)", 0.0,
       1000.0},
      {"ramp_time", ParamType::Real, 1.0,
       "smooth start: free stream U (1 - cos(pi t / T)) / 2 up to T, in D/U (0: impulsive)", 0.0,
       1e4},
      {"perturbation", ParamType::Real, 0.05,
       "transverse velocity nudge behind the cylinder at t = ramp_time, in U (breaks the symmetry)",
       0.0, 1.0},
      {"refinement_band", ParamType::Real, 0.0,
       "variable resolution: half-width b in D of the band |y - H/2| < b at D_over_dx, the rest "
       "at half that resolution (0: uniform)",
       0.0, 1000.0},
      {"force_filter_sigma", ParamType::Real, 0.25,
       "Gaussian low-pass of the force series before the shedding metrics, standard deviation in "
       "D/U (0: none; 0.25 keeps 97 % of a St = 0.165 lift, 29 % at 1 U/D, 0.7 % at 2 U/D)",
       0.0, 100.0},
      {"speed_bound", ParamType::Real, 5.0, "diverged when max |u| exceeds this many U", 1.0, 1e6},
      boundary_spec(),
      {"lateral_margin",
       ParamType::Real,
       2.0,
       "boundary = free_stream: fluid farther than this outside the top and bottom is deleted, "
       "in D",
       0.0,
       1000.0,
       false,
       {},
       true,
       true},
      {"sample_interval", ParamType::Real, 0.05,
       "force series sample interval in D/U (each sample averages the steps of its interval)", 0.0,
       1e3, true},
  };
  add_loop_params(c.params); // output_interval (cases/loop_params.hpp)
  c.size = [](const Params& prm) {
    const RunContext none;
    CylinderFreeStream c(prm, none);
    return size_flow_case<2>(c, prm, "wcsph_tvf");
  };
  c.run = [](const Params& prm, const RunContext& ctx) {
    CylinderFreeStream cfs(prm, ctx);
    return run_flow_case<2>(cfs, prm, ctx, "wcsph_tvf");
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_cylinder_free_stream_case()); // core/registry.hpp
} // namespace

} // namespace sph
