// Registry entry of scheme "elastic_solid" (total-Lagrangian SPH elastic solid, elastic_solid.hpp;
// docs/solid.md): its parameters, each stated once in a ParamTable bound to the Options member it
// sets, and the FlowScheme<D> the time loop drives, which wraps solid::Scheme<D, K, L> (K, the
// kernel, and L, the law, chosen once per job).
#include "schemes/solid/scheme_info.hpp"

#include "core/kernels/kernel.hpp"

#include <memory>

namespace sph {

namespace solid {

namespace {

const ParamTable<Options>& table() {
  static const ParamTable<Options> t =
      ParamTable<Options>()
          .choice("material", &Options::law,
                  {{"svk", Law::SaintVenantKirchhoff}, {"neo_hookean", Law::NeoHookean}},
                  "hyperelastic law: Saint Venant-Kirchhoff or compressible neo-Hookean (2D: "
                  "plane strain)")
          .string("kernel", &Options::kernel, "smoothing kernel",
                  {"wendland_c2", "cubic_spline", "quintic_spline"})
          .real("h_over_dx", &Options::h_over_dx, "smoothing length h / particle spacing dx",
                {0.5, 3.0})
          .real("cfl", &Options::cfl,
                "acoustic CFL number: dt = cfl h / (c_p + |v|max), c_p the P-wave speed",
                {0.0, 1.5, true})
          .real("damping", &Options::damping,
                "Kelvin-Voigt numerical damping: PK2 stress += damping rho0 c_p h dE/dt "
                "(0: none)",
                {0.0, 10.0});
  return t;
}

// The time loop's view of solid::Scheme<D, K, L>.
template <int D, class K, class L>
class Adapter final : public sph::FlowScheme<D> {
public:
  Adapter(const Options& o, const Flow<D>& flow, const K& kernel)
      : o_(o), s_(*flow.p, o_, kernel) {}

  void init() override { s_.init(); }
  void resume() override { s_.resume(); }
  StepStats advance(double& t, double t_end) override {
    StepStats st;
    st.dt = s_.step(t_end - t);
    st.substeps = 1;
    t += st.dt;
    return st;
  }
  double stable_dt() const override { return s_.stable_dt(); }
  void wall_velocities_for_output() override {} // the clamp is at rest
  // The neighbour list of the reference configuration (pairs and kernel values of r0).
  const NeighborList<D>& neighbors() const override { return s_.neighbors(); }
  const std::string& kernel_name() const override { return o_.kernel; }
  double h() const override { return o_.h; }
  void set_body_acceleration(const Vec<D>& g) override { s_.set_body_acceleration(g); }

  // The particle fields (positions, velocities, solid/r0, solid/a) carry the state; the step
  // count is the scheme's own.
  std::vector<std::string> state_names() const override { return {"elastic_solid/steps"}; }
  void save_state(StateArrays& out) const override {
    out["elastic_solid/steps"] = {static_cast<double>(s_.steps())};
  }
  void load_state(const StateArrays& in) override {
    const auto& a = in.at("elastic_solid/steps");
    if (a.size() != 1)
      throw std::runtime_error("elastic_solid: checkpoint array elastic_solid/steps: bad size");
    s_.set_steps(static_cast<long>(a[0]));
  }

  // Energies and the internal-force sums of the last step (the conservation checks of a case).
  std::vector<std::pair<std::string, double>> probes() const override {
    const InternalSums<D> m = s_.internal_sums();
    return {{"kinetic_energy", s_.kinetic_energy()},
            {"elastic_energy", s_.elastic_energy()},
            {"internal_force", m.force},
            {"internal_force_scale", m.force_scale},
            {"internal_torque", m.torque},
            {"internal_torque_scale", m.torque_scale}};
  }
  void add_metrics(RunResult& res, double) const override {
    res.add("solid_steps", static_cast<double>(s_.steps()));
    res.add("c_p", s_.c_p());
  }
  long work_steps() const override { return s_.steps(); }
  const std::vector<Mat<D>>* deformation_gradient() const override { return &s_.F(); }

private:
  Options o_;
  Scheme<D, K, L> s_;
};

template <int D>
std::unique_ptr<sph::FlowScheme<D>> make(const Params& prm, const Flow<D>& flow) {
  Options o = options_for_flow(prm, flow.rho0, flow.youngs_modulus, flow.poisson_ratio, flow.dx);
  o.external_force = flow.external_force;
  return with_kernel<D>(o.kernel, o.h, [&](const auto& k) -> std::unique_ptr<sph::FlowScheme<D>> {
    using Kn = std::decay_t<decltype(k)>;
    if (o.law == Law::NeoHookean)
      return std::make_unique<Adapter<D, Kn, NeoHookean<D>>>(o, flow, k);
    return std::make_unique<Adapter<D, Kn, SaintVenantKirchhoff<D>>>(o, flow, k);
  });
}

} // namespace

Options options_for_flow(const Params& prm, double rho0, double E, double nu, double dx) {
  Options o = table().apply(prm);
  o.rho0 = rho0, o.E = E, o.nu = nu, o.dx = dx;
  o.h = o.h_over_dx * dx;
  return o;
}

} // namespace solid

SchemeInfo make_elastic_solid_scheme() {
  SchemeInfo s;
  s.name = "elastic_solid";
  s.description = "total-Lagrangian SPH elastic solid: corrected kernel gradient, deformation "
                  "gradient, SVK / neo-Hookean, Kelvin-Voigt damping (Zhang, Rezavand & Hu, JCP "
                  "429 (2021) 110028; SPHinXsys)";
  s.params = solid::table().specs();
  s.make2 = &solid::make<2>;
  s.make3 = &solid::make<3>;
  return s;
}

namespace {
const Registrar<SchemeInfo> registered(make_elastic_solid_scheme()); // core/registry.hpp
} // namespace

} // namespace sph
