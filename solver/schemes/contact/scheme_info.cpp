// Registry entry of scheme "contact" (seed 003, Parshikov et al.): its parameters, each stated once
// in a ParamTable bound to the contact::Options member it sets, and the FlowScheme<D> the time loop
// drives, which wraps contact::Scheme<D, K> (K, the unit-h kernel, chosen once per job).
//
// What the scheme takes from the flow: the per-particle material fields rho0, c0 and eta (by name,
// set by the case: several materials in one run), Wall particles as no-slip solids at rest,
// Flow::slip_walls as mirror planes, a body acceleration (set_body_acceleration). Its time step is
// the stable step of contact.hpp shortened to land exactly on t_end.
#include "schemes/contact/scheme_info.hpp"

#include "core/kernels/kernel.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sph {

namespace contact {

namespace {

const ParamTable<Options>& table() {
  static const ParamTable<Options> t =
      ParamTable<Options>()
          .real("zeta", &Options::zeta,
                "fraction of the numerical viscosity removed by the correcting stress (eq. 26)",
                {0.0, 1.0})
          .string("eta_num", &Options::eta_num_text,
                  "numerical viscosity the correction is built on: \"eq37\" (eq. 37 per "
                  "particle) or a number in Pa s written as a string")
          .real("alpha", &Options::alpha,
                "smoothing length factor, h_ij = alpha (D_i + D_j) (eq. 12)", {0.5, 2.0})
          .string("kernel", &Options::kernel, "smoothing kernel", {"wendland_c2", "cubic_spline"})
          .real("cfl", &Options::cfl, "Courant number, dt = cfl min D_i / (c0_i + |U_i|)",
                {0.0, 1.0, true});
  return t;
}

// The time loop's view of contact::Scheme<D, K>.
template <int D, class K>
class Adapter final : public FlowScheme<D> {
public:
  Adapter(const Options& o, const Flow<D>& flow)
      : kernel_(o.kernel), h0_(o.alpha * 2.0 * flow.dx),
        s_(*flow.p, Fields::find_in(*flow.p), flow.box, o, flow.slip_walls) {}

  void init() override { s_.init(); }

  // The stable step, shortened to land on t_end; a step that is not finite and positive throws.
  StepStats advance(double& t, double t_end) override {
    const double dt = std::min(s_.stable_dt(), t_end - t);
    if (!(dt > 0.0) || !std::isfinite(dt))
      throw std::runtime_error("time step " + std::to_string(dt));
    s_.step(dt);
    t = (t_end - t - dt <= 1e-12 * t_end) ? t_end : t + dt;
    return {dt, 0, 0.0, 0.0};
  }
  double stable_dt() const override { return s_.stable_dt(); }

  void wall_velocities_for_output() override {} // solids at rest, mirror ghosts carry their own
  const NeighborList<D>& neighbors() const override { return s_.neighbors(); }
  const std::string& kernel_name() const override { return kernel_; }
  // The smoothing length of a pair of particles of the initial size D0 = flow.dx, alpha 2 D0
  // (eq. 12; h_ij varies with the particle sizes).
  double h() const override { return h0_; }
  // The fluid's force on the solids: minus the solids' force on the fluid at the last midpoint.
  Vec<D> force_on_walls(Vec<D>* viscous) override {
    if (viscous)
      throw std::logic_error(
          "contact: the wall force is not split into viscous and pressure parts");
    return -s_.solid_force();
  }
  void set_body_acceleration(const Vec<D>& g) override { s_.set_body_force(g); }

  std::vector<std::string> state_names() const override { return {"contact/carried"}; }
  void save_state(StateArrays& out) const override { out["contact/carried"] = s_.carried_state(); }
  void load_state(const StateArrays& in) override {
    s_.restore_carried_state(in.at("contact/carried"));
  }
  void add_metrics(RunResult&, double) const override {}
  long work_steps() const override { return static_cast<long>(s_.searches()); } // one per step

private:
  std::string kernel_;
  double h0_;
  Scheme<D, K> s_;
};

template <int D>
std::unique_ptr<FlowScheme<D>> make(const Params& prm, const Flow<D>& flow) {
  const Options o = options_from(prm);
  return with_kernel<D>(o.kernel, 1.0, [&](const auto& k) -> std::unique_ptr<FlowScheme<D>> {
    return std::make_unique<Adapter<D, std::decay_t<decltype(k)>>>(o, flow);
  });
}

} // namespace

Options options_from(const Params& prm) {
  Options o = table().apply(prm);
  const std::string& en = o.eta_num_text;
  if (en != "eq37") {
    std::size_t used = 0;
    try {
      o.eta_num = std::stod(en, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != en.size() || !(o.eta_num >= 0.0))
      throw std::invalid_argument(
          "contact: eta_num must be \"eq37\" or a number >= 0 (Pa s), got '" + en + "'");
  }
  return o;
}

double search_radius(const Params& prm, double Dmax) {
  const Options o = options_from(prm); // as contact::search_radius<K> (contact.hpp)
  return o.skin * o.alpha * 2.0 * Dmax * kernel_support_factor(o.kernel);
}

double eta_num_of(const Options& o, double D0, double Z) {
  return o.eta_num >= 0.0 ? o.eta_num : eta_num_eq37(D0, Z, o.alpha);
}

} // namespace contact

SchemeInfo make_contact_scheme() {
  SchemeInfo s;
  s.name = "contact";
  s.description = "Godunov-type contact SPH with numerical-viscosity correction zeta "
                  "(Parshikov, Medin, Rublev & Dyachkov 2023)";
  s.params = contact::table().specs();
  s.slip_walls = true;
  s.make2 = &contact::make<2>;
  s.make3 = &contact::make<3>;
  return s;
}

namespace {
const Registrar<SchemeInfo> registered(make_contact_scheme()); // core/registry.hpp
} // namespace

} // namespace sph
