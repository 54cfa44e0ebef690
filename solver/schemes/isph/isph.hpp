// Scheme "isph": incompressible SPH by two-step projection, seed 001 (Zheng, Ma & Shao 2018,
// Appl. Sci. 8, 249), section 2, after Cummins & Rudman (1999) and Shao & Lo (2003).
//
// One step, the stages in order (N particles, one neighbour search per step):
//   1. cell list + cached neighbour list on r_t (reorders all particle fields);
//   2. wall velocities for no-slip (Adami, Hu & Adams 2012, J. Comput. Phys. 231, eqs. 22-23;
//      operators/wall_velocity.hpp):
//      u_w = 2 u_prescribed - sum_f u_f W_wf / sum_f W_wf, the fluid velocity mirrored about the
//      wall's prescribed velocity (lid: U0, other walls and bodies: 0);
//   3. prediction, eqs. (7)-(8): u_* = u_t + (nu lap u_t + g) dt, lap u by VISC-01..04 (eqs.
//      15-20, operators/viscous_laplacian.hpp), g a uniform body acceleration
//      (set_body_acceleration; zero in the cavity cases, a channel's drive in poiseuille), the
//      walls carrying their mirror velocity (option visc_wall_velocity = mirror) or their
//      prescribed one (prescribed);
//   4. predicted density at r_* = r_t + u_* dt (eq. 9), by summation over the cached pairs with
//      r_ij* = r_ij + dt (u*_i - u*_j) (walls do not move);
//   5. PPE, eq. (13) with the Laplacian of eq. (14), assembled as a sparse matrix and solved
//      (schemes/isph/ppe_solver.hpp):
//        sum_j 8 m_j / (rho_i + rho_j)^2 P_ij r_ij.grad_i W_ij / (r_ij^2 + eta^2)
//            = (1 - alpha) div u*_i / dt + alpha (rho0 - rho*_i) / (rho0 dt^2),
//      div u*_i by eq. (4) with V_j = m_j / rho_j, the walls carrying their prescribed velocity
//      (option ppe_wall_velocity = prescribed) or their mirror velocity (mirror). The paper
//      prints the source as
//      alpha (rho - rho*) / dt^2 + (alpha - 1) rho div u* / dt for grad^2 P; combining the
//      continuity equation with eq. (10), as the paper says it does, gives the signs used here
//      (with the printed (alpha - 1) the projection would double the divergence instead of
//      removing it). Both sides are divided by rho0 as eq. (14) is grad.(grad P / rho).
//      Wall and body rows: P_w = sum_f P_f W_wf / sum_f W_wf (Adami et al. 2012 eq. 27 without
//      body force and wall acceleration: right for a body force along the walls, as a channel's
//      drive, not for gravity against a wall), a discrete homogeneous Neumann condition, solved
//      implicitly with the fluid rows; the paper uses SFDI instead. The pure-Neumann problem
//      fixes P only up to a constant: the fluid diagonal is raised by a relative 1e-6
//      (regularisation), which selects one level and spreads the source's incompatibility evenly
//      over all particles (pinning one particle to P = 0 instead concentrated it there and
//      drove that particle through the wall at a corner);
//   6. correction, eqs. (10)-(11): u_{t+dt} = u_* - dt grad P / rho0 with the kernel-corrected
//      gradient grad P_i = sum_j V_j (P_j - P_i) Gamma_i grad_i W_ij (eqs. 18-19; option
//      grad_correction, else Gamma = I). The difference form is used instead of eq. (3)
//      because the absolute pressure level is arbitrary in a closed cavity;
//   7. positions, eq. (12): r_{t+dt} = r_t + (u_t + u_{t+dt}) dt / 2, plus particle shifting
//      (option shifting = "fickian"): dr_i = -A h |u_i| dt grad C_i (Skillen, Lind, Stansby &
//      Rogers 2013, Comput. Methods Appl. Mech. Eng. 265, eq. 19, D = A h |u| dt), with
//      grad C_i = sum_j V_j (1 + R (W_ij / W(dx))^n) grad_i W_ij, R = 0.2, n = 4 (Lind, Xu,
//      Stansby & Rogers 2012, J. Comput. Phys. 231, eq. 25), capped at shift_max dx, computed on
//      the configuration of the step (no second neighbour search), and the velocity moved with
//      the particle by a first-order Taylor step u_i += grad u_i . dr_i (Lind et al. 2012);
//   8. wall clearance (a safety net of ours, option wall_clearance): a fluid particle closer than
//      wall_clearance dx to a wall particle is put back at that distance (counted). With the
//      default 0.5 dx, half the spacing of the wall particles, the midpoint between two
//      neighbouring wall particles is at exactly that distance from both: the net lets a particle
//      through the gap, and by removing its velocity towards each of the two it guides it along
//      the gap into the wall. Option wall_clearance_gaps closes the gaps: the distance is also
//      kept from the midpoint of every pair of wall particles at most sqrt(D) dx apart (lattice
//      neighbours and diagonals).
//
// Work arrays are sized at construction; a step allocates nothing in the SPH loops (the sparse
// LU of UMFPACK allocates its own factors).
#pragma once

#include "core/cell_list.hpp"
#include "core/neighbor_list.hpp"
#include "io/checkpoint.hpp"
#include "operators/correction_matrix.hpp"
#include "operators/interact.hpp"
#include "operators/viscous_laplacian.hpp"
#include "operators/wall_velocity.hpp"
#include "schemes/isph/ppe_solver.hpp"
#include "schemes/scheme.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace sph {

// Which velocity a wall or body particle carries into an operator: the no-slip mirror of stage 2
// (u_w = 2 u_prescribed - Shepard mean of the fluid, Adami et al. 2012 eqs. 22-23) or its
// prescribed velocity u_prescribed.
enum class WallVelocityUse { Mirror, Prescribed };

// The scheme's parameters (SchemeInfo "isph", schemes/isph/isph.cpp), read once per job.
struct IsphOptions {
  ViscForm visc = ViscForm::Visc04;
  WallVelocityUse visc_wall = WallVelocityUse::Mirror;    // in the viscous term (stage 3)
  WallVelocityUse ppe_wall = WallVelocityUse::Prescribed; // in div u* of the PPE (stages 4-5)
  double alpha_ppe = 0.01;
  PpeSolverKind solver = PpeSolverKind::BicgstabIlu0;
  double ppe_tol = 1e-6;
  int ppe_max_iter = 500;
  std::string kernel = "cubic_spline";
  double h_over_dx = 1.2;
  double eta_over_h = 0.01;
  bool grad_correction = true;
  bool shifting = true;
  double shift_A = 2.0;
  double shift_max = 0.1; // cap of |dr| in units of dx
  bool shift_velocity = true;
  double wall_clearance = 0.5;      // minimum fluid-wall particle distance / dx (0: off)
  bool wall_clearance_gaps = false; // also keep that distance from the gaps between wall particles

  static IsphOptions from_params(const Params& prm);
};

SchemeInfo make_isph_scheme();

namespace isph_ops {

inline bool is_fluid(Kind k) {
  return k == Kind::Fluid;
}

// Stage 4: rho*_i = m_i W(0) + sum_j m_j W(|r_ij + dt (um_i - um_j)|), um the moving velocity.
template <int D, class Kernel>
struct PredictedDensity {
  const std::vector<double>& m;
  const std::vector<Vec<D>>& um;
  const Kernel& kernel;
  double dt;
  std::vector<double>& rho_star;
  struct Acc {
    double rho = 0.0;
  };
  Acc init(std::size_t i) const { return {m[i] * kernel.W(0.0)}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    const Vec<D> r = q.r_ij + dt * (um[i] - um[q.j]);
    a.rho += m[q.j] * kernel.W(r.norm());
  }
  void finish(std::size_t i, const Acc& a) { rho_star[i] = a.rho; }
};

// Eq. (4): div u_i = -sum_j V_j u_ij . grad_i W_ij.
template <int D>
struct Divergence {
  const std::vector<double>& V;
  const std::vector<Vec<D>>& u;
  std::vector<double>& div;
  struct Acc {
    double s = 0.0;
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    a.s -= V[q.j] * (u[i] - u[q.j]).dot(q.grad());
  }
  void finish(std::size_t i, const Acc& a) { div[i] = a.s; }
};

// Stage 6: grad P_i = sum_j V_j (P_j - P_i) Gamma_i grad_i W_ij, u_i = u*_i - dt grad P_i / rho_i.
template <int D>
struct PressureCorrection {
  const std::vector<double>& V;
  const std::vector<double>& P;
  const std::vector<double>& rho;
  const std::vector<Mat<D>>* gamma; // nullptr: uncorrected
  const std::vector<Vec<D>>& u_star;
  double dt;
  std::vector<Vec<D>>& u_new;
  struct Acc {
    Vec<D> g = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    a.g += V[q.j] * (P[q.j] - P[i]) * q.grad();
  }
  void finish(std::size_t i, const Acc& a) {
    const Vec<D> g = gamma ? Vec<D>((*gamma)[i] * a.g) : a.g;
    u_new[i] = u_star[i] - (dt / rho[i]) * g;
  }
};

// Stage 7: Fickian shifting dr_i = -A h |u_i| dt grad C_i (Skillen et al. 2013; Lind et al. 2012).
template <int D, class Kernel>
struct ShiftingDisplacement {
  const std::vector<double>& V;
  const std::vector<Vec<D>>& u;
  const Kernel& kernel;
  double w_dx; // W(dx)
  double coef; // A h dt
  double max_shift;
  std::vector<Vec<D>>& dr;
  struct Acc {
    Vec<D> g = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t, const Pair<D>& q, Acc& a) const {
    const double f = q.W / w_dx, f2 = f * f;
    a.g += V[q.j] * (1.0 + 0.2 * f2 * f2) * q.grad();
  }
  void finish(std::size_t i, const Acc& a) {
    Vec<D> d = -coef * u[i].norm() * a.g;
    const double n = d.norm();
    if (n > max_shift)
      d *= max_shift / n;
    dr[i] = d;
  }
};

} // namespace isph_ops

template <int D, class Kernel>
class Isph {
public:
  // p: fluid, wall and body particles (m, rho = rho0, V = m / rho set); v_wall: index of the
  // vector field holding every wall/body particle's prescribed velocity.
  Isph(Particles<D>& p, const Domain<D>& domain, const Kernel& kernel, const IsphOptions& opt,
       int v_wall, double nu, double dt, double dx)
      : p_(p), kernel_(kernel), opt_(opt), v_wall_(v_wall), nu_(nu), dt_(dt), dx_(dx),
        cells_(domain, kernel.support()), lap_(opt.visc, kernel, opt.eta_over_h * kernel.h),
        ppe_(opt.solver, opt.ppe_tol, opt.ppe_max_iter),
        eta2_(std::pow(opt.eta_over_h * kernel.h, 2)) {
    const std::size_t N = p.size();
    gamma_.resize(N), trb_.resize(N), lapv_.resize(N), ustar_.resize(N), umove_.resize(N);
    rho_star_.resize(N), div_.resize(N), unew_.resize(N), dr_.resize(N), gradu_.resize(N);
    rhs_.resize(N), x_.resize(N);
    // Reference density: summation density of the initial configuration, averaged over fluid.
    rebuild();
    auto fluid = [this](std::size_t i) { return isph_ops::is_fluid(p_.kind[i]); };
    std::fill(umove_.begin(), umove_.end(), Vec<D>::Zero());
    isph_ops::PredictedDensity<D, Kernel> dens{p_.m, umove_, kernel_, 0.0, rho_star_};
    interact(nl_, dens, fluid);
    double s = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < N; ++i)
      if (fluid(i))
        s += rho_star_[i], ++n;
    if (n == 0)
      throw std::invalid_argument("isph: no fluid particle");
    rho0_sum_ = s / n;
  }

  // Advances the particles by dt.
  void step() {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    const std::size_t N = p_.size();
    auto fluid = [this](std::size_t i) { return isph_ops::is_fluid(p_.kind[i]); };
    auto solid = [this](std::size_t i) { return !isph_ops::is_fluid(p_.kind[i]); };

    // 1. neighbours on r_t
    rebuild();
    const auto& vw = p_.vector(v_wall_);
    // 2. no-slip wall velocities
    WallVelocity<D> wv{p_.kind, vw, p_.v};
    interact(nl_, wv, solid);
    // 3. prediction (eqs. 7-8)
    CorrectionMatrix<D> cm{p_.V, gamma_, trb_};
    interact(nl_, cm, fluid);
    lap_.prepare(nl_, p_.V, fluid);
    lap_.apply(nl_, p_.V, visc_velocity(vw), lapv_, fluid);
    const auto& uwall = opt_.ppe_wall == WallVelocityUse::Mirror ? p_.v : vw;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < N; ++i) {
      if (fluid(i)) {
        ustar_[i] = p_.v[i] + (nu_ * dt_) * lapv_[i] + dt_ * g_; // g = 0: bit for bit as before
        umove_[i] = ustar_[i];
      } else {
        ustar_[i] = uwall[i];
        umove_[i] = Vec<D>::Zero();
      }
    }
    // 4. predicted density at r_* (eq. 9) and div u_* (eq. 4)
    isph_ops::PredictedDensity<D, Kernel> dens{p_.m, umove_, kernel_, dt_, rho_star_};
    interact(nl_, dens, fluid);
    isph_ops::Divergence<D> dv{p_.V, ustar_, div_};
    interact(nl_, dv, fluid);
    // 5. PPE (eqs. 13-14)
    const auto t1 = clock::now();
    assemble();
    const auto t2 = clock::now();
    for (std::size_t i = 0; i < N; ++i)
      x_[i] = p_.p[i];
    last_iters_ = ppe_.solve(rhs_, x_, &p_.id);
    for (std::size_t i = 0; i < N; ++i)
      p_.p[i] = x_[i];
    const auto t3 = clock::now();
    // 6. projection (eqs. 10-11)
    isph_ops::PressureCorrection<D> pc{
        p_.V, p_.p, p_.rho, opt_.grad_correction ? &gamma_ : nullptr, ustar_, dt_, unew_};
    interact(nl_, pc, fluid);
    for (std::size_t i = 0; i < N; ++i)
      if (!fluid(i))
        unew_[i] = ustar_[i]; // the walls' velocity of the PPE source (ppe_wall_velocity)
    if (measure_div_) {
      isph_ops::Divergence<D> dn{p_.V, unew_, div_};
      interact(nl_, dn, fluid);
      double m = 0.0, s2 = 0.0;
      std::size_t nf = 0;
      for (std::size_t i = 0; i < N; ++i) {
        if (!fluid(i))
          continue;
        s2 += div_[i] * div_[i], ++nf;
        if (std::abs(div_[i]) > m)
          m = std::abs(div_[i]), div_argmax_ = p_.r[i];
      }
      div_max_ = m;
      div_rms_ = nf ? std::sqrt(s2 / static_cast<double>(nf)) : 0.0;
    }
    for (std::size_t i = 0; i < N; ++i)
      if (!fluid(i))
        unew_[i] = p_.v[i]; // the no-slip (mirrored) velocity for the velocity gradient
    // 7. shifting on this configuration, then positions (eq. 12)
    if (opt_.shifting) {
      isph_ops::ShiftingDisplacement<D, Kernel> sh{p_.V,
                                                   unew_,
                                                   kernel_,
                                                   kernel_.W(dx_),
                                                   opt_.shift_A * kernel_.h * dt_,
                                                   opt_.shift_max * dx_,
                                                   dr_};
      interact(nl_, sh, fluid);
      if (opt_.shift_velocity) {
        CorrectedGradient<D, Vec<D>> g{p_.V, gamma_, unew_, gradu_};
        interact(nl_, g, fluid);
      }
    }
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < N; ++i) {
      if (!fluid(i))
        continue;
      p_.r[i] += (0.5 * dt_) * (p_.v[i] + unew_[i]);
      if (opt_.shifting) {
        p_.r[i] += dr_[i];
        if (opt_.shift_velocity)
          unew_[i] += gradu_[i] * dr_[i];
      }
      p_.v[i] = unew_[i];
    }
    keep_clear_of_walls();
    const auto t4 = clock::now();
    auto sec = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
    time_step_ += sec(t0, t4), time_assemble_ += sec(t1, t2), time_solve_ += sec(t2, t3);
    iters_total_ += last_iters_;
    ++steps_;
  }

  // What the scheme carries from one step to the next besides the particle fields (for
  // checkpoints): its counters, accumulated timings and last divergence measurement. The pressure,
  // the PPE's warm start, is a particle field; the reference density rho0 is that of the initial
  // lattice, which a resumed job rebuilds before restoring the particles. Restore after
  // construction.
  std::vector<double> carried_state() const {
    std::vector<double> s{static_cast<double>(steps_),
                          static_cast<double>(iters_total_),
                          static_cast<double>(clearance_corrections_),
                          time_step_,
                          time_assemble_,
                          time_solve_,
                          static_cast<double>(last_iters_),
                          div_max_,
                          div_rms_};
    for (int k = 0; k < D; ++k)
      s.push_back(div_argmax_[k]);
    s.push_back(static_cast<double>(clearance_first_step_));
    s.push_back(static_cast<double>(clearance_steps_));
    for (int k = 0; k < D; ++k)
      s.push_back(clearance_first_r_[k]);
    return s;
  }
  void restore_carried_state(const std::vector<double>& s) {
    io::expect_state_size(s, 11 + 2 * D, "isph: checkpoint state");
    steps_ = static_cast<long>(s[0]), iters_total_ = static_cast<long>(s[1]);
    clearance_corrections_ = static_cast<long>(s[2]);
    time_step_ = s[3], time_assemble_ = s[4], time_solve_ = s[5];
    last_iters_ = static_cast<int>(s[6]), div_max_ = s[7], div_rms_ = s[8];
    for (int k = 0; k < D; ++k)
      div_argmax_[k] = s[9 + k];
    clearance_first_step_ = static_cast<long>(s[9 + D]);
    clearance_steps_ = static_cast<long>(s[10 + D]);
    for (int k = 0; k < D; ++k)
      clearance_first_r_[k] = s[11 + D + k];
  }

  // Recomputes the wall velocities of the current configuration (for diagnostics).
  void update_wall_velocity() {
    rebuild();
    WallVelocity<D> wv{p_.kind, p_.vector(v_wall_), p_.v};
    interact(nl_, wv, [this](std::size_t i) { return !isph_ops::is_fluid(p_.kind[i]); });
  }

  // A uniform body acceleration g on the fluid from the next step on (stage 3; zero until set).
  void set_body_acceleration(const Vec<D>& g) {
    g_ = g;
  }

  void set_measure_divergence(bool on) {
    measure_div_ = on;
  }
  double div_max() const {
    return div_max_;
  } // max |div u_{t+dt}| of the last measured step
  double div_rms() const {
    return div_rms_;
  } // RMS of div u_{t+dt} over the fluid, same step
  const Vec<D>& div_argmax() const {
    return div_argmax_;
  }
  // div u_{t+dt} per particle (current order; fluid entries) of the last measured step.
  const std::vector<double>& divergence() const {
    return div_;
  }
  int last_iterations() const {
    return last_iters_;
  }
  double ppe_residual() const {
    return ppe_.last_error();
  }
  const PpeSolver& ppe() const {
    return ppe_;
  }
  long steps() const {
    return steps_;
  }
  double dt() const {
    return dt_;
  }
  long clearance_corrections() const {
    return clearance_corrections_;
  }
  // Where and when the safety net first fired (the step index, -1 if never, and the corrected
  // particle of lowest index at its corrected position), and in how many steps it fired.
  long clearance_first_step() const {
    return clearance_first_step_;
  }
  const Vec<D>& clearance_first_r() const {
    return clearance_first_r_;
  }
  long clearance_steps() const {
    return clearance_steps_;
  }
  double time_step() const {
    return time_step_;
  }
  double time_assemble() const {
    return time_assemble_;
  }
  double time_solve() const {
    return time_solve_;
  }
  long iterations_total() const {
    return iters_total_;
  }
  double rho0() const {
    return rho0_sum_;
  }
  const NeighborList<D>& neighbors() const {
    return nl_;
  }

private:
  Particles<D>& p_;
  Kernel kernel_;
  IsphOptions opt_;
  int v_wall_;
  double nu_, dt_, dx_;
  CellList<D> cells_;
  NeighborList<D> nl_;
  ViscousLaplacian<D, Vec<D>, Kernel> lap_;
  PpeSolver ppe_;
  double eta2_;
  double rho0_sum_ = 1.0;
  std::vector<Mat<D>> gamma_;
  std::vector<double> trb_, rho_star_, div_, rhs_, x_;
  std::vector<Vec<D>> lapv_, ustar_, umove_, unew_, dr_, vvisc_;
  std::vector<Mat<D>> gradu_;
  Vec<D> g_ = Vec<D>::Zero(); // body acceleration (stage 3)
  bool measure_div_ = false;
  double div_max_ = 0.0, div_rms_ = 0.0;
  Vec<D> div_argmax_ = Vec<D>::Zero();
  int last_iters_ = 0;
  long steps_ = 0, iters_total_ = 0, clearance_corrections_ = 0;
  long clearance_first_step_ = -1, clearance_steps_ = 0;
  Vec<D> clearance_first_r_ = Vec<D>::Zero();
  double time_step_ = 0.0, time_assemble_ = 0.0, time_solve_ = 0.0;

  // Safety net against wall penetration (not in the paper): a fluid particle that ends the step
  // closer than wall_clearance dx to a wall or body particle is moved back to that distance along
  // the pair direction and loses its velocity component towards the wall particle. Counted in
  // clearance_corrections(); zero in a healthy run away from the lid corners.
  void keep_clear_of_walls() {
    const double dmin = opt_.wall_clearance * dx_;
    if (dmin <= 0.0)
      return;
    const std::size_t N = p_.size();
    long count = 0;
    std::size_t first = N; // the corrected particle of lowest index
    // Pushes fluid particle i to distance dmin from the point x (wall particles do not move).
    auto keep_from = [&](std::size_t i, const Vec<D>& x) {
      const Vec<D> d = p_.r[i] - x;
      const double r = d.norm();
      if (!(r < dmin && r > 0.0))
        return 0;
      const Vec<D> n = d / r;
      p_.r[i] += (dmin - r) * n;
      const double un = p_.v[i].dot(n);
      if (un < 0.0)
        p_.v[i] -= un * n;
      return 1;
    };
    // Gaps: pairs of wall particles at most sqrt(D) dx apart; a midpoint within dmin of i has
    // both ends within dmin + sqrt(D) dx / 2 of it (inside the kernel support).
    const double pair_max = std::sqrt(static_cast<double>(D)) * dx_ * (1.0 + 1e-9);
    const double near_max = dmin + 0.5 * pair_max;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : count) reduction(min : first)
    for (std::size_t i = 0; i < N; ++i) {
      if (!isph_ops::is_fluid(p_.kind[i]))
        continue;
      int c = 0; // the corrections of particle i
      for (std::uint32_t q = nl_.offset[i]; q < nl_.offset[i + 1]; ++q) {
        const std::uint32_t j = nl_.j[q];
        if (!isph_ops::is_fluid(p_.kind[j]))
          c += keep_from(i, p_.r[j]);
      }
      if (opt_.wall_clearance_gaps) {
        std::uint32_t near[64];
        int n_near = 0;
        for (std::uint32_t q = nl_.offset[i]; q < nl_.offset[i + 1] && n_near < 64; ++q) {
          const std::uint32_t j = nl_.j[q];
          if (!isph_ops::is_fluid(p_.kind[j]) && (p_.r[i] - p_.r[j]).norm() < near_max)
            near[n_near++] = j;
        }
        for (int a = 0; a < n_near; ++a)
          for (int b = a + 1; b < n_near; ++b)
            if ((p_.r[near[a]] - p_.r[near[b]]).norm() <= pair_max)
              c += keep_from(i, 0.5 * (p_.r[near[a]] + p_.r[near[b]]));
      }
      count += c;
      if (c > 0)
        first = std::min(first, i);
    }
    clearance_corrections_ += count;
    if (count > 0) {
      ++clearance_steps_;
      if (clearance_first_step_ < 0)
        clearance_first_step_ = steps_, clearance_first_r_ = p_.r[first];
    }
  }

  // The velocity field of the viscous term: the particles' own (walls: the no-slip mirror of
  // stage 2), or with visc_wall_velocity = prescribed the walls' prescribed velocity vw.
  const std::vector<Vec<D>>& visc_velocity(const std::vector<Vec<D>>& vw) {
    if (opt_.visc_wall == WallVelocityUse::Mirror)
      return p_.v;
    const std::size_t N = p_.size();
    vvisc_.resize(N);
    for (std::size_t i = 0; i < N; ++i)
      vvisc_[i] = isph_ops::is_fluid(p_.kind[i]) ? p_.v[i] : vw[i];
    return vvisc_;
  }

  void rebuild() {
    cells_.build(p_);
    nl_.build(cells_, p_.r, kernel_);
  }

  // CSR of the PPE: row i holds its neighbours and the diagonal, columns ascending (ILU(0) and the
  // diagonal look-ups of the solvers need them sorted). The cell list emits ascending j except in a
  // periodic domain, where the stencil wraps: such a row is sorted after it is filled.
  void assemble() {
    const std::size_t N = p_.size();
    auto& off = ppe_.offset;
    auto& col = ppe_.col;
    auto& val = ppe_.val;
    off.resize(N + 1);
    for (std::size_t i = 0; i <= N; ++i)
      off[i] = static_cast<std::int32_t>(nl_.offset[i] + i);
    col.resize(off[N]), val.resize(off[N]);
    const double a = opt_.alpha_ppe, r0 = rho0_sum_;
    const double wall_scale = 1.0 / (dx_ * dx_);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::size_t i = 0; i < N; ++i) {
      std::int32_t k = off[i];
      const std::uint32_t b = nl_.offset[i], e = nl_.offset[i + 1];
      const bool fl = isph_ops::is_fluid(p_.kind[i]);
      double wsum = 0.0;
      if (!fl)
        for (std::uint32_t q = b; q < e; ++q)
          if (isph_ops::is_fluid(p_.kind[nl_.j[q]]))
            wsum += nl_.W[q];
      double diag = 0.0;
      std::int32_t kdiag = -1;
      for (std::uint32_t q = b; q < e; ++q) {
        const std::uint32_t j = nl_.j[q];
        if (kdiag < 0 && j > i)
          kdiag = k++;
        double c = 0.0;
        if (fl) {
          const double rs = p_.rho[i] + p_.rho[j];
          c = -8.0 * p_.m[j] / (rs * rs) * nl_.r[q] * nl_.dW[q] / (nl_.r[q] * nl_.r[q] + eta2_);
          diag += c;
        } else if (wsum > 0.0 && isph_ops::is_fluid(p_.kind[j])) {
          c = wall_scale * nl_.W[q] / wsum;
        }
        col[k] = static_cast<std::int32_t>(j);
        val[k] = -c;
        ++k;
      }
      if (kdiag < 0)
        kdiag = k++;
      col[kdiag] = static_cast<std::int32_t>(i);
      if (fl) {
        val[kdiag] = diag * (1.0 + 1e-6);
        rhs_[i] = -((1.0 - a) * div_[i] / dt_ + a * (r0 - rho_star_[i]) / (r0 * dt_ * dt_));
      } else {
        val[kdiag] = wall_scale;
        rhs_[i] = 0.0;
      }
      sort_row(col.data() + off[i], val.data() + off[i], off[i + 1] - off[i]);
    }
  }

  // Insertion sort of one CSR row by column (rows hold ~30 entries; already sorted: one pass).
  static void sort_row(std::int32_t* c, double* v, std::int32_t n) {
    for (std::int32_t a = 1; a < n; ++a) {
      const std::int32_t ca = c[a];
      const double va = v[a];
      std::int32_t b = a;
      for (; b > 0 && c[b - 1] > ca; --b)
        c[b] = c[b - 1], v[b] = v[b - 1];
      c[b] = ca, v[b] = va;
    }
  }
};

} // namespace sph
