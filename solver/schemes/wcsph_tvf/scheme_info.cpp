// Registry entry of scheme "wcsph_tvf" (seed 002, Wang, Haidn & Hu, transport-velocity
// formulation with limiter; equations in docs/tvf.md): its parameters, each stated once in a
// ParamTable bound to the Options member it sets, and the FlowScheme<D> the time loop drives, which
// wraps wcsph_tvf::Scheme<D, K> (K, the kernel, chosen once per job).
#include "schemes/wcsph_tvf/scheme_info.hpp"

#include "core/kernels/kernel.hpp"
#include "io/particle_checkpoint.hpp"
#include "operators/wall_velocity.hpp"

#include <algorithm>
#include <cmath>

namespace sph {

namespace wcsph_tvf {

namespace {

const ParamTable<Options>& table() {
  static const ParamTable<Options> t =
      ParamTable<Options>()
          .choice("tvf", &Options::tvf,
                  {{"none", Tvf::None},
                   {"original", Tvf::Original},
                   {"smoothing_length", Tvf::SmoothingLength},
                   {"limited", Tvf::Limited}},
                  "transport-velocity correction: none, original (Adami 2013 background pressure, "
                  "kick-drift-kick), smoothing_length (eq. 14), limited (eqs. 15-16)")
          .choice("riemann_dissipation", &Options::dissipation,
                  {{"limited", Dissipation::Limited},
                   {"full", Dissipation::Full},
                   {"none", Dissipation::None}},
                  "momentum dissipation of the Riemann solver in the 2nd half: limited (eq. 6), "
                  "full (no limiter) or none (central)")
          .choice(
              "limiter_sign", &Options::sign,
              {{"expansion", LimiterSign::Expansion}, {"compression", LimiterSign::Compression}},
              "pairs the dissipation limiter acts on: expansion (SPHinXsys) or compression "
              "(Zhang 2017)")
          .boolean("kernel_correction", &Options::kernel_correction,
                   "linear kernel-gradient correction B in the pressure force and the TVF residue")
          .boolean("shift_velocity", &Options::shift_velocity,
                   "tvf = smoothing_length / limited: carry the velocity along the TVF shift, "
                   "v_i += (grad v_i) Delta r_i (a Taylor correction, not in Wang, Haidn & Hu)")
          .neutral()
          .boolean("riemann_density", &Options::riemann_density,
                   "the continuity's Riemann term rho_i sum_j (p_i - p_j) / (rho0 c0) V_j dW_ij "
                   "(1st half; SPHinXsys: on)")
          .neutral()
          .boolean("wall_extrapolation", &Options::wall_extrapolation,
                   "wall pressure p_w = p_i + rho_i r_iw max(0, (F_prior_i / m_i) . (-e_iw)); "
                   "false: p_w = p_i")
          .neutral()
          .boolean("substep_pairs", &Options::substep_pairs,
                   "pair geometry (r_ij, W_ij, dW_ij) of the current positions at every acoustic "
                   "sub-step instead of frozen over the advection step (SPHinXsys: frozen)")
          .neutral()
          .choice("wall_dissipation", &Options::wall_dissipation,
                  {{"pair", WallDissipation::Pair}, {"normal", WallDissipation::Normal}},
                  "Riemann dissipation of a wall pair: along e_iw (pair) or along the wall's "
                  "normal, none for tangential sliding (normal: SPHinXsys; needs the case's wall "
                  "normals, walls at rest or prescribed)")
          .neutral()
          .string("kernel", &Options::kernel, "smoothing kernel",
                  {"wendland_c2", "cubic_spline", "quintic_spline"})
          .real("h_over_dx", &Options::h_over_dx, "smoothing length h / particle spacing dx",
                {0.5, 3.0})
          .real("c0_factor", &Options::c0_factor, "artificial sound speed c0 = c0_factor U (eq. 2)",
                {1.0, 1000.0})
          .real("cfl_ad", &Options::cfl_ad, "advection CFL number (eq. 9)", {0.0, 1.0, true})
          .real("cfl_ac", &Options::cfl_ac, "acoustic CFL number (eq. 11)", {0.0, 2.0, true})
          .real("limiter_eta", &Options::limiter_eta,
                "slope eta of the dissipation limiter beta = min((eta / c0) max(s u_ij, 0), 1) "
                "(eq. 6; riemann_dissipation = limited)",
                {0.0, 100.0})
          .neutral()
          .real("tvf_alpha", &Options::tvf_alpha,
                "coefficient alpha of the TVF shift alpha h^2 g (eq. 14)", {0.0, 10.0})
          .real("tvf_kappa", &Options::tvf_kappa,
                "slope kappa of the TVF limiter min(kappa h^2 |g|^2, 1) (eq. 15)", {0.0, 1e6})
          .real("pb_factor", &Options::pb_factor,
                "tvf = original: background pressure p_b = pb_factor rho0 c0^2", {0.0, 100.0})
          .real("viscous_eps", &Options::viscous_eps,
                "eps of the viscous force's (v_i - v_j) / (r_ij + eps h) (SPHinXsys: 0.01; on a "
                "lattice it lowers the viscosity by about 1 % per 0.01)",
                {0.0, 1.0})
          .neutral();
  return t;
}

// The time loop's view of wcsph_tvf::Scheme<D, K>. Solid particles: Wall and Body particles are
// the scheme's walls (a body is a wall moving with its prescribed velocity); with a prescribed
// velocity field they start with that velocity.
template <int D, class K>
class Adapter final : public sph::FlowScheme<D> {
public:
  Adapter(const Options& o, const Flow<D>& flow)
      : p_(*flow.p), v_wall_(flow.v_wall), o_(o), f_(prepare(flow, o)), s_(p_, f_, flow.box, o_) {
    s_.set_boundary_hooks({flow.buffer_pressure, flow.before_density, flow.after_density,
                           flow.after_kick, flow.surface_indicator, flow.body_motion});
  }

  void init() override { s_.init(); }
  void particles_changed() override { s_.particles_changed(); }
  void resume() override { s_.resume(r0_, builds_); }

  StepStats advance(double& t, double t_end) override {
    const StepInfo i = s_.advance_towards(t, t_end);
    return {i.Dt, i.substeps, i.v_max, i.tv_max};
  }
  double stable_dt() const override { return s_.advection_dt(); }

  void wall_velocities_for_output() override {
    if (v_wall_ < 0)
      return;
    WallVelocity<D> wv{p_.kind, p_.vector(v_wall_), p_.v};
    interact(s_.neighbors(), wv, [&](std::size_t i) { return p_.kind[i] == Kind::Wall; });
  }
  const NeighborList<D>& neighbors() const override { return s_.neighbors(); }
  const std::string& kernel_name() const override { return o_.kernel; }
  double h() const override { return o_.h; }
  Vec<D> force_on_walls(Vec<D>* viscous) override { return s_.force_on_walls(viscous); }
  void set_body_acceleration(const Vec<D>& g) override { s_.set_body_acceleration(g); }

  // The carried scalars, and the Verlet list's reference positions and build count (a resumed
  // run rebuilds the very list of the uninterrupted run from them).
  std::vector<std::string> state_names() const override {
    return {"wcsph_tvf/carried", "wcsph_tvf/verlet_r0", "wcsph_tvf/verlet_builds"};
  }
  void save_state(StateArrays& out) const override {
    out["wcsph_tvf/carried"] = s_.carried_state();
    out["wcsph_tvf/verlet_r0"] = io::detail::flatten<D>(s_.verlet().reference());
    out["wcsph_tvf/verlet_builds"] = {static_cast<double>(s_.verlet().builds())};
  }
  void load_state(const StateArrays& in) override {
    s_.restore_carried_state(in.at("wcsph_tvf/carried"));
    r0_.resize(p_.size());
    io::detail::unflatten<D>(in.at("wcsph_tvf/verlet_r0"), r0_, "wcsph_tvf/verlet_r0");
    const auto& b = in.at("wcsph_tvf/verlet_builds");
    io::expect_state_size(b, 1, "wcsph_tvf: checkpoint verlet_builds");
    builds_ = static_cast<long>(b[0]);
  }
  void add_metrics(RunResult& res, double) const override {
    res.add("acoustic_steps", static_cast<double>(s_.acoustic_steps()));
    res.add("neighbour_builds", static_cast<double>(s_.verlet().builds()));
  }
  long work_steps() const override { return s_.acoustic_steps(); }
  // The acoustic sub-steps of one advection step (eq. 11 within eq. 10's step).
  double work_per_step() const override {
    return std::max(1.0, std::ceil(s_.advection_dt() / s_.acoustic_dt() * (1.0 - 1e-12)));
  }

  wcsph_tvf::Scheme<D, K>& core() { return s_; }

private:
  Particles<D>& p_;
  int v_wall_;
  Options o_;
  Fields f_;
  wcsph_tvf::Scheme<D, K> s_;
  std::vector<Vec<D>> r0_; // loaded Verlet reference positions, for resume()
  long builds_ = 0;

  static Fields prepare(const Flow<D>& flow, const Options& o) {
    Particles<D>& p = *flow.p;
    if (o.wall_dissipation == WallDissipation::Normal) {
      if (flow.normal < 0)
        throw std::invalid_argument("wcsph_tvf: wall_dissipation = normal needs the case's wall "
                                    "normals (this case sets none)");
      if (flow.body_motion && !flow.normals_follow_bodies)
        throw std::invalid_argument("wcsph_tvf: wall_dissipation = normal: the case does not turn "
                                    "the wall normals of its moving bodies (use pair)");
    }
    for (auto& k : p.kind)
      if (k == Kind::Body)
        k = Kind::Wall;
    if (flow.v_wall >= 0)
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p.kind[i] == Kind::Wall)
          p.v[i] = p.vector(flow.v_wall)[i];
    Fields f = Fields::add_to(p, flow.v_wall);
    f.h = flow.h;
    f.a_wall = flow.a_wall;
    f.f_body = flow.wall_force;
    if (o.wall_dissipation == WallDissipation::Normal)
      f.n_wall = flow.normal;
    return f;
  }
};

template <int D>
std::unique_ptr<sph::FlowScheme<D>> make(const Params& prm, const Flow<D>& flow) {
  const Options o = options_for_flow(prm, flow.rho0, flow.U, flow.L, flow.Re, flow.dx);
  return with_kernel<D>(o.kernel, o.h, [&](const auto& k) -> std::unique_ptr<sph::FlowScheme<D>> {
    return std::make_unique<Adapter<D, std::decay_t<decltype(k)>>>(o, flow);
  });
}

} // namespace

Options options_from(const Params& prm) {
  return table().apply(prm);
}

Options options_for_flow(const Params& prm, double rho0, double U, double L, double Re, double dx) {
  Options o = options_from(prm);
  o.rho0 = rho0;
  o.U_ref = U;
  o.c0 = o.c0_factor * U;
  o.mu = rho0 * U * L / Re;
  o.dx = dx;
  o.h = o.h_over_dx * dx;
  return o;
}

} // namespace wcsph_tvf

SchemeInfo make_wcsph_tvf_scheme() {
  SchemeInfo s;
  s.name = "wcsph_tvf";
  s.metrics = {{"acoustic_steps", "acoustic sub-steps (eq. 11) of the whole run"},
               {"neighbour_builds", "Verlet-list rebuilds"}};
  s.description = "Riemann WCSPH, dual-criteria time stepping and transport-velocity correction "
                  "with limiter (Wang, Haidn & Hu, arXiv:2411.13992)";
  s.params = wcsph_tvf::table().specs();
  s.free_stream = true;
  s.moving_bodies = true;
  s.make2 = &wcsph_tvf::make<2>;
  s.make3 = &wcsph_tvf::make<3>;
  return s;
}

namespace {
const Registrar<SchemeInfo> registered(make_wcsph_tvf_scheme()); // core/registry.hpp
} // namespace

} // namespace sph
