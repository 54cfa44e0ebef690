// Registry entry of scheme "alsph" (augmented-Lagrangian SPH, seed 004: Kolukisa, Ozbulut & Yildiz
// 2021, section 2): its parameters, each stated once in a ParamTable bound to the Options member it
// sets, and the FlowScheme<D> the time loop drives, which wraps
// alsph::Scheme<D, QuinticSpline<D>, Real> (schemes/alsph/alsph.hpp: the time integrator; Real the
// storage of its cached pair coefficients, chosen once per job by the parameter `coefficients`).
//
// What the scheme takes from the flow: fixed steps of flow.dt (t = n dt after n steps, a run of
// t_end takes ceil(t_end / dt - 1e-9) steps); nu = U L / Re and rho0; Body particles fixed with
// the pressure of eq. (20) (their outward normals: the vector field flow.normal); Buffer particles
// keep their velocity and take their pressure from flow.buffer_pressure; Flow::slip_walls as
// free-slip mirror ghosts (Kind::Wall, seed 004 Figure 2), dropped and regenerated at the start of
// every step for every fluid and buffer particle within one kernel support of a wall, then the one
// neighbour search of the step (cell sort, pair list with kernel values) and the ghost -> source
// map in the sorted order.
//
// The fluid's force on the bodies (force_on_walls) is the reaction of the fluid-body pair forces,
//   F = - sum_{i fluid} sum_{j body} [ -V_i V_j (p_i + p_j) grad_i W_ij
//                                      + 2 mu V_i V_j (r_ij . grad_i W_ij)/(r_ij^2 + eta^2) (u_i -
//                                      u_j) ],
// the force the paper sums as V_i rho_i a_i over the body particles (section 3), without the
// pressures deeper inside the body than one support.
#include "schemes/alsph/alsph.hpp"
#include "schemes/alsph/scheme_info.hpp"

#include "core/cell_list.hpp"
#include "core/kernels/quintic_spline.hpp"
#include "schemes/scheme.hpp"

#include <cmath>
#include <memory>

namespace sph {
namespace alsph {

namespace {

enum class Precision { Double, Float };

struct Options : Settings {
  double h_over_dx = 1.2;                     // h / dx of the quintic kernel (support 3 h)
  Precision coefficients = Precision::Double; // storage of the cached pair coefficients
};

const ParamTable<Options>& table() {
  static const ParamTable<Options> t =
      ParamTable<Options>()
          .real("c_bv", &Options::c_bv, "C_BV in the penalty r_AL = C_BV u_max^2 dt (eq. 8)",
                {0.0, 1e6, true})
          .real("epsilon", &Options::epsilon,
                "convergence tolerance on max |div u| (eq. 13), in U/D (the paper: 1e-3 1/s)",
                {0.0, {}})
          .integer("max_iterations", &Options::max_iterations,
                   "maximum inner iterations per time step", {1.0, 1000.0})
          .integer("algorithm", &Options::algorithm,
                   "1: derivatives on updated positions r^{n+1,m}; 2: on r^n (section 2.4)",
                   {1.0, 2.0})
          .boolean("shifting", &Options::shifting, "artificial particle displacement (eqs. 18-19)")
          .real("h_over_dx", &Options::h_over_dx,
                "smoothing length h / dx (quintic kernel, support 3h)", {0.5, 3.0})
          .choice("coefficients", &Options::coefficients,
                  {{"double", Precision::Double}, {"float", Precision::Float}},
                  "storage of the cached pair coefficients V_j Gamma_i grad W_ij and the Laplacian "
                  "coefficient (float: half the bytes the inner iterations stream; sums in double)")
          .neutral();
  return t;
}

// The fluid-body pair forces on each fluid particle (file comment), and their viscous part.
template <int D>
struct BodyForceOp {
  const std::vector<Kind>& kind;
  const std::vector<double>& V;
  const std::vector<double>& p;
  const std::vector<Vec<D>>& u;
  double mu, eta2;
  std::vector<Vec<D>>& f;
  std::vector<Vec<D>>& f_visc;
  struct Acc {
    Vec<D> f = Vec<D>::Zero(), fv = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    if (kind[q.j] != Kind::Body)
      return;
    const Vec<D> gw = q.grad();
    const double vv = V[i] * V[q.j];
    const Vec<D> visc = (2.0 * mu * vv * q.r_ij.dot(gw) / (q.r * q.r + eta2)) * (u[i] - u[q.j]);
    a.f -= vv * (p[i] + p[q.j]) * gw;
    a.f += visc;
    a.fv += visc;
  }
  void finish(std::size_t i, const Acc& a) { f[i] = a.f, f_visc[i] = a.fv; }
};

// The time loop's view of alsph::Scheme<D, QuinticSpline<D>, Real> (file comment).
template <int D, class Real>
class Adapter final : public FlowScheme<D> {
public:
  using K = QuinticSpline<D>;

  Adapter(const Options& o, const Flow<D>& flow)
      : p_(*flow.p), flow_(flow), kernel_(o.h_over_dx * flow.dx), s_(kernel_, settings(o, flow)),
        cells_(flow.box, kernel_.support()), cpu0_(cpu_seconds()) {
    if (!(flow.dt > 0.0))
      throw std::invalid_argument("alsph: the flow must give a time step dt > 0");
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (p_.kind[i] == Kind::Body && flow.normal < 0)
        throw std::invalid_argument("alsph: body particles need their normals (Flow::normal)");
  }

  void init() override {}

  sph::StepStats advance(double& t, double) override {
    mirror_ghosts();
    const double ts0 = cpu_seconds();
    cells_.build(p_);
    nl_.build(cells_, p_.r, kernel_);
    search_s_ += cpu_seconds() - ts0;
    map_ghosts();
    if (flow_.normal < 0)
      no_normals_.assign(p_.size(), Vec<D>::Zero());
    const auto& normal = flow_.normal >= 0 ? p_.vector(flow_.normal) : no_normals_;
    last_ = s_.step(
        p_, nl_, ghosts_, normal,
        [this](Particles<D>& q, const NeighborList<D>& l) {
          if (flow_.buffer_pressure)
            flow_.buffer_pressure(q, l);
        },
        g_);
    ++steps_;
    t = static_cast<double>(steps_) * flow_.dt;
    total_iterations_ += last_.iterations;
    converged_steps_ += last_.converged ? 1 : 0;
    return sph::StepStats{flow_.dt, last_.iterations, last_.u_max, 0.0};
  }
  bool finished(double, double t_end) const override {
    return steps_ >= static_cast<long>(std::ceil(t_end / flow_.dt - 1e-9));
  }
  double stable_dt() const override { return flow_.dt; }

  void wall_velocities_for_output() override {} // bodies at rest; ghosts carry mirrored velocities
  const NeighborList<D>& neighbors() const override { return nl_; }
  const std::string& kernel_name() const override { return kernel_name_; }
  double h() const override { return kernel_.h; }

  Vec<D> force_on_walls(Vec<D>* viscous) override {
    f_.resize(p_.size()), fv_.resize(p_.size());
    const double eta2 = std::pow(s_.settings().eta_over_h * kernel_.h, 2);
    BodyForceOp<D> op{p_.kind, p_.V, p_.p, p_.v, flow_.rho0 * flow_.nu(), eta2, f_, fv_};
    interact(nl_, op, [&](std::size_t i) { return p_.kind[i] == Kind::Fluid; });
    Vec<D> F = Vec<D>::Zero(), Fv = Vec<D>::Zero();
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (p_.kind[i] == Kind::Fluid)
        F -= f_[i], Fv -= fv_[i];
    if (viscous)
      *viscous = Fv;
    return F;
  }
  void set_body_acceleration(const Vec<D>& g) override { g_ = g; }

  std::vector<std::string> state_names() const override {
    return {"alsph/timers", "alsph/counters"};
  }
  void save_state(StateArrays& out) const override {
    out["alsph/timers"] = s_.carried_state();
    out["alsph/counters"] = {static_cast<double>(steps_), static_cast<double>(total_iterations_),
                             static_cast<double>(converged_steps_), search_s_, cpu_so_far()};
  }
  void load_state(const StateArrays& in) override {
    s_.restore_carried_state(in.at("alsph/timers"));
    const auto& c = in.at("alsph/counters");
    io::expect_state_size(c, 5, "alsph: checkpoint array alsph/counters");
    steps_ = static_cast<long>(c[0]), total_iterations_ = static_cast<long>(c[1]);
    converged_steps_ = static_cast<long>(c[2]), search_s_ = c[3];
    cpu_before_ = c[4], cpu0_ = cpu_seconds();
  }

  // Of the last step: div_mean, div_max (mean and max |div u| over the fluid), iterations.
  std::vector<std::pair<std::string, double>> probes() const override {
    return {{"div_mean", last_.div_mean},
            {"div_max", last_.div_max},
            {"iterations", static_cast<double>(last_.iterations)}};
  }

  // iterations_mean, converged_fraction (steps meeting eq. 13 before max_iterations); costs in
  // process CPU microseconds per particle: a fresh neighbour search (cells, pairs, kernel values,
  // V, Gamma), one inner iteration, its pair refresh (algorithm 1), the shifting, everything.
  void add_metrics(RunResult& res, double) const override {
    const double steps = static_cast<double>(steps_);
    res.add("iterations_mean", steps_ ? static_cast<double>(total_iterations_) / steps : 0.0);
    res.add("converged_fraction", steps_ ? static_cast<double>(converged_steps_) / steps : 0.0);
    res.add("cpu_s", cpu_so_far());
    const Timers& tm = s_.timers();
    if (steps_ > 0 && tm.particle_steps > 0) {
      const double search_us = 1e6 * (search_s_ + tm.geometry) / tm.particle_steps;
      res.add("search_cpu_us_per_particle", search_us);
      res.add("shifting_cpu_us_per_particle", 1e6 * tm.shifting / tm.particle_steps);
      res.add("cpu_us_per_particle_step", 1e6 * cpu_so_far() / tm.particle_steps);
      if (tm.particle_iterations > 0) {
        const double it_us = 1e6 * tm.iterations / tm.particle_iterations;
        res.add("iteration_cpu_us_per_particle", it_us);
        res.add("refresh_cpu_us_per_particle", 1e6 * tm.refresh / tm.particle_iterations);
        res.add("search_over_iteration", search_us / it_us);
      }
    }
  }
  long work_steps() const override { return steps_; }

private:
  Particles<D>& p_;
  Flow<D> flow_;
  K kernel_;
  Scheme<D, K, Real> s_;
  CellList<D> cells_;
  NeighborList<D> nl_;
  MirrorGhosts<D> ghosts_;
  StepStats last_;
  Vec<D> g_ = Vec<D>::Zero();
  long steps_ = 0, total_iterations_ = 0, converged_steps_ = 0;
  double search_s_ = 0.0, cpu_before_ = 0.0, cpu0_ = 0.0;
  std::vector<char> keep_;
  std::vector<std::int64_t> ghost_src_old_; // per particle before the sort: source index or -1
  std::vector<int> ghost_wall_old_;         // per particle before the sort: its wall or -1
  std::vector<std::uint32_t> inv_;
  std::vector<Vec<D>> f_, fv_, no_normals_;
  const std::string kernel_name_ = "quintic_spline";

  static Settings settings(const Options& o, const Flow<D>& flow) {
    Settings s = o;
    s.nu = flow.nu(), s.rho = flow.rho0, s.dt = flow.dt;
    return s;
  }
  double cpu_so_far() const { return cpu_before_ + cpu_seconds() - cpu0_; }

  // Last step's ghosts out (order kept), a mirror ghost of every fluid and buffer particle within
  // one support of a slip wall appended (walls in their order).
  void mirror_ghosts() {
    keep_.assign(p_.size(), 1);
    bool any = false;
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (p_.kind[i] == Kind::Wall)
        keep_[i] = 0, any = true;
    if (any)
      p_.keep_only(keep_);
    const std::size_t n = p_.size();
    ghost_src_old_.assign(n, -1);
    ghost_wall_old_.assign(n, -1);
    const double support = kernel_.support();
    for (std::size_t i = 0; i < n; ++i) {
      if (p_.kind[i] != Kind::Fluid && p_.kind[i] != Kind::Buffer)
        continue;
      for (std::size_t w = 0; w < flow_.slip_walls.size(); ++w) {
        const SlipWall& wall = flow_.slip_walls[w];
        const double y = p_.r[i][wall.axis];
        if (std::abs(y - wall.position) >= support)
          continue;
        Vec<D> x = p_.r[i], v = p_.v[i];
        x[wall.axis] = 2.0 * wall.position - y;
        v[wall.axis] = -v[wall.axis];
        const std::size_t g = p_.add(x, p_.m[i], p_.rho[i], Kind::Wall);
        p_.v[g] = v, p_.p[g] = p_.p[i], p_.id[g] = -1; // a ghost has no identity
        ghost_src_old_.push_back(static_cast<std::int64_t>(i));
        ghost_wall_old_.push_back(static_cast<int>(w));
      }
    }
  }
  // Ghost -> source in the order of the search's cell sort.
  void map_ghosts() {
    const auto& perm = cells_.perm();
    inv_.resize(perm.size());
    for (std::size_t i = 0; i < perm.size(); ++i)
      inv_[perm[i]] = static_cast<std::uint32_t>(i);
    ghosts_.clear();
    for (std::size_t i = 0; i < perm.size(); ++i) {
      const std::int64_t so = ghost_src_old_[perm[i]];
      if (so < 0)
        continue;
      const SlipWall& wall = flow_.slip_walls[ghost_wall_old_[perm[i]]];
      ghosts_.add(static_cast<std::uint32_t>(i), inv_[static_cast<std::size_t>(so)], wall.axis,
                  wall.position);
    }
  }
};

std::unique_ptr<FlowScheme<2>> make2(const Params& prm, const Flow<2>& flow) {
  const Options o = table().apply(prm);
  if (o.coefficients == Precision::Float)
    return std::make_unique<Adapter<2, float>>(o, flow);
  return std::make_unique<Adapter<2, double>>(o, flow);
}

} // namespace

// The smoothing length of the job's parameters for spacing dx (a case builds its geometry on it).
double smoothing_length(const Params& prm, double dx) {
  return table().apply(prm).h_over_dx * dx;
}

} // namespace alsph

SchemeInfo make_alsph_scheme() {
  SchemeInfo s;
  s.name = "alsph";
  s.description = "Augmented-Lagrangian SPH, Algorithms 1 and 2 (Kolukisa, Ozbulut & Yildiz 2021, "
                  "Symmetry 13:472, section 2)";
  s.params = alsph::table().specs();
  s.slip_walls = true;
  s.make2 = &alsph::make2;
  return s;
}

namespace {
const Registrar<SchemeInfo> registered(make_alsph_scheme()); // core/registry.hpp
} // namespace

} // namespace sph
