// Case "cylinder_array": slow (Stokes) flow through a square array of cylinders, seed 003
// (Parshikov et al.), section 5.5 and Table 2, run with scheme "contact" with and without the
// numerical-viscosity correction zeta; reference: Sangani & Acrivos, Int. J. Multiphase Flow 8
// (1982) 193-206 (Table 1: K against the solid fraction c), and the paper's eq. (39).
//
// Set-up (2D): one cylinder of diameter d at the centre of a periodic square cell of side S (the
// array of period S, Fig. 10). A lattice of particles of size D0 = d / n_d; S = N D0 with
// N = round(n_d / d_over_S) (so d/S is rounded to a lattice: metric d_over_S_used). Lattice points
// with |x| >= d/2 are fluid; those with d/2 - 1.05 R_search < |x| < d/2 are the solid, a no-slip
// wall at rest (contact.hpp: mirrored velocity and pressure per pair). The fluid starts at rest and
// is driven by a uniform body force g along x, equivalent to a mean pressure gradient G = rho0 g
// (reference/analytic_solutions section 4: with a body force on the fluid only the flow is that of
// the pressure gradient G, whose drag per unit length is F = G S^2).
//
// Drive: G = K_d(c) eta U / S^2 with U = Re eta / (rho0 d) and K_d the dilute expansion of
// Sangani & Acrivos (eq. 13 there, 4 pi / (-ln(c)/2 - 0.738 + c - 0.887 c^2 + 2.038 c^3)): the
// pressure gradient that would give Reynolds number Re if the drag were that of the dilute
// theory. It only sets the forcing level; every metric is measured.
//
// Measurement, at t = (0.8, 0.9, 1.0) t_end, t_end = t_end_visc S^2 rho0 / eta:
//   U_s        superficial velocity: (1/S^2) sum_fluid V_i U_x,i (flow rate per unit width)
//   K          dimensionless drag F / (eta U_s) = G S^2 / (eta U_s): compare with Sangani &
//              Acrivos's K(c) (their Table 1); with the numerical viscosity uncorrected K grows by
//              about (eta + eta_num) / eta
//   Re         rho0 U_s d / eta
//   CD         drag coefficient F / (rho0 U_s^2 d / 2) = 2 K / Re (seed 003, section 5.5)
//   CD_eq39    16 pi a0 / Re, seed 003 eq. (39), a0 the series in omega = pi d / (2 S)
//   CD_ratio   CD / CD_eq39 (= K / (8 pi a0); Table 2 of seed 003 gives 1.13-1.33 corrected,
//              2.5-3.4 uncorrected)
//   U_drift    |U_s(t_end) - U_s(0.8 t_end)| / U_s(t_end): how close to steady the flow is
//   drag_balance  the drag measured on the solid particles (pair forces) over the body force on
//              the fluid, g M_fluid: 1 in a steady state
// Fig. 11c: the tangential velocity u_t = u . (sin theta, -cos theta) (clockwise: along the flow
// over the top of the cylinder; theta from the +x axis, the flow direction) along rays at theta =
// 90, 75, 60, 45, 30 and 15 degrees, from the first fluid row r = a + D0/2 to S/2, at t_end, by
// Shepard interpolation of the fluid particles (Wendland C2, h = 1.3 D0): metric ut_max_90 (the
// largest u_t / U_s on the 90-degree ray) and, with an output directory, cylinder_array.h5 columns
// rays/{r_over_a, ut_90, ut_75, ...} in units of U_s (the final particles for ParaView's
// streamlines are the loop's snapshot). Cost (besides the time loop's): wall_s, wall_per_step_s,
// n_fluid, n_solid. Runs on the shared time loop (cases/time_loop.hpp) with scheme contact; the
// drive is the scheme's body acceleration; checkpoints carry the samples taken so far.
#include "cases/loop_params.hpp"
#include "cases/materials.hpp"
#include "cases/time_loop.hpp"
#include "core/kernels/wendland_c2.hpp"
#include "core/lattice.hpp"
#include "io/job_attributes.hpp"
#include "schemes/contact/scheme_info.hpp"

#include <string>
#include <vector>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace sph {

// Seed 003, eq. (39): the coefficient a0 of C_D = 16 pi a0 / Re, omega = pi d / (2 S).
double cylinder_array_a0(double d_over_S) {
  const double w = std::numbers::pi * d_over_S / 2.0, w2 = w * w;
  const double c[] = {2.0 / 3.0,          -1.0 / 9.0,       8.0 / 135.0,
                      -53.0 / 1350.0,     1112.0 / 42525.0, -241643.0 / 13395375.0,
                      18776.0 / 1488375.0};
  double s = 1.0 - 2.0 * std::log(2.0 * w), wp = 1.0;
  for (double ck : c)
    wp *= w2, s += ck * wp;
  return 1.0 / s;
}

namespace {

// Sangani & Acrivos (1982) eq. 13, the dilute expansion of K (used only to set the drive).
double k_dilute(double c) {
  return 4.0 * std::numbers::pi /
         (-0.5 * std::log(c) - 0.738 + c - 0.887 * c * c + 2.038 * c * c * c);
}

class CylinderArrayCase final : public FlowCase<2> {
public:
  CylinderArrayCase(const Params& prm, const RunContext& ctx) : prm_(prm), ctx_(ctx) {
    const Material& mat = material_or_throw(get_string(prm, "material"), "cylinder_array");
    rho0_ = mat.rho0, c0_ = mat.c0;
    eta_ = liquid_viscosity(get_real(prm, "eta"), mat, "cylinder_array");
    d_ = get_real(prm, "d");
    const int n_d = static_cast<int>(get_int(prm, "n_d"));
    D0_ = d_ / n_d;
    N_ = static_cast<int>(std::lround(n_d / get_real(prm, "d_over_S")));
    S_ = N_ * D0_;
    if (S_ <= d_ + 2.0 * D0_)
      throw std::invalid_argument("cylinder_array: d_over_S too close to 1 for n_d = " +
                                  std::to_string(n_d) + " (less than 2 particles in the gap)");
    const double a = 0.5 * d_;
    c_ = std::numbers::pi * a * a / (S_ * S_);
    const double U_target = get_real(prm, "Re") * eta_ / (rho0_ * d_);
    G_ = k_dilute(c_) * eta_ * U_target / (S_ * S_);
    t_end_ = get_real(prm, "t_end_visc") * S_ * S_ * rho0_ / eta_;
  }

  Flow<2> build(Particles<2>& p) override {
    p_ = &p;
    const double Rs = contact::search_radius(prm_, 1.05 * D0_);
    if (S_ < 3.0 * Rs)
      throw std::invalid_argument("cylinder_array: the cell (S = " + std::to_string(N_) +
                                  " D0) is smaller than 3 search radii; raise n_d");
    const contact::Fields f = contact::Fields::add_to(p);
    const double vol = D0_ * D0_, a = 0.5 * d_;
    for_each_lattice_point<2>({0, 0}, {N_, N_}, D0_, [&](Vec<2> x, const std::array<int, 2>&) {
      x[0] -= 0.5 * S_, x[1] -= 0.5 * S_;
      const double r = x.norm();
      if (r < a - 1.05 * Rs)
        return;
      const bool solid = r < a;
      const std::size_t i = p.add(x, rho0_ * vol, rho0_, solid ? Kind::Wall : Kind::Fluid);
      p.scalar(f.rho0)[i] = rho0_;
      p.scalar(f.c0)[i] = c0_;
      p.scalar(f.eta)[i] = eta_;
      n_fluid_ += !solid;
    });
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid)
        M_fluid_ += p.m[i];
    n_solid_ = p.size() - n_fluid_;

    Flow<2> flow;
    flow.box.lo = Vec<2>::Constant(-0.5 * S_);
    flow.box.hi = Vec<2>::Constant(0.5 * S_);
    flow.box.periodic = {true, true};
    flow.rho0 = rho0_, flow.dx = D0_, flow.L = d_;
    return flow;
  }
  // The drive: a uniform body force g = G / rho0 along x on the fluid.
  void start(FlowScheme<2>& s) override { s.set_body_acceleration(Vec<2>(G_ / rho0_, 0.0)); }
  double t_end() const override { return t_end_; }
  // Only a speed that is not finite: the density test below is this case's divergence test.
  double speed_bound() const override { return std::numeric_limits<double>::max(); }

  // Every 100 steps and at the samples: diverged when a density deviates by more than 10 %. The
  // superficial velocity at t = (0.8, 0.9, 1.0) t_end.
  bool after_step(FlowScheme<2>&, const LoopState& at, const StepStats&) override {
    const Particles<2>& p = *p_;
    if (at.steps % 100 == 0 || (next_ < 3 && at.t >= sample_at[next_] * t_end_ * (1.0 - 1e-12)))
      contact::check_density_deviation(p, max_drho_, 0.1, at.steps);
    while (next_ < 3 && at.t >= sample_at[next_] * t_end_ * (1.0 - 1e-12))
      U_k_[next_++] = superficial();
    return false;
  }

  void finish(FlowScheme<2>& s, const LoopState& at, RunResult& res) override {
    const double U_s = U_k_[2];
    const double Kd = G_ * S_ * S_ / (eta_ * U_s);
    const double Re = rho0_ * U_s * d_ / eta_;
    const double CD = 2.0 * Kd / Re;
    const double CD39 = 16.0 * std::numbers::pi * cylinder_array_a0(d_ / S_) / Re;
    res.add("K", Kd);
    res.add("U_s", U_s);
    res.add("Re", Re);
    res.add("CD", CD);
    res.add("CD_eq39", CD39);
    res.add("CD_ratio", CD / CD39);
    res.add("U_drift", std::abs(U_k_[2] - U_k_[0]) / std::abs(U_s));
    res.add("drag_balance", s.force_on_walls()[0] / (G_ / rho0_ * M_fluid_));
    res.add("solid_fraction", c_);
    res.add("d_over_S_used", d_ / S_);
    res.add("eta_phys", eta_);
    res.add("eta_num_ref", contact::eta_num_of(contact::options_from(prm_), D0_, rho0_ * c0_));
    res.add("D0", D0_);
    res.add("t_end", t_end_);
    res.add("max_density_dev", max_drho_);
    res.add("wall_s", at.wall_s);
    res.add("wall_per_step_s", at.wall_s / at.steps);
    res.add("n_fluid", static_cast<double>(n_fluid_));
    res.add("n_solid", static_cast<double>(n_solid_));
    rays(U_s, res);
  }

  std::vector<std::string> state_names() const override { return {"cylinder_array/samples"}; }
  void save_state(StateArrays& out) const override {
    out["cylinder_array/samples"] = {max_drho_, static_cast<double>(next_), U_k_[0], U_k_[1],
                                     U_k_[2]};
  }
  void load_state(const StateArrays& in) override {
    const auto& a = in.at("cylinder_array/samples");
    io::expect_state_size(a, 5, "cylinder_array: checkpoint array cylinder_array/samples");
    max_drho_ = a[0], next_ = static_cast<int>(a[1]);
    U_k_[0] = a[2], U_k_[1] = a[3], U_k_[2] = a[4];
  }

private:
  static constexpr double sample_at[3] = {0.8, 0.9, 1.0};
  Params prm_;
  RunContext ctx_;
  double rho0_ = 0.0, c0_ = 0.0, eta_ = 0.0, d_ = 0.0, D0_ = 0.0, S_ = 0.0, c_ = 0.0, G_ = 0.0;
  double t_end_ = 0.0, M_fluid_ = 0.0, max_drho_ = 0.0;
  double U_k_[3] = {0.0, 0.0, 0.0};
  int N_ = 0, next_ = 0;
  std::size_t n_fluid_ = 0, n_solid_ = 0;
  Particles<2>* p_ = nullptr;

  // The tangential-velocity profiles along the rays (file comment).
  void rays(double U_s, RunResult& res) const {
    const Particles<2>& p = *p_;
    const WendlandC2<2> K(1.3 * D0_);
    const double a = 0.5 * d_, r_in = a + 0.5 * D0_, r_out = 0.5 * S_, support = K.support();
    const int n = std::max(2, static_cast<int>(std::round((r_out - r_in) / (0.5 * D0_))) + 1);
    const int angles[] = {90, 75, 60, 45, 30, 15};
    std::vector<std::vector<double>> cols(7, std::vector<double>(n));
    std::vector<std::string> names{"r_over_a"};
    for (int k = 0; k < n; ++k)
      cols[0][k] = (r_in + (r_out - r_in) * k / (n - 1)) / a;
    double ut_max_90 = 0.0;
    for (int c = 0; c < 6; ++c) {
      names.push_back("ut_" + std::to_string(angles[c]));
      const double th = angles[c] * std::numbers::pi / 180.0;
      const Vec<2> er(std::cos(th), std::sin(th)), et(std::sin(th), -std::cos(th));
      for (int k = 0; k < n; ++k) {
        const Vec<2> x = cols[0][k] * a * er;
        double w = 0.0, u = 0.0;
        for (std::size_t i = 0; i < p.size(); ++i) {
          if (p.kind[i] != Kind::Fluid)
            continue;
          Vec<2> dx = x - p.r[i];
          for (int ax = 0; ax < 2; ++ax)
            dx[ax] -= S_ * std::round(dx[ax] / S_); // periodic cell: minimum image
          const double r = dx.norm();
          if (r >= support)
            continue;
          const double wi = p.m[i] / p.rho[i] * K.W(r);
          w += wi, u += wi * p.v[i].dot(et);
        }
        cols[1 + c][k] = w > 0.0 ? u / w / U_s : 0.0;
        if (angles[c] == 90)
          ut_max_90 = std::max(ut_max_90, cols[1 + c][k]);
      }
    }
    res.add("ut_max_90", ut_max_90);
    if (auto h5 = io::open_job_output(ctx_, "cylinder_array", prm_)) {
      h5->write_columns("rays", names, cols);
      h5->close();
    }
  }

  // Superficial velocity (1/S^2) sum_fluid V_i U_x,i.
  double superficial() const {
    double q = 0.0;
    for (std::size_t i = 0; i < p_->size(); ++i)
      if (p_->kind[i] == Kind::Fluid)
        q += p_->m[i] / p_->rho[i] * p_->v[i][0];
    return q / (S_ * S_);
  }
};

RunResult run_cylinder_array(const Params& prm, const RunContext& ctx) {
  CylinderArrayCase c(prm, ctx);
  return run_flow_case<2>(c, prm, ctx, "contact");
}

} // namespace

CaseInfo make_cylinder_array_case() {
  CaseInfo c;
  c.name = "cylinder_array";
  c.description =
      "Stokes flow through a square array of cylinders: drag K vs Sangani & Acrivos "
      "(1982); contact SPH with and without the zeta correction (Parshikov et al. 2023, 5.5)";
  c.schemes = {"contact"};
  c.params = {
      {"material",
       ParamType::String,
       std::string("glycerol"),
       "liquid: a Table 1 material of Parshikov et al. 2023 (rho0, c0, eta)",
       {},
       {},
       false,
       material_keys()},
      {"eta", ParamType::Real, -1.0, "dynamic viscosity, Pa s (< 0: the material's)", -1.0, {}},
      {"d", ParamType::Real, 1e-3, "cylinder diameter, m", 0.0, {}, true},
      {"d_over_S", ParamType::Real, 0.5, "diameter over the period of the array", 0.0, 0.85, true},
      {"n_d", ParamType::Int, std::int64_t{20}, "particles per cylinder diameter (D0 = d / n_d)",
       4.0, 10000.0},
      {"Re", ParamType::Real, 0.005,
       "Reynolds number rho0 U d / eta that sets the drive (dilute-theory estimate; Re is "
       "measured)",
       0.0, 1.0, true},
      {"t_end_visc",
       ParamType::Real,
       0.15,
       "end time in units of the viscous time S^2 rho0 / eta",
       0.0,
       {},
       true},
  };
  add_loop_params(c.params); // output_interval (cases/loop_params.hpp)
  c.run = [](const Params& prm, const RunContext& ctx) { return run_cylinder_array(prm, ctx); };
  c.size = [](const Params& prm) {
    const RunContext none;
    CylinderArrayCase c(prm, none);
    return size_flow_case<2>(c, prm, "contact");
  };
  return c;
}

namespace {
const Registrar<CaseInfo> registered(make_cylinder_array_case()); // core/registry.hpp
} // namespace

} // namespace sph
