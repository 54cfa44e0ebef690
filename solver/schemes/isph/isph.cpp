// Scheme "isph" (seed 001, Zheng, Ma & Shao 2018, section 2): its parameters and their parsing.
// The time integrator itself is schemes/isph/isph.hpp (a template on dimension and kernel).
#include "schemes/isph/isph.hpp"

#include "core/kernels/kernel.hpp"

namespace sph {

namespace {

// (name, value) of every name a parser accepts.
template <class E>
std::vector<std::pair<std::string, E>> named(const std::vector<std::string>& names,
                                             E (*parse)(const std::string&)) {
  std::vector<std::pair<std::string, E>> v;
  for (const auto& n : names)
    v.emplace_back(n, parse(n));
  return v;
}

std::vector<std::pair<std::string, WallVelocityUse>> wall_velocity_uses() {
  return {{"mirror", WallVelocityUse::Mirror}, {"prescribed", WallVelocityUse::Prescribed}};
}

const ParamTable<IsphOptions>& table() {
  static const ParamTable<IsphOptions> t =
      ParamTable<IsphOptions>()
          .choice("visc", &IsphOptions::visc, named(visc_names(), &parse_visc),
                  "viscous Laplacian form (seed 001 eqs. 15-20)")
          .choice("visc_wall_velocity", &IsphOptions::visc_wall, wall_velocity_uses(),
                  "velocity of the wall particles in the viscous term: mirror (2 u_wall - Shepard "
                  "mean of the fluid, Adami et al. 2012) or prescribed (u_wall)")
          .neutral()
          .choice("ppe_wall_velocity", &IsphOptions::ppe_wall, wall_velocity_uses(),
                  "velocity of the wall particles in div u* of the PPE source: prescribed (u_wall) "
                  "or mirror (2 u_wall - Shepard mean of the fluid)")
          .neutral()
          .real("alpha_ppe", &IsphOptions::alpha_ppe,
                "weight alpha of the density-invariance part of the mixed PPE source (seed 001 "
                "eq. 13)",
                {0.0, 1.0})
          .choice("ppe_solver", &IsphOptions::solver, named(ppe_solver_names(), &parse_ppe_solver),
                  "PPE linear solver: umfpack (sparse LU), or bicgstab (warm-started) with ilut, "
                  "ilu0, jacobi or amg (HYPRE BoomerAMG), or gmres_amg")
          .real("ppe_tol", &IsphOptions::ppe_tol, "relative residual tolerance of bicgstab",
                {0.0, 1e-2, true})
          .integer("ppe_max_iter", &IsphOptions::ppe_max_iter, "iteration limit of bicgstab",
                   {1.0, 100000.0})
          .string("kernel", &IsphOptions::kernel,
                  "smoothing kernel (the paper uses the cubic spline)", kernel_names())
          .real("h_over_dx", &IsphOptions::h_over_dx, "smoothing length h / dx", {0.8, 3.0})
          .real("eta_over_h", &IsphOptions::eta_over_h,
                "eta / h, singularity guard in r^2 + eta^2 (eqs. 14, 15, 17, 20)", {0.0, 0.5})
          .boolean("grad_correction", &IsphOptions::grad_correction,
                   "kernel-corrected pressure gradient (Gamma of eq. 19) in the projection step")
          .choice("shifting", &IsphOptions::shifting, {{"none", false}, {"fickian", true}},
                  "particle shifting: none, or fickian (Lind et al. 2012 with D = A h |u| dt, "
                  "Skillen et al. 2013)")
          .real("shift_A", &IsphOptions::shift_A, "shifting coefficient A in D = A h |u| dt",
                {0.0, 100.0})
          .real("shift_max", &IsphOptions::shift_max, "cap of one step's shift, in units of dx",
                {0.0, 1.0})
          .boolean("shift_velocity", &IsphOptions::shift_velocity,
                   "correct the velocity of a shifted particle by u += grad u . dr")
          .real("wall_clearance", &IsphOptions::wall_clearance,
                "minimum fluid-to-wall-particle distance / dx enforced after each step (0: off)",
                {0.0, 1.0})
          .boolean("wall_clearance_gaps", &IsphOptions::wall_clearance_gaps,
                   "keep the wall_clearance distance also from the midpoints of neighbouring wall "
                   "particles (closes the gaps between them, which 0.5 dx leaves open)")
          .neutral();
  return t;
}

// The time loop's view of Isph<D, K>: fixed steps of flow.dt (t = n dt after n steps, so that a
// run of t_end takes ceil(t_end / dt) steps whatever the rounding), solid particles (Wall, Body)
// moving with their prescribed velocity flow.v_wall (required).
template <int D, class K>
class Adapter final : public FlowScheme<D> {
public:
  Adapter(const IsphOptions& o, const Flow<D>& flow, const K& kernel)
      : flow_(flow), o_(o), kernel_(kernel) {
    if (flow.v_wall < 0)
      throw std::invalid_argument("isph: the flow must give the solid particles' velocity");
    if (!(flow.dt > 0.0))
      throw std::invalid_argument("isph: the flow must give a time step dt > 0");
    if (flow.h >= 0)
      throw std::invalid_argument("isph: no variable resolution (a per-particle h field)");
  }

  void init() override {
    s_ = std::make_unique<Isph<D, K>>(*flow_.p, flow_.box, kernel_, o_, flow_.v_wall, flow_.nu(),
                                      flow_.dt, flow_.dx);
  }

  StepStats advance(double& t, double) override {
    s_->step();
    t = static_cast<double>(s_->steps()) * flow_.dt;
    StepStats st;
    st.dt = flow_.dt;
    st.substeps = s_->last_iterations();
    return st;
  }
  bool finished(double, double t_end) const override {
    return s_->steps() >= static_cast<long>(std::ceil(t_end / flow_.dt - 1e-9));
  }
  double stable_dt() const override { return flow_.dt; }
  void measure_next_step(bool on) override { s_->set_measure_divergence(on); }
  void set_body_acceleration(const Vec<D>& g) override { s_->set_body_acceleration(g); }
  std::vector<std::pair<std::string, double>> probes() const override {
    return {{"div_max", s_->div_max()}, {"ppe_iters", static_cast<double>(s_->last_iterations())}};
  }

  void wall_velocities_for_output() override { s_->update_wall_velocity(); }
  const NeighborList<D>& neighbors() const override { return s_->neighbors(); }
  const std::string& kernel_name() const override { return o_.kernel; }
  double h() const override { return kernel_.h; }

  std::vector<std::string> state_names() const override { return {"isph/carried"}; }
  void save_state(StateArrays& out) const override { out["isph/carried"] = s_->carried_state(); }
  void load_state(const StateArrays& in) override {
    s_->restore_carried_state(in.at("isph/carried"));
  }
  void add_metrics(RunResult& res, double) const override {
    const double steps = static_cast<double>(s_->steps());
    const Vec<D> at = s_->div_argmax();
    res.add("div_max", s_->div_max());
    res.add("div_max_x", at.x());
    res.add("div_max_y", at.y());
    if constexpr (D == 3)
      res.add("div_max_z", at.z());
    res.add("div_rms", s_->div_rms());
    res.add("ppe_assembly_s_per_step", s_->time_assemble() / steps);
    res.add("ppe_solve_s_per_step", s_->time_solve() / steps);
    res.add("ppe_share", (s_->time_assemble() + s_->time_solve()) / s_->time_step());
    res.add("ppe_iters_mean", static_cast<double>(s_->iterations_total()) / steps);
    res.add("ppe_residual", s_->ppe_residual());
    res.add("wall_clearance_corrections", static_cast<double>(s_->clearance_corrections()));
    // Where the net fired first (not recorded when it never fired), and in how many steps.
    res.add("wall_clearance_steps", static_cast<double>(s_->clearance_steps()));
    if (s_->clearance_first_step() >= 0) {
      res.add("wall_clearance_first_t",
              static_cast<double>(s_->clearance_first_step() + 1) * s_->dt());
      res.add("wall_clearance_first_x", s_->clearance_first_r().x());
      res.add("wall_clearance_first_y", s_->clearance_first_r().y());
      if constexpr (D == 3)
        res.add("wall_clearance_first_z", s_->clearance_first_r().z());
    }
  }
  long work_steps() const override { return s_->steps(); }

private:
  Flow<D> flow_;
  IsphOptions o_;
  K kernel_;
  std::unique_ptr<Isph<D, K>> s_;
};

template <int D>
std::unique_ptr<FlowScheme<D>> make(const Params& prm, const Flow<D>& flow) {
  const IsphOptions o = IsphOptions::from_params(prm);
  return with_kernel<D>(
      o.kernel, o.h_over_dx * flow.dx, [&](const auto& k) -> std::unique_ptr<FlowScheme<D>> {
        return std::make_unique<Adapter<D, std::decay_t<decltype(k)>>>(o, flow, k);
      });
}

} // namespace

IsphOptions IsphOptions::from_params(const Params& prm) {
  return table().apply(prm);
}

SchemeInfo make_isph_scheme() {
  SchemeInfo s;
  s.name = "isph";
  s.description = "ISPH two-step projection with VISC-01..04 viscous Laplacians "
                  "(Zheng, Ma & Shao 2018, section 2)";
  s.params = table().specs();
  s.make2 = &make<2>;
  s.make3 = &make<3>;
  return s;
}

namespace {
const Registrar<SchemeInfo> registered(make_isph_scheme()); // core/registry.hpp
} // namespace

} // namespace sph
