// Case "fsi_beam": flow-induced vibration of an elastic beam attached behind a rigid cylinder in a
// channel, the Turek & Hron FSI2 benchmark (S. Turek, J. Hron, "Proposal for numerical
// benchmarking of fluid-structure interaction between an elastic object and laminar
// incompressible flow", in: Fluid-Structure Interaction, LNCSE 53, Springer, 2006, pp. 371-385;
// seed 002: Wang, Haidn & Hu, section 4.3 and its table, refs. [36-38]). Fluid: scheme
// "wcsph_tvf"; solid: scheme "elastic_solid" (docs/solid.md) on its own particle set; the two
// coupled by coupling/fsi.hpp (docs/fsi.md).
//
// Geometry (Turek & Hron, section 2; units m, s, with rho_f = 1 and U = 1, so that every quantity
// is the benchmark's dimensionless one): channel [0, 2.5] x [0, 0.41]; cylinder centre C = (0.2,
// 0.2), radius R = 0.05 (D = 0.1); beam [0.2 + sqrt(R^2 - 0.01^2), 0.6] x [0.19, 0.21] (length
// 0.35 from the cylinder's front point x = 0.25, thickness 0.02), clamped in the cylinder; tip A =
// (0.6, 0.2).
// Inflow (their eq. 1 and the FSI2 start): u(0, y, t) = 1.5 U y (H - y) / (H/2)^2 ramp(t),
// ramp(t) = (1 - cos(pi t / T)) / 2 for t < T = ramp_time (2), 1 after; U = 1 the mean inflow.
// Outflow at x = 2.5; no-slip top and bottom walls and cylinder.
// FSI2 parameters (Turek & Hron Table 2, and seed 002 section 4.3): rho_s / rho_f = 10 (1e4 / 1e3
// kg/m^3), Re = U D / nu_f = 100 (nu_f = 1e-3), Poisson ratio nu_s = 0.4, shear modulus mu_s =
// 0.5e6 Pa, so E = 2 mu_s (1 + nu_s) = 1.4e6 Pa and E / (rho_f U^2) = 1.4e3.
// Results there (FSI2, point A; quoted from memory of their table, not re-checked): u_y = 1.23e-3
// +- 8.06e-2 m at 2.0 Hz, u_x = -1.458e-2 +- 1.25e-2 m at 3.8 Hz; the seed's table
// (studies/reference/wang2024_fsi_beam_tip.csv): y amplitude 0.830 D and frequency f D / U = 0.190
// for Turek & Hron, 0.790 and 0.186 for seed 002.
//
// Discretisation: one spacing dx = 0.02 / H_over_dx (particles across the beam) for fluid and
// solid (single resolution; H_over_dx even, so that the lattice fits the channel's 0.41 and the
// beam's 0.19). Fluid on the cell-centred lattice of [0, 2.5] x [0, 0.41] outside the cylinder and
// the beam; channel walls: ceil(support / dx) rows of Wall particles below y = 0 and above y = H,
// over the buffers too; the cylinder: Wall rings R - (k + 1/2) dx, k dx < support (as
// cylinder_free_stream), except where the beam's clamp lies; the beam: the lattice columns from
// the tip back into the cylinder, Solid outside the cylinder and Wall (the clamp) inside it, to a
// depth of ceil(support / dx) columns behind the attachment. The solid set's particles have
// images in the fluid set (coupling/fsi.hpp). Inflow: the emitter buffer (boundaries/
// open_boundary.hpp) upstream of x = 0 moving with u(y, t), pressure extrapolated from the fluid
// (Shepard, as a channel driven by its inflow needs); outflow: the disposer at x = 2.5, pressure
// 0. The fluid starts at rest.
//
// Metrics (window t >= settle_fraction t_end; tip displacement u = x_A(t) - x_A(0), x_A the mean
// over the solid's tip column x = 0.6 - dx/2):
//   tip_y_amplitude_over_D  half the peak-to-peak of u_y over the whole periods of the window (or
//                           over the window when it holds none) / D
//   tip_frequency           f D / U, f from the upward zero crossings of u_y in the window
//                           (diagnostics/signal.hpp); tip_cycles the periods used;
//                           tip_frequency_spectral from the periodogram peak
//   tip_x_mean, tip_y_mean  time means of u_x, u_y over the same interval / D
//   tip_y_max_over_D        max |u_y| / D over the whole run
//   cd_mean, cl_rms, cd_amplitude, cl_amplitude, St, ... (cases/shedding.hpp) of the force of the
//                           fluid on the cylinder plus the beam: C_D = 2 F_x / (rho_f U^2 D),
//                           C_L = 2 F_y / (rho_f U^2 D), F the sum of the fluid's force on their
//                           wall particles (wcsph_tvf's wall reactions, averaged over each step)
//   cl_mean                 time mean of C_L over the same window as cd_mean
//   drag, lift              Turek & Hron's units (CFD2: 136.7 and 10.53): the time means of the
//                           force in N per m at their rho_f = 1000 kg/m^3, 50 cd_mean and 50
//                           cl_mean
//   lift_oscillation        half the peak-to-peak of C_L over the window / |cl_mean| (CFD2 is
//                           steady: ~0)
//   cd_end, cl_end          the last sample; tip_dx_end, tip_dy_end the last tip displacement / D
//   solid_substeps_mean     solid steps per fluid step; n_fluid, n_solid, advection_steps
// HDF5 (<output_dir>/fsi_beam.h5): series/{t, tip_dx, tip_dy, cd, cl} (every advection step) and
// the job's attributes.
// Time loop: the shared one; emitter and disposer before each step; the solid advances inside the
// fluid step (its body_motion hook); tip and forces after it. Checkpoints: the solid's particles
// and step count, the series, the open boundaries' counters.
#include "boundaries/open_boundary.hpp"
#include "cases/case.hpp"
#include "cases/shedding.hpp"
#include "cases/time_loop.hpp"
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "coupling/fsi.hpp"
#include "diagnostics/signal.hpp"
#include "io/job_attributes.hpp"
#include "io/particle_checkpoint.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace sph {
namespace {

using V2 = Vec<2>;
constexpr double pi = std::numbers::pi;

// Turek & Hron's geometry (m) and the fluid's scales (rho_f = 1, U = 1).
constexpr double U = 1.0, rho_f = 1.0, D = 0.1, R = 0.05, L_channel = 2.5, H_channel = 0.41;
constexpr double beam_h = 0.02, x_tip = 0.6;
const V2 centre(0.2, 0.2);

class FsiBeam final : public FlowCase<2> {
public:
  FsiBeam(const Params& prm, const RunContext& ctx) : prm_(prm), ctx_(ctx) {
    n_ = static_cast<int>(get_int(prm, "H_over_dx"));
    dx_ = beam_h / n_;
    t_end_ = get_real(prm, "t_end");
    t_settle_ = get_real(prm, "settle_fraction") * t_end_;
    ramp_ = get_real(prm, "ramp_time");
  }

  Flow<2> build(Particles<2>& p) override {
    p_ = &p;
    const double dx = dx_;
    const int nx = static_cast<int>(std::lround(L_channel / dx));
    const int ny = static_cast<int>(std::lround(H_channel / dx));
    const double h = get_real(prm_, "h_over_dx") * dx;
    const double support = kernel_support_factor(get_string(prm_, "kernel")) * h;
    const int nw = static_cast<int>(std::ceil(support / dx - 1e-9)); // wall layers
    const int layers = nw + 1;                                       // buffer columns
    const double m = rho_f * dx * dx;
    const double y_lo = centre[1] - 0.5 * beam_h, y_hi = centre[1] + 0.5 * beam_h;
    const double x_attach = centre[0] + std::sqrt(R * R - 0.25 * beam_h * beam_h);
    const double x_clamp = x_attach - nw * dx; // the clamp reaches this deep into the cylinder
    auto in_beam = [&](const V2& x) {
      return x[0] > centre[0] && x[0] < x_tip && x[1] > y_lo && x[1] < y_hi;
    };

    // The solid: the beam's lattice columns from the tip back to x_clamp.
    const double rho_s = get_real(prm_, "density_ratio") * rho_f;
    for (int i = 0;; ++i) {
      const double x = x_tip - (i + 0.5) * dx;
      if (x < x_clamp)
        break;
      for (int j = 0; j < n_; ++j) {
        const V2 r(x, y_lo + (j + 0.5) * dx);
        const Kind k = (r - centre).norm() >= R ? Kind::Solid : Kind::Wall;
        solid_.add(r, rho_s * dx * dx, rho_s, k);
      }
    }

    // The fluid set: channel walls, cylinder rings, fluid, the solid's images, the inlet buffer.
    body_ = p.add_scalar("fsi_beam/body"); // 1: a wall particle of the cylinder or the beam
    for (int i = -(layers + nw); i < nx + layers + nw; ++i)
      for (int k = 0; k < nw; ++k) {
        const double x = (i + 0.5) * dx;
        p.add(V2(x, -(k + 0.5) * dx), m, rho_f, Kind::Wall);
        p.add(V2(x, H_channel + (k + 0.5) * dx), m, rho_f, Kind::Wall);
      }
    for (int k = 0;; ++k) {
      const double rk = R - (k + 0.5) * dx;
      if (rk <= 0.25 * dx || (k + 0.5) * dx > support)
        break;
      const int na = std::max(1, static_cast<int>(std::lround(2.0 * pi * rk / dx)));
      for (int a = 0; a < na; ++a) {
        const double th = (a + 0.5) * 2.0 * pi / na;
        const V2 r = centre + rk * V2(-std::cos(th), std::sin(th));
        if (r[0] >= x_clamp - 0.5 * dx && r[1] > y_lo && r[1] < y_hi)
          continue; // the beam's clamp is there
        p.scalar(body_)[p.add(r, m, rho_f, Kind::Wall)] = 1.0;
      }
    }
    for_each_lattice_point<2>({0, 0}, {nx, ny}, dx, [&](const V2& x, const std::array<int, 2>&) {
      if ((x - centre).norm() >= R && !in_beam(x))
        p.add(x, m, rho_f);
    });
    // The outlet buffer, full from the start (the fluid at the outlet then has a full support).
    const int zk = open_boundary::zone_field(p);
    for_each_lattice_point<2>({nx, 0}, {nx + layers, ny}, dx,
                              [&](const V2& x, const std::array<int, 2>&) {
                                p.scalar(zk)[p.add(x, m, rho_f, Kind::Buffer)] = 2.0;
                              });
    Flow<2> f;
    f.v_wall = p.add_vector("v_wall"); // zero but on the images
    const std::size_t n_before_images = p.size();
    coupling_.add_images(p, solid_, rho_f, dx, f.v_wall);
    for (std::size_t k = n_before_images; k < p.size(); ++k)
      p.scalar(body_)[k] = 1.0;
    // Wall normals into the fluid (wcsph_tvf's wall_dissipation = normal): the channel walls'
    // +-y; on the cylinder and the beam the normal of the nearest face (radial, beam top, bottom,
    // tip), the beam's faces only from its clamp on.
    f.normal = p.add_vector("normal");
    auto& normal = p.vector(f.normal);
    const auto& body = p.scalar(body_);
    for (std::size_t k = 0; k < p.size(); ++k) {
      if (p.kind[k] != Kind::Wall)
        continue;
      const V2 r = p.r[k];
      V2& n = normal[k];
      if (body[k] == 0.0) {
        n = r[1] < 0.5 * H_channel ? V2(0.0, 1.0) : V2(0.0, -1.0);
        continue;
      }
      const double rc = (r - centre).norm();
      double best = rc < R ? R - rc : std::numeric_limits<double>::infinity();
      n = rc > 0.0 ? V2((r - centre) / rc) : V2(-1.0, 0.0);
      if (r[0] >= x_clamp - dx && r[1] > y_lo && r[1] < y_hi) {
        const std::pair<double, V2> faces[] = {{y_hi - r[1], V2(0.0, 1.0)},
                                               {r[1] - y_lo, V2(0.0, -1.0)},
                                               {x_tip - r[0], V2(1.0, 0.0)}};
        for (const auto& [d, nf] : faces)
          if (d < best)
            best = d, n = nf;
      }
    }
    // With wall_dissipation = normal the beam's normals turn with it (n = F^-T n0 normalised).
    if (!get_bool(prm_, "rigid_beam") && prm_.count("wall_dissipation") &&
        get_string(prm_, "wall_dissipation") == "normal")
      coupling_.follow_normals(f);

    typename open_boundary::Emitter<2>::Config ec;
    ec.x_in = 0.0, ec.layers = layers, ec.dx = dx, ec.lo = {0, 0}, ec.hi = {nx, ny};
    ec.rho0 = rho_f, ec.extrapolate_pressure = true, ec.zone = 1;
    ec.u_in = [this](const V2& r, double t) { return V2(inflow(r[1], t), 0.0); };
    emitter_ = std::make_unique<open_boundary::Emitter<2>>(ec);
    typename open_boundary::Disposer<2>::Config dc;
    dc.x_out = nx * dx, dc.layers = layers, dc.dx = dx, dc.zone = 2;
    disposer_ = std::make_unique<open_boundary::Disposer<2>>(dc);
    next_id_ = static_cast<std::int64_t>(p.size());
    emitter_->fill(p, 0.0, next_id_);
    f.buffer_pressure = [](Particles<2>& q, const NeighborList<2>& nl) {
      const auto& z = q.scalar(open_boundary::zone_field(q));
      auto inlet = [&](std::size_t i) { return q.kind[i] == Kind::Buffer && z[i] == 1.0; };
      open_boundary::BufferPressure<2, decltype(inlet)> op{q.kind, q.p, inlet, 0.0};
      interact(nl, op, inlet);
    };

    f.box.lo = V2::Zero(), f.box.hi = V2(nx * dx, ny * dx);
    f.box.periodic = {false, false};
    f.rho0 = rho_f, f.U = U, f.L = D, f.Re = get_real(prm_, "Re"), f.dx = dx;

    // The solid's flow and scheme (its parameters: the scheme's defaults, the job's kernel and
    // h_over_dx, and solid_damping).
    Flow<2> sf;
    sf.p = &solid_;
    sf.rho0 = rho_s, sf.dx = dx;
    sf.youngs_modulus = get_real(prm_, "youngs_modulus") * rho_f * U * U;
    sf.poisson_ratio = get_real(prm_, "poisson_ratio");
    coupling_.attach(f, sf);
    if (get_bool(prm_, "rigid_beam"))
      f.body_motion = nullptr; // the beam stays a rigid wall (the fluid's force still computed)
    Params sp;
    for (const auto& s : find_scheme("elastic_solid")->params)
      sp[s.name] = prm_.count(s.name) ? prm_.at(s.name) : s.default_value;
    sp["damping"] = prm_.at("solid_damping");
    sp["scheme"] = std::string("elastic_solid");
    solid_scheme_ = make_scheme<2>(sp, sf, "elastic_solid");
    return f;
  }

  double t_end() const override { return t_end_; }
  double speed_bound() const override { return get_real(prm_, "speed_bound") * U; }

  void start(FlowScheme<2>&) override {
    solid_scheme_->init();
    coupling_.start(*solid_scheme_);
    find_tip();
  }

  void before_step(FlowScheme<2>& s, const LoopState& at) override {
    // The outlet buffer's velocity: the Shepard average of its fluid and outlet-buffer
    // neighbours' velocities (a zero-gradient outflow; one Jacobi sweep per step, on the list of
    // the current positions, before the particle set changes).
    Particles<2>& p = *p_;
    const auto& z = p.scalar(open_boundary::zone_field(p));
    auto outlet = [&](std::size_t i) { return p.kind[i] == Kind::Buffer && z[i] == 2.0; };
    OutletVelocity op{p, z, v_out_};
    v_out_.assign(p.size(), V2::Zero());
    interact(s.neighbors(), op, outlet);
    for (std::size_t i = 0; i < p.size(); ++i)
      if (outlet(i))
        p.v[i] = v_out_[i];
    const bool removed = disposer_->update(p);
    const double t_mid = at.t + 0.5 * s.stable_dt();
    const bool added = emitter_->update(p, t_mid, next_id_) > 0;
    if (removed || added)
      s.particles_changed();
  }

  bool after_step(FlowScheme<2>&, const LoopState& at, const StepStats&) override {
    const Particles<2>& p = *p_;
    const auto& fw = p.vector(coupling_.wall_force_field());
    const auto& body = p.scalar(body_);
    V2 F = V2::Zero();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (body[i] != 0.0)
        F += fw[i];
    const V2 u = tip() - tip0_;
    if (!std::isfinite(F.squaredNorm()) || !std::isfinite(u.squaredNorm()))
      throw std::runtime_error("force or tip not finite");
    const double q = 0.5 * rho_f * U * U * D;
    const double row[] = {at.t, u[0], u[1], F[0] / q, F[1] / q};
    for (std::size_t k = 0; k < series_.size(); ++k)
      series_[k].push_back(row[k]);
    tip_y_max_ = std::max(tip_y_max_, std::abs(u[1]));
    return false;
  }

  void finish(FlowScheme<2>&, const LoopState& at, RunResult& res) override {
    const auto &t = series_[0], &ux = series_[1], &uy = series_[2];
    const diag::Frequency fz = diag::zero_crossing_frequency(t, uy, t_settle_);
    double t0 = t_settle_, t1 = t.empty() ? 0.0 : t.back();
    if (fz.cycles >= 1) {
      t0 = fz.t_first, t1 = fz.t_last;
      res.add("tip_frequency", fz.f * D / U);
      res.add("tip_period_cv", fz.period_std * fz.f);
    }
    res.add("tip_cycles", static_cast<double>(fz.cycles));
    const diag::Frequency fs = diag::spectral_peak_frequency(t, uy, t_settle_);
    if (fs.f > 0.0)
      res.add("tip_frequency_spectral", fs.f * D / U);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t k = 0; k < t.size(); ++k)
      if (t[k] >= t0 && t[k] <= t1)
        lo = std::min(lo, uy[k]), hi = std::max(hi, uy[k]);
    if (hi >= lo)
      res.add("tip_y_amplitude_over_D", 0.5 * (hi - lo) / D);
    const double mx = diag::time_mean(t, ux, t0, t1), my = diag::time_mean(t, uy, t0, t1);
    if (std::isfinite(mx))
      res.add("tip_x_mean", mx / D), res.add("tip_y_mean", my / D);
    res.add("tip_y_max_over_D", tip_y_max_ / D);
    const AveragingWindow w =
        add_shedding_metrics(t, series_[3], series_[4], t_settle_, D / U, res);
    // Turek & Hron's units: drag and lift in N per m of span at their rho_f = 1000 kg/m^3 (ours is
    // 1, with U = 1 m/s and D = 0.1 m as theirs), F = rho_f U^2 D C / 2 = 50 C.
    const double cl_mean = diag::time_mean(t, series_[4], w.t0, w.t1);
    if (std::isfinite(cl_mean) && std::isfinite(w.cd_mean)) {
      const double to_newton = 1000.0 * 0.5 * U * U * D;
      res.add("cl_mean", cl_mean);
      res.add("drag", to_newton * w.cd_mean);
      res.add("lift", to_newton * cl_mean);
      if (w.cl_hi >= w.cl_lo && cl_mean != 0.0)
        res.add("lift_oscillation", 0.5 * (w.cl_hi - w.cl_lo) / std::abs(cl_mean));
    }
    if (!t.empty()) {
      res.add("cd_end", series_[3].back()), res.add("cl_end", series_[4].back());
      res.add("tip_dx_end", ux.back() / D), res.add("tip_dy_end", uy.back() / D);
    }
    res.add("advection_steps", static_cast<double>(at.steps));
    if (at.steps > 0)
      res.add("solid_substeps_mean",
              static_cast<double>(coupling_.substeps()) / static_cast<double>(at.steps));
    double n_fluid = 0.0, n_solid = 0.0;
    for (const Kind k : p_->kind)
      n_fluid += k == Kind::Fluid;
    for (const Kind k : solid_.kind)
      n_solid += k == Kind::Solid;
    res.add("n_fluid", n_fluid);
    res.add("n_solid", n_solid);
    res.add("mass_in", emitter_->mass_in());
    res.add("mass_out", disposer_->mass_out());
    solid_scheme_->add_metrics(res, 0.0);
    if (auto h5 = io::open_job_output(ctx_, "fsi_beam", prm_)) {
      h5->attribute("t_settle", t_settle_);
      h5->write_columns("series", {"t", "tip_dx", "tip_dy", "cd", "cl"},
                        {series_[0], series_[1], series_[2], series_[3], series_[4]});
      h5->close();
    }
  }

  // The solid's particles and scheme state, the series, the open boundaries' counters.
  std::vector<std::string> state_names() const override {
    std::vector<std::string> n;
    for (const auto& a : io::particle_array_names(solid_))
      n.push_back("fsi_beam/solid/" + a);
    for (const auto& a : solid_scheme_->state_names())
      n.push_back(a);
    for (std::size_t k = 0; k < series_.size(); ++k)
      n.push_back("fsi_beam/series" + std::to_string(k));
    n.push_back("fsi_beam/loop");
    return n;
  }
  void save_state(StateArrays& out) const override {
    StateArrays a;
    io::add_particle_arrays(solid_, a);
    for (auto& [k, v] : a)
      out["fsi_beam/solid/" + k] = v;
    solid_scheme_->save_state(out);
    for (std::size_t k = 0; k < series_.size(); ++k)
      out["fsi_beam/series" + std::to_string(k)] = series_[k];
    out["fsi_beam/loop"] = {static_cast<double>(next_id_),
                            emitter_->mass_in(),
                            disposer_->mass_out(),
                            disposer_->mass_lost(),
                            static_cast<double>(coupling_.substeps()),
                            tip_y_max_};
  }
  void load_state(const StateArrays& in) override {
    StateArrays a;
    const std::string pre = "fsi_beam/solid/";
    for (const auto& [k, v] : in)
      if (k.rfind(pre, 0) == 0)
        a[k.substr(pre.size())] = v;
    io::restore_particle_arrays(solid_, a);
    solid_scheme_->load_state(in);
    solid_scheme_->resume();
    coupling_.start(*solid_scheme_);
    for (std::size_t k = 0; k < series_.size(); ++k)
      series_[k] = in.at("fsi_beam/series" + std::to_string(k));
    const auto& l = in.at("fsi_beam/loop");
    io::expect_state_size(l, 6, "fsi_beam: checkpoint array fsi_beam/loop");
    next_id_ = static_cast<std::int64_t>(l[0]);
    emitter_->set_mass_in(l[1]);
    disposer_->set_masses(l[2], l[3]);
    coupling_.set_substeps(static_cast<long>(l[4]));
    tip_y_max_ = l[5];
    find_tip();
  }

private:
  Params prm_;
  RunContext ctx_;
  int n_ = 4;
  double dx_ = 0.005, t_end_ = 0.0, t_settle_ = 0.0, ramp_ = 2.0;
  Particles<2>* p_ = nullptr;
  Particles<2> solid_;
  std::unique_ptr<FlowScheme<2>> solid_scheme_;
  fsi::SolidFluidCoupling<2> coupling_;
  std::unique_ptr<open_boundary::Emitter<2>> emitter_;
  std::unique_ptr<open_boundary::Disposer<2>> disposer_;
  std::int64_t next_id_ = 0;
  int body_ = -1;
  std::vector<std::size_t> tip_; // the solid's tip column
  V2 tip0_ = V2::Zero();
  double tip_y_max_ = 0.0;
  std::array<std::vector<double>, 5> series_; // t, u_x, u_y, C_D, C_L

  std::vector<V2> v_out_;
  // v_i = sum_j W_ij v_j / sum_j W_ij over fluid and outlet-buffer partners j (unchanged without).
  struct OutletVelocity {
    const Particles<2>& p;
    const std::vector<double>& zone;
    std::vector<V2>& out;
    struct Acc {
      V2 num = V2::Zero();
      double den = 0.0;
    };
    Acc init(std::size_t) const { return {}; }
    void pair(std::size_t, const Pair<2>& q, Acc& a) const {
      if (p.kind[q.j] == Kind::Fluid || (p.kind[q.j] == Kind::Buffer && zone[q.j] == 2.0))
        a.num += q.W * p.v[q.j], a.den += q.W;
    }
    void finish(std::size_t i, const Acc& a) { out[i] = a.den > 0.0 ? V2(a.num / a.den) : p.v[i]; }
  };

  double inflow(double y, double t) const {
    const double ramp = t < ramp_ ? 0.5 * (1.0 - std::cos(pi * t / ramp_)) : 1.0;
    const double hh = 0.5 * H_channel;
    return 1.5 * U * y * (H_channel - y) / (hh * hh) * ramp;
  }
  // The tip column from the reference positions (the solid's order is fixed after its init).
  void find_tip() {
    const auto& r0 = solid_.vector(solid_.find_vector("solid/r0"));
    tip_.clear();
    tip0_ = V2::Zero();
    for (std::size_t i = 0; i < solid_.size(); ++i)
      if (solid_.kind[i] == Kind::Solid && r0[i][0] > x_tip - dx_)
        tip_.push_back(i), tip0_ += r0[i];
    tip0_ /= static_cast<double>(tip_.size());
  }
  V2 tip() const {
    V2 s = V2::Zero();
    for (const std::size_t i : tip_)
      s += solid_.r[i];
    return s / static_cast<double>(tip_.size());
  }
};

} // namespace

CaseInfo make_fsi_beam_case() {
  CaseInfo c;
  c.name = "fsi_beam";
  c.description = "elastic beam behind a cylinder in a channel, Turek & Hron FSI2 (Wang, Haidn & "
                  "Hu 2024, section 4.3): wcsph_tvf fluid coupled to the elastic_solid beam";
  c.schemes = {"wcsph_tvf"};
  c.params = {
      {"H_over_dx", ParamType::Int, std::int64_t{4},
       "particles across the beam (thickness 0.02 / dx; even), fluid and solid", 2.0, 64.0},
      {"Re", ParamType::Real, 100.0, "Reynolds number U D / nu_f (FSI2: 100)", 0.0, 1e5, true},
      {"density_ratio", ParamType::Real, 10.0, "rho_s / rho_f (FSI2: 10)", 0.0, 1e4, true},
      {"youngs_modulus", ParamType::Real, 1.4e3, "E / (rho_f U^2) (FSI2: 1.4e3)", 0.0, 1e9, true},
      {"poisson_ratio", ParamType::Real, 0.4,
       "Poisson ratio of the beam (FSI2: 0.4; 2D: plane "
       "strain)",
       -0.99, 0.49},
      {"solid_damping", ParamType::Real, 0.05,
       "the beam's Kelvin-Voigt numerical damping (elastic_solid's damping)", 0.0, 10.0},
      {"rigid_beam", ParamType::Bool, false,
       "the beam held rigid (not advanced; Turek & Hron's CFD tests): the reference of the "
       "coupled run's forces"},
      {"ramp_time", ParamType::Real, 2.0,
       "inflow ramp (1 - cos(pi t / T)) / 2 over t < T (FSI2: 2)", 0.0, 1e3},
      {"t_end", ParamType::Real, 15.0, "end time (D / U = 0.1)", 0.0, 1e4, true},
      {"settle_fraction", ParamType::Real, 0.5,
       "the tip and force metrics are over t >= settle_fraction t_end", 0.0, 0.99},
      {"speed_bound", ParamType::Real, 5.0, "diverged when a speed exceeds this many U", 1.0, 1e6},
  };
  add_loop_params(c.params); // output_interval (cases/loop_params.hpp)
  c.check = [](const Params& prm) -> std::optional<std::string> {
    if (get_int(prm, "H_over_dx") % 2 != 0)
      return "fsi_beam: H_over_dx must be even (the lattice then fits the channel's 0.41 and the "
             "beam's 0.19)";
    return std::nullopt;
  };
  c.size = [](const Params& prm) {
    const RunContext none;
    FsiBeam c(prm, none);
    return size_flow_case<2>(c, prm, "wcsph_tvf");
  };
  c.run = [](const Params& prm, const RunContext& ctx) {
    FsiBeam b(prm, ctx);
    return run_flow_case<2>(b, prm, ctx, "wcsph_tvf");
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_fsi_beam_case()); // core/registry.hpp
} // namespace

} // namespace sph
