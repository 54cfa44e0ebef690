// Scheme "wcsph_tvf": weakly-compressible SPH with the linearised Riemann solver, dual-criteria
// time stepping and the transport-velocity correction with its limiter (seed 002: Wang, Haidn &
// Hu, "The efficient implementation of transport velocity formulation", arXiv:2411.13992).
// The seed's text lost its equations; they are rebuilt from the authors' code (SPHinXsys) in
// ../shared/notes/tvf_equations.md, whose section numbers are cited below as [notes 2b] etc.
// docs/tvf.md states every equation implemented here and where we depart from SPHinXsys.
//
// Conventions [notes 1]: e_ij = r_ij / |r_ij| with r_ij = r_i - r_j (points from j to i),
// dW_ij = dW/dr <= 0, grad_i W_ij = dW_ij e_ij. V_i = m_i / rho_i is set by the density
// summation once per advection step and frozen during the acoustic sub-steps, like the pair
// geometry (W_ij, dW_ij, e_ij come from the neighbour list built at the end of the previous
// advection step).
//
// Per advection step of size Dt (stage_names(): the list is built once from the options, a stage
// that is off left out):
//   density_summation  rho_i = rho0 sum_j W_ij / sigma0 (self term included; sigma0 = sum W on
//                      the perfect lattice), V_i = m_i / rho_i                 (eq. 8) [notes 3]
//   correction_matrix  (kernel_correction only) B_i = [sum_j V_j grad_i W_ij (x) (r_j - r_i)]^-1
//   viscous_force      F^nu_i = V_i sum_j 2 mu (v_i - v_j) / (r_ij + 0.01 h) V_j dW_ij [notes 2d]
//                      F_prior_i = F^nu_i + m_i g (g: a body acceleration, zero by default)
//   transport          tvf = smoothing_length / limited (eqs. 14-16) [notes 5]:
//                        g_i  = -sum_j (B_i + B_j) V_j dW_ij e_ij     (B = I without correction)
//                        psi_i = min(kappa h^2 |g_i|^2, 1) (limited), 1 (smoothing_length)
//                        r_i += alpha h^2 psi_i g_i,   alpha = 0.2, kappa = 100
//                      shift_velocity (option, not in seed 002): then v_i += (grad v_i) Delta r_i,
//                        grad v_i = sum_j V_j (v_j - v_i) (x) B_i grad_i W_ij (ops::ShiftVelocity)
//                      tvf = original (Adami, Hu & Adams 2013, eq. 13; eq. 12 of seed 002):
//                        a~_i = -(p_b / m_i) sum_j (V_i^2 + V_j^2) dW_ij e_ij, p_b = f_pb rho0
//                        c0^2, used by the kick-drift-kick transport of every acoustic sub-step
//                        below
//   acoustic           sub-steps dt = min(Dt_ac, Dt - tau) until tau = Dt, position Verlet
//                      [notes 4]:
//     1st half: rho_i += dt/2 drho_i; p_i = c0^2 (rho_i - rho0); r_i += dt/2 vt_i
//               F^p_i = -V_i sum_j (p_i B_j + p_j B_i) V_j dW_ij e_ij  (Riemann P* mean part)
//               drho_i = rho_i sum_j (p_i - p_j) / (rho0 c0) V_j dW_ij (Riemann U* jump part)
//               v_i += dt (F_prior_i + F^p_i + F^diss_i) / m_i   (F^diss from the last 2nd half)
//     2nd half: r_i += dt/2 vt_i
//               drho_i += rho_i sum_j u_ij V_j dW_ij,  u_ij = (v_i - v_j) . e_ij   (continuity)
//               F^diss_i = V_i sum_j rho0 c0 beta_ij u_ij V_j dW_ij e_ij  (Riemann P* jump part)
//               rho_i += dt/2 drho_i
//     with the dissipation limiter (eq. 6; Zhang, Hu & Adams 2017):
//       beta_ij = min(3 max(s u_ij, 0) / c0, 1)   limited; s = +1 "expansion" (SPHinXsys master),
//                                                  s = -1 "compression" (Zhang 2017) [notes 2b]
//       beta_ij = 1 (full, no limiter) or 0 (none: central 2nd half, SPHinXsys' Taylor-Green)
//     (policy types LimitedBeta, FullBeta, NoBeta, chosen outside the pair loops). The sub-steps'
//     pair loops read e_ij = r_ij / r and V_j dW_ij from ops::AcousticPairs, computed once at the
//     start of the stage (V_j and the pair geometry are frozen over the step).
//     vt_i = v_i, or v_i + dt/2 a~_i for tvf = original (Adami's transport velocity at the half
//     step, so each sub-step moves the particle by an extra dt^2/2 a~_i), whose momentum equation
//     also gets the extra stress A = rho v (x) (vt - v):  F^A_i = -V_i sum_j V_j (A_i + A_j) .
//     grad_i W_ij
//     Switches that change one piece of SPHinXsys' scheme, to separate error sources (defaults:
//     SPHinXsys'): riemann_density = false drops the 1st half's drho term; wall_extrapolation =
//     false sets p_w = p_i; substep_pairs = true recomputes r_ij, W, dW (not V_j) from the current
//     positions at every sub-step (candidates from a Verlet list rebuilt every step, with a skin of
//     at least half the support; a particle moving further within a step stops the run).
//   neighbours         wrap periodic axes; when a particle has moved more than skin/2 since the
//                      last build, sort by cell and rebuild the Verlet list (cutoff = support +
//                      skin, core/verlet_list.hpp); the pair geometry (r_ij, r, W, dW of the
//                      pairs within the support) of the new positions, every step.
// Time steps (eqs. 9-11) [notes 4]:
//   Dt_ad = cfl_ad h / max(sqrt(max_i max(|v_i|^2, 4 h |F^diss_i + F_prior_i| / m_i)), U_ref, nu/h)
//   Dt_ac = cfl_ac h / max_i (c0 + |v_i|),  cfl_ad = 0.25, cfl_ac = 0.6.
//
// Variable resolution (seed 002 section 4.4; Fields::h, a per-particle smoothing length): the
// pairs' kernel has h_ij = (h_i + h_j) / 2 (core/neighbor_list.hpp), the density is the mass
// summation ops::MassSummation, the TVF shift of eqs. (14)-(16) uses h_i (the point of the seed's
// h^2 scaling: Adami's background pressure has no length scale to adapt), and both time steps use
// the smallest h. Particles keep their h (no splitting or merging).
//
// Walls (Kind::Wall particles with a prescribed velocity field, e.g. the cavity) [notes 2c]:
// counted in the density summation; in the 1st half with p_w = p_i + rho_i |r_iw|
// max(0, (F_prior_i / m_i) . (-e_iw)); in the continuity, dissipation and viscous force with
// v_w* = 2 v_wall - v_i. Wall particles are not integrated. The dissipation of a wall pair acts
// along e_iw on (v_i - v_w*) . e_iw (wall_dissipation = pair), or, as SPHinXsys', along the wall
// particle's normal n_w on (v_i - v_w*) . n_w (normal; the case's Flow::normal), so that fluid
// sliding past a wall gets none.
//
// Moving bodies coupled to a solid (fluid-structure interaction; coupling/fsi.hpp; Zhang,
// Rezavand & Hu, JCP 429 (2021) 110028, section 3, and SPHinXsys' fluid_structure_interaction/
// fluid_structure_interaction.{h,hpp}, read for the formulas): with Fields::a_wall the wall
// pressure extrapolation uses the relative acceleration, p_w = p_i + rho_i |r_iw|
// max(0, (F_prior_i / m_i - a_w) . (-e_iw)); with Fields::f_body every Wall particle w gets the
// reaction of the very pair terms its fluid partners i felt from it (Newton's third law), summed
// over the acoustic sub-steps as the impulses the fluid took and averaged over the step:
//   F_w = (1 / Dt) sum_k dt_k sum_i -( F^nu_iw + F^p_iw,k + F^diss_iw,k-1 )
// (F^nu of the step, F^p of sub-step k's 1st half, F^diss of the 2nd half before it: what the
// kick of sub-step k used), so sum_i m_i dv_i + Dt sum_w F_w = 0 to round-off over any steps.
// The body_motion hook runs after the sub-steps, before the neighbour search: the case moves the
// walls (advances the solid over the step and copies its positions, velocities, accelerations).
//
// Open boundaries (boundaries/open_boundary.hpp; Flow's hooks, set with set_boundary_hooks):
// Buffer particles (inflow and outflow buffers) are not integrated but drift with their velocity
// in both half steps (the case prescribes it), and are partners of every pair loop with their own
// v, p and V = m / rho; Flow::buffer_pressure sets their pressure after every pressure update.
// A free-stream boundary (Zhang et al. 2023) adds: before_density / after_density around the
// density reinitialisation, after_kick after every velocity update of the 1st half, and the
// surface indicator field, whose particles the transport-velocity shift skips (SPHinXsys'
// TransportVelocityCorrection<BulkParticles>). A case that adds or removes particles calls
// particles_changed(): the Verlet list is rebuilt on the new set.
//
// The transport-velocity magnitude of the over-correction indicator (seed 002, Fig. 1) is
// |Delta r^tvf_i| / Dt: the shift the correction adds in one advection step over that step.
#pragma once

#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "core/verlet_list.hpp"
#include "io/checkpoint.hpp"
#include "operators/correction_matrix.hpp"
#include "operators/interact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace sph::wcsph_tvf {

enum class Tvf { None, Original, SmoothingLength, Limited };
enum class Dissipation { Limited, Full, None };
enum class LimiterSign { Expansion, Compression };
enum class WallDissipation { Pair, Normal };

struct Options {
  Tvf tvf = Tvf::Limited;
  Dissipation dissipation = Dissipation::Limited;
  LimiterSign sign = LimiterSign::Expansion;
  bool kernel_correction = false;
  double rho0 = 1.0;         // reference density
  double c0 = 10.0;          // artificial sound speed (10 U_ref)
  double mu = 0.01;          // dynamic viscosity
  double U_ref = 1.0;        // reference speed of the advection criterion
  double h = 0.013;          // smoothing length (1.3 dx)
  double dx = 0.01;          // lattice spacing (sigma0, particle volume)
  double cfl_ad = 0.25;      // advection CFL (eq. 9)
  double cfl_ac = 0.6;       // acoustic CFL (eq. 11)
  double limiter_eta = 3.0;  // slope of the dissipation limiter (eq. 6)
  double tvf_alpha = 0.2;    // coefficient of eq. (14)
  double tvf_kappa = 100.0;  // slope of the limiter, eq. (15)
  double pb_factor = 1.0;    // original TVF: p_b = pb_factor rho0 c0^2
  double viscous_eps = 0.01; // r_ij + eps h in the viscous force

  // Switches that leave out or add one piece of SPHinXsys' scheme (defaults: SPHinXsys'), to
  // separate error sources (docs/tvf.md):
  bool shift_velocity = false;    // v_i += (grad v_i) Delta r_i after the TVF shift (ShiftVelocity)
  bool riemann_density = true;    // 1st half: drho_i = rho_i sum (p_i - p_j)/(rho0 c0) V_j dW_ij
  bool wall_extrapolation = true; // p_w = p_i + rho_i r max(0, a . (-e)); false: p_w = p_i
  bool substep_pairs = false;     // the pairs of the current positions at every sub-step
  // Riemann dissipation of a wall pair: along e_iw on (v_i - v_w*) . e_iw (pair), or along the
  // wall particle's normal n_w on (v_i - v_w*) . n_w (normal; SPHinXsys' walls; Fields::n_wall)
  WallDissipation wall_dissipation = WallDissipation::Pair;

  // Verlet skin as a fraction of the support (of the coarsest with two levels; not a job parameter:
  // it changes the cost and the particle order, so results by round-off only). 0.25 by measurement:
  // Taylor-Green n = 100, 205 advection steps, 1 thread, CPU per step relative to skin 0 (a search
  // every step): 0.91-0.94 at 0.25 (91 builds), 0.95-0.98 at 0.5 (52), 1.02 at 0.75, 1.04-1.07 at 1
  // (docs/architecture.md).
  double skin = 0.25;
  // Set by a flow from its scales (options_for_flow): h = h_over_dx dx, c0 = c0_factor U_ref.
  std::string kernel = "wendland_c2";
  double h_over_dx = 1.3;
  double c0_factor = 10.0;
};

// Per-particle fields that must follow the particles through the cell sort.
struct Fields {
  int drho = -1;   // d rho / dt of the last half step (used by the next 1st half)
  int f_diss = -1; // Riemann dissipation force of the last 2nd half
  int v_wall = -1; // prescribed velocity of wall particles (may be -1: no walls)
  int h = -1;      // per-particle smoothing length (variable resolution; -1: h = Options::h)
  int a_wall = -1; // acceleration of wall particles (moving bodies; -1: walls not accelerating)
  int f_body = -1; // out: force of the fluid on each wall particle, averaged over the last step
                   // (-1: not computed). force_dissipation of a wall particle then holds the
                   // reaction of the last 2nd half's dissipation force on it.
  int n_wall = -1; // unit normal of each wall particle, pointing into the fluid (wall_dissipation =
                   // normal; -1: the dissipation along e_iw)
  template <int D>
  static Fields add_to(Particles<D>& p, int v_wall = -1) {
    Fields f;
    f.drho = p.add_scalar("drho_dt");
    f.f_diss = p.add_vector("force_dissipation");
    f.v_wall = v_wall;
    return f;
  }
};

// Sum_j W_ij (self term included) over a perfect lattice of spacing dx: sigma0 of eq. (8).
template <int D, class K>
double lattice_number_density(const K& kernel, double dx) {
  const int n = static_cast<int>(std::ceil(kernel.support() / dx)) + 1;
  double s = 0.0;
  std::array<int, D> i;
  i.fill(-n);
  while (true) {
    double r2 = 0.0;
    for (int a = 0; a < D; ++a)
      r2 += (i[a] * dx) * (i[a] * dx);
    s += kernel.W(std::sqrt(r2));
    int a = 0;
    while (a < D && ++i[a] > n)
      i[a] = -n, ++a;
    if (a == D)
      break;
  }
  return s;
}

// Dissipation limiter of the momentum Riemann jump (eq. 6): beta_ij for u_ij = (v_i - v_j).e_ij,
// one policy type per Options::dissipation, made once from the options, so that the 2nd half's
// pair loop has neither an option branch nor a division:
//   limited  beta = min((eta / c0) max(s u, 0), 1),  s = +1 "expansion", -1 "compression"
//   full     beta = 1
//   none     beta = 0 (on = false: the pair loop leaves the term out; adding the zero term would
//            leave the sum's bits unchanged)
struct LimitedBeta {
  static constexpr bool on = true;
  double eta_c0, s;
  explicit LimitedBeta(const Options& o)
      : eta_c0(o.limiter_eta / o.c0), s(o.sign == LimiterSign::Expansion ? 1.0 : -1.0) {}
  double operator()(double u) const { return std::min(eta_c0 * std::max(s * u, 0.0), 1.0); }
};
struct FullBeta {
  static constexpr bool on = true;
  explicit FullBeta(const Options&) {}
  double operator()(double) const { return 1.0; }
};
struct NoBeta {
  static constexpr bool on = false;
  explicit NoBeta(const Options&) {}
  double operator()(double) const { return 0.0; }
};

// Calls f(beta) with the policy of o.dissipation (outside the pair loops).
template <class F>
void with_beta(const Options& o, F&& f) {
  switch (o.dissipation) {
  case Dissipation::None:
    return f(NoBeta(o));
  case Dissipation::Full:
    return f(FullBeta(o));
  case Dissipation::Limited:
  default:
    return f(LimitedBeta(o));
  }
}

// beta_ij of any setting, dispatched per call (the walls' reactions, single pairs).
inline double dissipation_beta(const Options& o, double u) {
  double b = 0.0;
  with_beta(o, [&](auto beta) { b = beta(u); });
  return b;
}
struct AnyBeta {
  static constexpr bool on = true;
  const Options& o;
  explicit AnyBeta(const Options& opt) : o(opt) {}
  double operator()(double u) const { return dissipation_beta(o, u); }
};

// Limiter of the transport-velocity correction, eq. (15): psi = min(kappa h^2 |g|^2, 1).
inline double tvf_limiter(double kappa, double h, double g2) {
  return std::min(kappa * h * h * g2, 1.0);
}

namespace ops {

// Density reinitialisation (eq. 8): rho_i = rho0 (sum_j W_ij) / sigma0, V_i = m_i / rho_i.
template <int D>
struct DensitySummation {
  Particles<D>& p;
  double W0, rho0, sigma0;
  std::vector<double>& sumW;

  struct Acc {
    double w;
  };
  Acc init(std::size_t) const { return {W0}; }
  void pair(std::size_t, const Pair<D>& q, Acc& a) const { a.w += q.W; }
  void finish(std::size_t i, const Acc& a) {
    sumW[i] = a.w;
    p.rho[i] = rho0 * a.w / sigma0;
    p.V[i] = p.m[i] / p.rho[i];
  }
};

// Variable resolution (seed 002 section 4.4): rho_i = sum_j m_j W(r_ij, h_ij) / (dx^D sigma0), self
// term m_i W(0, h_i) included, h_ij = (h_i + h_j) / 2; dx^D sigma0 (the lattice's sum_j V_j W_ij,
// the same for every spacing at fixed h/dx) makes it rho0 on any uniform lattice, and equal to
// DensitySummation there.
template <int D>
struct MassSummation {
  Particles<D>& p;
  const std::vector<double>& h;
  double W0h0, h0, rho0, lattice_sum; // W(0) at h0; dx^D sigma0
  double sigma0;
  std::vector<double>& sumW;

  struct Acc {
    double w;
  };
  Acc init(std::size_t i) const { return {p.m[i] * W0h0 * std::pow(h0 / h[i], D)}; }
  void pair(std::size_t, const Pair<D>& q, Acc& a) const { a.w += p.m[q.j] * q.W; }
  void finish(std::size_t i, const Acc& a) {
    p.rho[i] = a.w / lattice_sum;
    p.V[i] = p.m[i] / p.rho[i];
    sumW[i] = sigma0 * p.rho[i] / rho0; // the equivalent number density
  }
};

// Velocity of partner j as particle i sees it: v_j for fluid, 2 v_wall - v_i for a wall.
template <int D>
inline Vec<D> partner_velocity(const Particles<D>& p, const Vec<D>* v_wall, std::size_t i,
                               std::uint32_t j) {
  if (v_wall && p.kind[j] == Kind::Wall)
    return 2.0 * v_wall[j] - p.v[i];
  return p.v[j];
}

// Pressure of wall particle w as fluid particle a sees it across their pair (distance r, e the unit
// vector from w to a): p_w = p_a + rho_a r max(0, (F_prior_a / m_a - a_w) . (-e)), a_w the wall's
// acceleration (a_wall nullptr: at rest). Used by FirstHalf and, reversed, WallPressureReaction.
template <int D>
inline double wall_pressure(const Particles<D>& p, const std::vector<Vec<D>>& f_prior,
                            const Vec<D>* a_wall, std::size_t a, std::size_t w, double r,
                            const Vec<D>& e, double extrapolation = 1.0) {
  const Vec<D> a_rel = a_wall ? Vec<D>(f_prior[a] / p.m[a] - a_wall[w]) : f_prior[a] / p.m[a];
  return p.p[a] + extrapolation * p.rho[a] * r * std::max(0.0, a_rel.dot(-e));
}

// Viscous force F^nu_i = V_i sum_j 2 mu (v_i - v_j) / (r_ij + eps h) V_j dW_ij [notes 2d].
template <int D>
struct ViscousForce {
  const Particles<D>& p;
  const Vec<D>* v_wall;
  double mu, eps_h;
  std::vector<Vec<D>>& f_prior;
  bool walls_only = false; // the wall partners' share only (force_on_walls)

  struct Acc {
    Vec<D> f = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    if (walls_only && p.kind[q.j] != Kind::Wall)
      return;
    const Vec<D> vj = partner_velocity(p, v_wall, i, q.j);
    a.f += (2.0 * mu * p.V[q.j] * q.dW / (q.r + eps_h)) * (p.v[i] - vj);
  }
  void finish(std::size_t i, const Acc& a) { f_prior[i] = p.V[i] * a.f; }
};

// Zero-order consistency residue (eq. 14): g_i = -sum_j (B_i + B_j) V_j dW_ij e_ij (fluid
// partners), -sum_w 2 B_i V_w dW_iw e_iw (walls); B = I without kernel correction.
template <int D>
struct TvfResidue {
  const Particles<D>& p;
  const std::vector<Mat<D>>* B; // nullptr: identity
  std::vector<Vec<D>>& g;

  struct Acc {
    Vec<D> g = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    const Vec<D> gw = (p.V[q.j] * q.dW / q.r) * q.r_ij; // V_j grad_i W_ij
    if (!B)
      a.g -= 2.0 * gw;
    else if (p.kind[q.j] == Kind::Wall)
      a.g -= 2.0 * ((*B)[i] * gw);
    else
      a.g -= ((*B)[i] + (*B)[q.j]) * gw;
  }
  void finish(std::size_t i, const Acc& a) { g[i] = a.g; }
};

// Velocity of a particle moved by the TVF shift, carried to its new place by a first-order Taylor
// expansion (Xu, Stansby & Laurence, JCP 228 (2009) 6703; Lind, Xu, Stansby & Rogers, JCP 231
// (2012) 1499): v_i += (grad v_i) Delta r_i, grad v_i = sum_j V_j (v_j - v_i) (x)
// B_i grad_i W_ij (B = I without kernel correction; walls with v_w* = 2 v_wall - v_i). Not in
// seed 002, whose shift (eq. 16) leaves v_i as it is: an option that measures what that costs.
template <int D>
struct ShiftVelocity {
  const Particles<D>& p;
  const Vec<D>* v_wall;
  const std::vector<Mat<D>>* B; // nullptr: identity
  const std::vector<Vec<D>>& shift;
  std::vector<Vec<D>>& dv;

  struct Acc {
    Vec<D> dv = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    Vec<D> gw = (p.V[q.j] * q.dW / q.r) * q.r_ij; // V_j grad_i W_ij
    if (B)
      gw = (*B)[i] * gw;
    a.dv += gw.dot(shift[i]) * (partner_velocity(p, v_wall, i, q.j) - p.v[i]);
  }
  void finish(std::size_t i, const Acc& a) { dv[i] = a.dv; }
};

// Background-pressure acceleration of the original TVF (Adami et al. 2013, eq. 13):
// a~_i = -(p_b / m_i) sum_j (V_i^2 + V_j^2) dW_ij e_ij.
template <int D>
struct BackgroundPressure {
  const Particles<D>& p;
  double pb;
  std::vector<Vec<D>>& a_tilde;

  struct Acc {
    Vec<D> a = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    const double Vi = p.V[i], Vj = p.V[q.j];
    a.a -= ((Vi * Vi + Vj * Vj) * q.dW / q.r) * q.r_ij;
  }
  void finish(std::size_t i, const Acc& a) { a_tilde[i] = (pb / p.m[i]) * a.a; }
};

// The pair coefficients of the acoustic sub-steps, frozen over the advection step like V_j and the
// pair geometry: e_ij = r_ij / r and V_j dW_ij (V_j grad_i W_ij = V_j dW_ij e_ij), indexed as the
// pairs of the neighbour list nl. Computed once per step after the density summation
// (AcousticPairsOf), so that FirstHalf and SecondHalf, two pair loops per sub-step, neither divide
// by r nor gather V_j: the same values as they compute from a Pair, so the same bits.
template <int D>
struct AcousticPairs {
  const NeighborList<D>* nl = nullptr; // the pairs (distances r for the wall pressure)
  bool walls = true;                   // some particle is a wall (the ops' Walls policy)
  std::vector<Vec<D>> e;
  std::vector<double> VdW;
};

// Fills AcousticPairs for the rows it is run on (interact_indexed; out sized to nl's pairs).
template <int D>
struct AcousticPairsOf {
  const NeighborList<D>& nl;
  const std::vector<double>& V;
  AcousticPairs<D>& out;

  struct Acc {};
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t, std::uint32_t j, std::uint32_t k, Acc&) const {
    out.e[k] = nl.r_ij[k] / nl.r[k];
    out.VdW[k] = V[j] * nl.dW[k];
  }
  void finish(std::size_t, const Acc&) {}
};

// 1st half (Integration1stHalf, Riemann): pressure force F^p (mean part of P*), the density
// dissipation (jump part of U*), and for tvf = original Adami's extra stress with
// dv_i = vt_i - v_i = dt/2 a~_i. Pairs from the neighbour list (interact), or by index with the
// step's AcousticPairs (interact_indexed, the scheme's sub-steps). Walls = false: no partner is a
// wall particle (the scheme's choice when the particles hold none; no kind test per pair).
template <int D, bool Walls = true>
struct FirstHalf {
  const Particles<D>& p;
  const std::vector<Mat<D>>* B;       // nullptr: identity
  const std::vector<Vec<D>>& f_prior; // for the wall pressure extrapolation
  const std::vector<Vec<D>>* a_tilde; // nullptr unless tvf = original
  double half_dt;                     // dt / 2 (transport-velocity increment of a~)
  double inv_rho0c0;
  std::vector<Vec<D>>& force;           // out: F^p (+ F^A)
  std::vector<double>& drho;            // out: drho/dt (assigned)
  bool walls_only = false;              // the wall partners' share only (force_on_walls)
  const Vec<D>* a_wall = nullptr;       // wall accelerations (moving bodies), nullptr: at rest
  const AcousticPairs<D>* ap = nullptr; // the indexed pairs' coefficients
  double wall_extrapolation = 1.0;      // 0: p_w = p_i (Options::wall_extrapolation false)

  struct Acc {
    Vec<D> f = Vec<D>::Zero();
    double d = 0.0;
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    term(
        i, q.j, q.r_ij / q.r, p.V[q.j] * q.dW, [&] { return q.r; }, a);
  }
  void pair(std::size_t i, std::uint32_t j, std::uint32_t k, Acc& a) const {
    term(
        i, j, ap->e[k], ap->VdW[k], [&] { return ap->nl->r[k]; }, a);
  }
  // Pair (i, j): e = e_ij, VdW = V_j dW_ij, r() = |r_ij| (read only for a wall partner).
  template <class R>
  void term(std::size_t i, std::uint32_t j, const Vec<D>& e, double VdW, R&& r, Acc& a) const {
    bool wall = false;
    if constexpr (Walls) {
      wall = p.kind[j] == Kind::Wall;
      if (walls_only && !wall)
        return;
    }
    double pj = p.p[j];
    if (wall)
      pj = wall_pressure(p, f_prior, a_wall, i, j, r(), e, wall_extrapolation);
    const Vec<D> gw = VdW * e; // V_j grad_i W_ij
    if (!B)
      a.f -= (p.p[i] + pj) * gw;
    else if (wall)
      a.f -= (p.p[i] + pj) * ((*B)[i] * gw);
    else
      a.f -= (p.p[i] * (*B)[j] + pj * (*B)[i]) * gw;
    a.d += (p.p[i] - pj) * VdW;
    if (a_tilde && !wall) {
      // (A_i + A_j) . grad W with A = rho v (x) dv: rho_i v_i (dv_i . gW) + rho_j v_j (dv_j . gW)
      const Vec<D> dvi = half_dt * (*a_tilde)[i], dvj = half_dt * (*a_tilde)[j];
      a.f -= p.rho[i] * dvi.dot(gw) * p.v[i] + p.rho[j] * dvj.dot(gw) * p.v[j];
    }
  }
  void finish(std::size_t i, const Acc& a) {
    force[i] = p.V[i] * a.f;
    drho[i] = (p.rho[i] * inv_rho0c0) * a.d;
  }
};

// 2nd half (Integration2ndHalf): continuity with u_ij = (v_i - v_j) . e_ij and the momentum
// dissipation of the Riemann solver with the limiter (eq. 6) of policy Beta (the scheme's: the
// options' own, with_beta). Pairs and Walls as FirstHalf's.
template <int D, class Beta = AnyBeta, bool Walls = true>
struct SecondHalf {
  const Particles<D>& p;
  const Vec<D>* v_wall;
  const Options& o;
  double rho0c0;
  std::vector<double>& drho;            // in: 1st-half dissipation; out: += continuity
  std::vector<Vec<D>>& f_diss;          // out: dissipation force (assigned)
  bool walls_only = false;              // the wall partners' share only (force_on_walls)
  const AcousticPairs<D>* ap = nullptr; // the indexed pairs' coefficients
  Beta beta = Beta(o);                  // the limiter
  const Vec<D>* n_wall = nullptr;       // wall normals: a wall pair's dissipation along n_w

  struct Acc {
    double d = 0.0;
    Vec<D> f = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    term(i, q.j, q.r_ij / q.r, p.V[q.j] * q.dW, a);
  }
  void pair(std::size_t i, std::uint32_t j, std::uint32_t k, Acc& a) const {
    term(i, j, ap->e[k], ap->VdW[k], a);
  }
  // Pair (i, j): e = e_ij, VdW = V_j dW_ij.
  void term(std::size_t i, std::uint32_t j, const Vec<D>& e, double VdW, Acc& a) const {
    if constexpr (Walls)
      if (walls_only && p.kind[j] != Kind::Wall)
        return;
    const Vec<D> vj = Walls ? partner_velocity(p, v_wall, i, j) : p.v[j];
    const Vec<D> dv = p.v[i] - vj;
    const double u = dv.dot(e);
    a.d += u * VdW;
    // Added also when beta = 0 (a zero term leaves the sum's bits unchanged): the sign of u_ij
    // is random pair to pair, and a branch on it mispredicts about every other pair. Left out
    // only without dissipation (NoBeta).
    if constexpr (Beta::on) {
      if constexpr (Walls)
        if (n_wall && p.kind[j] == Kind::Wall) { // along the wall's normal: no tangential part
          const Vec<D>& n = n_wall[j];
          const double un = dv.dot(n);
          a.f += (rho0c0 * beta(un) * un * VdW) * n;
          return;
        }
      a.f += (rho0c0 * beta(u) * u * VdW) * e;
    }
  }
  void finish(std::size_t i, const Acc& a) {
    drho[i] += p.rho[i] * a.d;
    f_diss[i] = p.V[i] * a.f;
  }
};

// The reactions on the walls (moving bodies, Fields::f_body): for wall particle w (the row) and
// each fluid partner a, minus the pair term fluid a felt from w in ViscousForce, FirstHalf and
// SecondHalf, written from w's row (r_wa = -r_aw, the same W and dW; e_aw = -r_wa / r). The
// fluid-side quantities (V_a, p_a, rho_a, F_prior_a, v_a) are the partner's.

// -F^nu_aw = -V_a 2 mu V_w dW (v_a - v_w*) / (r + eps h),  v_w* = 2 v_wall - v_a.
template <int D>
struct WallViscousReaction {
  const Particles<D>& p;
  const Vec<D>* v_wall;
  double mu, eps_h;
  std::vector<Vec<D>>& f; // out, wall rows

  struct Acc {
    Vec<D> f = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t w, const Pair<D>& q, Acc& a) const {
    const std::uint32_t k = q.j;
    if (p.kind[k] != Kind::Fluid)
      return;
    const Vec<D> vw = partner_velocity(p, v_wall, k, static_cast<std::uint32_t>(w));
    a.f -= (p.V[k] * 2.0 * mu * p.V[w] * q.dW / (q.r + eps_h)) * (p.v[k] - vw);
  }
  void finish(std::size_t w, const Acc& a) { f[w] = a.f; }
};

// -F^p_aw = V_a (p_a + p_w) V_w dW [B_a] e_aw,  p_w = p_a + rho_a r max(0, (F_prior_a / m_a - a_w)
// . (-e_aw)).
template <int D>
struct WallPressureReaction {
  const Particles<D>& p;
  const std::vector<Mat<D>>* B; // nullptr: identity
  const std::vector<Vec<D>>& f_prior;
  const Vec<D>* a_wall;            // nullptr: walls at rest
  std::vector<Vec<D>>& f;          // out, wall rows
  double wall_extrapolation = 1.0; // as FirstHalf's

  struct Acc {
    Vec<D> f = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t w, const Pair<D>& q, Acc& a) const {
    const std::uint32_t k = q.j;
    if (p.kind[k] != Kind::Fluid)
      return;
    const Vec<D> e_aw = -q.r_ij / q.r;
    const double pw = wall_pressure(p, f_prior, a_wall, k, w, q.r, e_aw, wall_extrapolation);
    const Vec<D> gw = (p.V[w] * q.dW) * e_aw; // V_w grad_a W_aw
    const Vec<D> t = B ? Vec<D>((*B)[k] * gw) : gw;
    a.f += (p.V[k] * (p.p[k] + pw)) * t;
  }
  void finish(std::size_t w, const Acc& a) { f[w] = a.f; }
};

// -F^diss_aw = -V_a rho0 c0 beta(u) u V_w dW e_aw,  u = (v_a - v_w*) . e_aw (with n_wall: n_w for
// e_aw, as SecondHalf).
template <int D>
struct WallDissipationReaction {
  const Particles<D>& p;
  const Vec<D>* v_wall;
  const Options& o;
  double rho0c0;
  std::vector<Vec<D>>& f;         // out, wall rows
  const Vec<D>* n_wall = nullptr; // wall normals (SecondHalf's)

  struct Acc {
    Vec<D> f = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t w, const Pair<D>& q, Acc& a) const {
    const std::uint32_t k = q.j;
    if (p.kind[k] != Kind::Fluid)
      return;
    const Vec<D> e_aw = n_wall ? n_wall[w] : Vec<D>(-q.r_ij / q.r);
    const Vec<D> vw = partner_velocity(p, v_wall, k, static_cast<std::uint32_t>(w));
    const double u = (p.v[k] - vw).dot(e_aw);
    a.f -= (p.V[k] * rho0c0 * dissipation_beta(o, u) * u * p.V[w] * q.dW) * e_aw;
  }
  void finish(std::size_t w, const Acc& a) { f[w] = a.f; }
};

} // namespace ops

// The open-boundary hooks of a flow (schemes/scheme.hpp, Flow) the scheme calls in its step.
template <int D>
struct BoundaryHooks {
  std::function<void(Particles<D>&, const NeighborList<D>&)> buffer_pressure, before_density,
      after_density;
  std::function<void(Particles<D>&, double)> after_kick;
  int surface_indicator = -1; // scalar field: nonzero = free surface (no TVF shift)
  // Moving bodies: after the acoustic sub-steps of the step [t0, t0 + Dt], before the neighbour
  // search (the case moves its wall particles: a coupled solid, coupling/fsi.hpp).
  std::function<void(Particles<D>&, double t0, double Dt)> body_motion;
};

// What one advection step did (for the case's diagnostics).
struct StepInfo {
  double Dt = 0.0;
  int substeps = 0;
  double tv_max = 0.0; // max_i |Delta r^tvf_i| / Dt
  double v_max = 0.0;  // max fluid speed at the start of the step
};

template <int D, class K>
class Scheme {
public:
  Scheme(Particles<D>& p, const Fields& f, const Domain<D>& box, const Options& o)
      : p_(p), f_(f), box_(box), o_(o), kernel_(o.h), stages_(build_stages(o)) {}

  // The advection step: an ordered list of named stages built once from the options, leaving out
  // what is off (the correction matrix without kernel_correction, the transport stage with
  // tvf = none).
  struct Stage {
    const char* name;
    void (Scheme::*run)(double Dt, StepInfo& info);
  };
  static std::vector<Stage> build_stages(const Options& o) {
    std::vector<Stage> s{{"density_summation", &Scheme::density_summation}};
    if (o.kernel_correction)
      s.push_back({"correction_matrix", &Scheme::correction_matrix});
    s.push_back({"viscous_force", &Scheme::viscous_force});
    if (o.tvf != Tvf::None)
      s.push_back({"transport", &Scheme::transport});
    s.push_back({"acoustic", &Scheme::acoustic});
    s.push_back({"neighbours", &Scheme::neighbours});
    return s;
  }
  std::vector<std::string> stage_names() const {
    std::vector<std::string> n;
    for (const auto& st : stages_)
      n.emplace_back(st.name);
    return n;
  }

  const Options& options() const { return o_; }
  const K& kernel() const { return kernel_; }
  double sigma0() const { return sigma0_; }
  const NeighborList<D>& neighbors() const { return nl_; }
  // Sum_j W_ij of the last density summation (fluid particles; in the current order).
  const std::vector<double>& sum_w() const { return sumW_; }
  const std::vector<Vec<D>>& tvf_shift() const { return shift_; }
  long acoustic_steps() const { return acoustic_steps_; }
  // What the scheme carries from one advection step to the next besides the particle fields
  // (for checkpoints): the last step's peak acceleration (advection criterion) and the sub-step
  // count. Restore after init().
  std::vector<double> carried_state() const {
    return {a_last_max_, static_cast<double>(acoustic_steps_)};
  }
  void restore_carried_state(const std::vector<double>& s) {
    io::expect_state_size(s, 2, "wcsph_tvf: checkpoint state");
    a_last_max_ = s[0];
    acoustic_steps_ = static_cast<long>(s[1]);
  }

  // Sum_j W_ij (self term included) on the neighbour list of the current positions (valid
  // between advection steps: the list is rebuilt at the end of each).
  void number_density(std::vector<double>& out) const {
    out.resize(p_.size());
    const double W0 = kernel_.W(0.0);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < p_.size(); ++i) {
      double w = W0;
      for (std::uint32_t k = nl_.offset[i]; k < nl_.offset[i + 1]; ++k)
        w += nl_.W[k];
      out[i] = w;
    }
  }

  void set_boundary_hooks(const BoundaryHooks<D>& b) {
    hooks_ = b;
  }
  // The case added, removed or re-kinded particles since the last step: a new Verlet list (and
  // cell sort) on the current set, and its pairs.
  void particles_changed() {
    vl_->rebuild(p_);
    pair_geometry();
  }

  // Builds the Verlet list and the pairs on the initial positions; the first density summation
  // happens in the first step.
  void init() {
    setup();
    neighbour_search();
  }

  // A resumed run (after the particle fields were restored): the Verlet list of the build whose
  // reference positions r0 and build count a checkpoint saved (verlet().reference(), builds()),
  // and the pairs of the current positions: the uninterrupted run had the same list at that step
  // (the particles are in that build's order, so nothing is sorted).
  void resume(const std::vector<Vec<D>>& r0, long builds) {
    setup();
    if (r0.size() != p_.size())
      throw std::runtime_error(
          "wcsph_tvf: checkpoint reference positions do not match the particles");
    vl_->restore(p_, r0, builds);
    pair_geometry();
  }
  const VerletList<D>& verlet() const {
    return *vl_;
  }

private:
  void setup() {
    sigma0_ = lattice_number_density<D>(kernel_, o_.dx);
    double h_max = o_.h;
    h_min_ = o_.h;
    if (variable()) {
      const auto& h = p_.scalar(f_.h);
      h_min_ = h_max = h.at(0);
      for (std::size_t i = 0; i < p_.size(); ++i)
        h_min_ = std::min(h_min_, h[i]), h_max = std::max(h_max, h[i]);
    }
    if (variable()) {
      // Two levels: each pair's cutoff from its own h and the cells sized for the finest pair
      // (core/verlet_list.hpp); the skin that of the coarse support, as with one list: a skin of
      // the fine support (half of it) is crossed within one advection step (0.25 h / |v|max), so
      // the list was rebuilt 1.55 times per step instead of 0.95 (D/dx = 20 with the band).
      const double s0 = kernel_.support() / o_.h, fine = s0 * h_min_, coarse = s0 * h_max;
      vl_ = std::make_unique<VerletList<D>>(
          box_, s0, h_min_, h_max, VerletList<D>::largest_skin(box_, fine, o_.skin * coarse), f_.h);
      return;
    }
    const double support = kernel_.support();
    // substep_pairs: half the support as skin (a step moves a particle by ~0.25 h)
    const double skin = o_.substep_pairs ? std::max(o_.skin, 0.5) : o_.skin;
    vl_ = std::make_unique<VerletList<D>>(
        box_, support, VerletList<D>::largest_skin(box_, support, skin * support));
  }

public:
  // Advection time step, eqs. (9)-(10), from the current velocities and the forces of the last
  // step (F_prior + F^diss); with variable resolution on the smallest h.
  double advection_dt() const {
    const double h = h_min_;
    double s2 = 4.0 * h * a_last_max_;
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (fluid(i))
        s2 = std::max(s2, p_.v[i].squaredNorm());
    const double nu = o_.mu / o_.rho0;
    return o_.cfl_ad * h / std::max({std::sqrt(s2), o_.U_ref, nu / h});
  }

  // Acoustic time step, eq. (11).
  double acoustic_dt() const {
    double v2 = 0.0;
    const std::size_t N = p_.size();
#pragma omp parallel for schedule(static) reduction(max : v2)
    for (std::size_t i = 0; i < N; ++i)
      if (fluid(i))
        v2 = std::max(v2, p_.v[i].squaredNorm());
    return o_.cfl_ac * h_min_ / (o_.c0 + std::sqrt(v2));
  }

  // One advection step of size Dt through the stage list. Dt_nominal (default Dt) is the step of
  // the advection criterion before the caller shortened it to land on an output time: the
  // smoothing-length corrections shift by alpha h^2 psi g whatever the step, so their transport
  // velocity is measured over Dt_nominal; the original variant's shift scales with Dt.
  StepInfo advance(double Dt, double Dt_nominal = 0.0) {
    StepInfo info;
    info.Dt = Dt;
    dt_tv_ = (o_.tvf == Tvf::Original || !(Dt_nominal > 0.0)) ? Dt : Dt_nominal;
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (fluid(i))
        info.v_max = std::max(info.v_max, p_.v[i].norm());
    for (const auto& st : stages_)
      (this->*st.run)(Dt, info);
    return info;
  }

  // One advection step from t towards t_end (t is advanced): the criterion's step, except that the
  // last two steps share what remains, so that the run lands exactly on t_end without a sliver of
  // a last step.
  StepInfo advance_towards(double& t, double t_end) {
    const double Dt_ad = advection_dt(), rem = t_end - t;
    const double Dt = rem <= Dt_ad ? rem : (rem < 2.0 * Dt_ad ? 0.5 * rem : Dt_ad);
    t0_ = t;
    const StepInfo info = advance(Dt, Dt_ad);
    t = (t_end - t - Dt <= 1e-12 * t_end) ? t_end : t + Dt;
    return info;
  }

  bool fluid(std::size_t i) const {
    return p_.kind[i] == Kind::Fluid;
  }
  // Variable resolution: a per-particle smoothing length field (Fields::h).
  bool variable() const {
    return f_.h >= 0;
  }

  // A uniform body acceleration g acting on the fluid from the next step on (added to F_prior as
  // m_i g; e.g. the smooth start of a periodic free stream).
  void set_body_acceleration(const Vec<D>& g) {
    g_body_ = g;
  }

  // Force of the fluid on the wall particles (a body at rest): minus the walls' share of the
  // viscous, pressure (1st half, wall pressure extrapolated) and Riemann-dissipation (2nd half)
  // forces on the fluid particles, on the current state and neighbour list (call between advection
  // steps). Newton's third law: the same pair forces the fluid feels, summed over fluid i.
  // viscous (optional): the viscous part alone (the rest is pressure and Riemann dissipation).
  Vec<D> force_on_walls(Vec<D>* viscous = nullptr) {
    const std::size_t N = p_.size();
    wf_visc_.resize(N), wf_p_.resize(N), wf_diss_.resize(N), wf_drho_.assign(N, 0.0);
    // F_prior of the wall pressure extrapolation on the current positions (the step's own F_prior
    // and B are indexed in the order before the step's final cell sort).
    wf_prior_.resize(N);
    prior_force(wf_prior_);
    const std::vector<Mat<D>>* B = nullptr; // likewise the correction matrices, if used
    if (o_.kernel_correction) {
      wf_B_.resize(N, Mat<D>::Identity()), wf_trB_.resize(N);
      correction(wf_B_, wf_trB_);
      B = &wf_B_;
    }
    ops::ViscousForce<D> fv{p_, v_wall(), o_.mu, o_.viscous_eps * o_.h, wf_visc_, true};
    interact(nl_, fv, fluid_only());
    ops::FirstHalf<D> fp{p_,    B,        wf_prior_, nullptr, 0.0, 1.0 / (o_.rho0 * o_.c0),
                         wf_p_, wf_drho_, true};
    fp.wall_extrapolation = o_.wall_extrapolation ? 1.0 : 0.0;
    interact(nl_, fp, fluid_only());
    ops::SecondHalf<D> fd{p_, v_wall(), o_, o_.rho0 * o_.c0, wf_drho_, wf_diss_, true};
    fd.n_wall = n_wall();
    interact(nl_, fd, fluid_only());
    Vec<D> F = Vec<D>::Zero(), Fv = Vec<D>::Zero();
    for (std::size_t i = 0; i < N; ++i)
      if (fluid(i))
        F -= wf_p_[i] + wf_diss_[i], Fv -= wf_visc_[i];
    if (viscous)
      *viscous = Fv;
    return F + Fv;
  }

private:
  Particles<D>& p_;
  Fields f_;
  Domain<D> box_;
  Options o_;
  K kernel_;
  std::vector<Stage> stages_; // the advection step, built once (build_stages)
  double sigma0_ = 1.0;
  std::unique_ptr<VerletList<D>> vl_;
  NeighborList<D> nl_;
  ops::AcousticPairs<D> ap_; // the sub-steps' pair coefficients (acoustic_pairs)
  std::vector<double> sumW_, traceB_;
  std::vector<Mat<D>> B_;
  std::vector<Vec<D>> f_prior_, force_, g_, shift_, a_tilde_, dv_;
  long acoustic_steps_ = 0;
  double a_last_max_ = 0.0; // max_i |F_prior_i + F^diss_i| / m_i at the end of the last step
  double h_min_ = 1.0;      // smallest smoothing length (time steps)
  double dt_tv_ = 1.0;      // step over which the transport velocity is measured
  Vec<D> g_body_ = Vec<D>::Zero();
  BoundaryHooks<D> hooks_;
  double t0_ = 0.0; // time at the start of the advection step (the hooks' sub-step times)
  std::vector<Vec<D>> wf_prior_, wf_visc_, wf_p_, wf_diss_; // force_on_walls' scratch
  std::vector<Vec<D>> w_visc_, w_p_, w_impulse_;            // moving bodies: the walls' reactions
  std::vector<double> wf_drho_, wf_trB_;
  std::vector<Mat<D>> wf_B_;

  const Vec<D>* v_wall() const {
    return f_.v_wall >= 0 ? p_.vector(f_.v_wall).data() : nullptr;
  }
  const Vec<D>* n_wall() const {
    return f_.n_wall >= 0 ? p_.vector(f_.n_wall).data() : nullptr;
  }
  const std::vector<Mat<D>>* B() const {
    return o_.kernel_correction ? &B_ : nullptr;
  }
  auto fluid_only() const {
    return [this](std::size_t i) { return fluid(i); };
  }
  auto walls_only() const {
    return [this](std::size_t i) { return p_.kind[i] == Kind::Wall; };
  }
  // Moving bodies: the fluid's force on every wall particle is computed (Fields::f_body).
  bool coupled() const {
    return f_.f_body >= 0;
  }
  const Vec<D>* a_wall() const {
    return f_.a_wall >= 0 ? p_.vector(f_.a_wall).data() : nullptr;
  }

  void neighbours(double Dt, StepInfo&) {
    if (hooks_.body_motion)
      hooks_.body_motion(p_, t0_, Dt);
    neighbour_search();
  }
  void neighbour_search() {
    // substep_pairs: a fresh candidate list every step, so that the sub-steps' pairs (from these
    // candidates) stay complete while no particle moves more than skin/2 within the step.
    if (!vl_->update(p_) && o_.substep_pairs)
      vl_->rebuild(p_);
    pair_geometry();
  }
  // substep_pairs: r_ij, W, dW of the current positions from the candidates of the step's list,
  // and the sub-steps' coefficients (V_j stays that of the density summation).
  void substep_geometry() {
    if (vl_->max_displacement2(p_.r) > 0.25 * vl_->skin() * vl_->skin())
      throw std::runtime_error("wcsph_tvf: substep_pairs: a particle moved more than half the "
                               "Verlet skin within one advection step");
    if (variable())
      nl_.build(*vl_, p_.r, kernel_, p_.scalar(f_.h));
    else
      nl_.build(*vl_, p_.r, kernel_);
    acoustic_pairs();
  }
  void pair_geometry() {
    if (variable())
      nl_.build(*vl_, p_.r, kernel_, p_.scalar(f_.h));
    else
      nl_.build(*vl_, p_.r, kernel_);
    const std::size_t N = p_.size();
    sumW_.resize(N), traceB_.resize(N), B_.resize(N, Mat<D>::Identity());
    f_prior_.resize(N, Vec<D>::Zero()), force_.resize(N), g_.resize(N);
    shift_.resize(N, Vec<D>::Zero()), a_tilde_.resize(N, Vec<D>::Zero());
    if (coupled())
      w_visc_.resize(N, Vec<D>::Zero()), w_p_.resize(N, Vec<D>::Zero()), w_impulse_.resize(N);
  }

  void density_summation(double, StepInfo&) {
    if (hooks_.before_density)
      hooks_.before_density(p_, nl_);
    if (variable()) {
      ops::MassSummation<D> op{p_,
                               p_.scalar(f_.h),
                               kernel_.W(0.0),
                               o_.h,
                               o_.rho0,
                               std::pow(o_.dx, D) * sigma0_,
                               sigma0_,
                               sumW_};
      interact(nl_, op, fluid_only());
    } else {
      ops::DensitySummation<D> op{p_, kernel_.W(0.0), o_.rho0, sigma0_, sumW_};
      interact(nl_, op, fluid_only());
    }
    const std::size_t N = p_.size();
    for (std::size_t i = 0; i < N; ++i)
      if (!fluid(i))
        p_.V[i] = p_.m[i] / p_.rho[i];
    if (hooks_.after_density)
      hooks_.after_density(p_, nl_);
  }

  void correction_matrix(double, StepInfo&) {
    correction(B_, traceB_);
  }
  // The correction matrices of the fluid particles on the current neighbour list.
  void correction(std::vector<Mat<D>>& B, std::vector<double>& trB) {
    CorrectionMatrix<D> op{p_.V, B, trB};
    interact(nl_, op, fluid_only());
  }

  void viscous_force(double, StepInfo&) {
    prior_force(f_prior_);
    if (coupled()) { // the walls' share, for their reaction (moving bodies)
      ops::WallViscousReaction<D> op{p_, v_wall(), o_.mu, o_.viscous_eps * o_.h, w_visc_};
      interact(nl_, op, walls_only());
    }
  }
  // F_prior = F^nu + m g of the fluid particles on the current neighbour list.
  void prior_force(std::vector<Vec<D>>& out) {
    ops::ViscousForce<D> op{p_, v_wall(), o_.mu, o_.viscous_eps * o_.h, out};
    interact(nl_, op, fluid_only());
    if (g_body_.squaredNorm() > 0.0)
      for (std::size_t i = 0; i < p_.size(); ++i)
        if (fluid(i))
          out[i] += p_.m[i] * g_body_;
  }

  // Eqs. (14)-(16) once per advection step, or Adami's a~ for the sub-steps (not a stage with
  // tvf = none: the shift stays zero).
  void transport(double, StepInfo& info) {
    const std::size_t N = p_.size();
    if (o_.tvf == Tvf::Original) {
      ops::BackgroundPressure<D> op{p_, o_.pb_factor * o_.rho0 * o_.c0 * o_.c0, a_tilde_};
      interact(nl_, op, fluid_only());
      std::fill(shift_.begin(), shift_.end(), Vec<D>::Zero()); // accumulated by the sub-steps
      return;
    }
    ops::TvfResidue<D> op{p_, B(), g_};
    interact(nl_, op, fluid_only());
    const double* hv = variable() ? p_.scalar(f_.h).data() : nullptr; // eq. (14) with h_i
    const double* surface = // free-surface particles keep their place (bulk particles only)
        hooks_.surface_indicator >= 0 ? p_.scalar(hooks_.surface_indicator).data() : nullptr;
    double tv = 0.0;
#pragma omp parallel for schedule(static) reduction(max : tv)
    for (std::size_t i = 0; i < N; ++i) {
      if (!fluid(i))
        continue;
      if (surface && surface[i] != 0.0) {
        shift_[i] = Vec<D>::Zero();
        continue;
      }
      const double h = hv ? hv[i] : o_.h, c = o_.tvf_alpha * h * h;
      const double psi =
          o_.tvf == Tvf::Limited ? tvf_limiter(o_.tvf_kappa, h, g_[i].squaredNorm()) : 1.0;
      shift_[i] = (c * psi) * g_[i];
      p_.r[i] += shift_[i];
      tv = std::max(tv, shift_[i].norm());
    }
    info.tv_max = tv / dt_tv_;
    if (o_.shift_velocity) { // the velocity follows the shift (on the pairs before it)
      dv_.resize(N);
      ops::ShiftVelocity<D> sv{p_, v_wall(), B(), shift_, dv_};
      interact(nl_, sv, fluid_only());
      for (std::size_t i = 0; i < N; ++i)
        if (fluid(i))
          p_.v[i] += dv_[i];
    }
  }

  // e_ij and V_j dW_ij of the fluid rows, for the sub-steps (V_j is frozen until the next density
  // summation, the pairs until the next neighbour search).
  void acoustic_pairs() {
    ap_.nl = &nl_;
    ap_.walls = std::find(p_.kind.begin(), p_.kind.end(), Kind::Wall) != p_.kind.end();
    ap_.e.resize(nl_.num_pairs()), ap_.VdW.resize(nl_.num_pairs());
    ops::AcousticPairsOf<D> op{nl_, p_.V, ap_};
    interact_indexed(nl_, op, fluid_only());
  }

  // Calls f(std::true_type) when some particle is a wall, else f(std::false_type) (the Walls
  // policy of FirstHalf and SecondHalf; outside the pair loops).
  template <class F>
  void with_walls(F&& f) const {
    if (ap_.walls)
      f(std::true_type{});
    else
      f(std::false_type{});
  }

  void acoustic(double Dt, StepInfo& info) {
    const std::size_t N = p_.size();
    const bool original = o_.tvf == Tvf::Original;
    auto& drho = p_.scalar(f_.drho);
    auto& fd = p_.vector(f_.f_diss);
    const double rho0c0 = o_.rho0 * o_.c0;
    if (coupled())
      std::fill(w_impulse_.begin(), w_impulse_.end(), Vec<D>::Zero());
    const double inv_r0c0 = o_.riemann_density ? 1.0 / rho0c0 : 0.0;
    acoustic_pairs();
    double tau = 0.0;
    while (tau < Dt * (1.0 - 1e-12)) {
      if (o_.substep_pairs) // the pairs of the current positions (the list's candidates)
        substep_geometry();
      const double dt = std::min(acoustic_dt(), Dt - tau);
      const double half = 0.5 * dt;
      // 1st half: density and pressure at the half step, drift, pressure force, kick.
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < N; ++i) {
        if (!fluid(i)) {
          if (p_.kind[i] == Kind::Buffer)
            p_.r[i] += half * p_.v[i];
          continue;
        }
        p_.rho[i] += half * drho[i];
        p_.p[i] = o_.c0 * o_.c0 * (p_.rho[i] - o_.rho0);
        Vec<D> vt = p_.v[i];
        if (original) {
          vt += half * a_tilde_[i];
          shift_[i] += (half * half) * a_tilde_[i];
        }
        p_.r[i] += half * vt;
      }
      if (hooks_.buffer_pressure)
        hooks_.buffer_pressure(p_, nl_);
      {
        with_walls([&](auto walls) {
          // riemann_density false: the U* jump term's coefficient is zero (drho = 0 exactly)
          ops::FirstHalf<D, decltype(walls)::value> op{
              p_,    B(),      f_prior_, original ? &a_tilde_ : nullptr,
              half,  inv_r0c0, force_,   drho,
              false, a_wall(), &ap_,     o_.wall_extrapolation ? 1.0 : 0.0};
          interact_indexed(nl_, op, fluid_only());
        });
      }
      if (coupled()) { // the impulse the fluid's kick takes from each wall, reversed
        ops::WallPressureReaction<D> op{p_,       B(),  f_prior_,
                                        a_wall(), w_p_, o_.wall_extrapolation ? 1.0 : 0.0};
        interact(nl_, op, walls_only());
#pragma omp parallel for schedule(static)
        for (std::size_t i = 0; i < N; ++i)
          if (p_.kind[i] == Kind::Wall)
            w_impulse_[i] += dt * (w_visc_[i] + w_p_[i] + fd[i]);
      }
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < N; ++i)
        if (fluid(i))
          p_.v[i] += (dt / p_.m[i]) * (f_prior_[i] + force_[i] + fd[i]);
      if (hooks_.after_kick)
        hooks_.after_kick(p_, t0_ + tau);
        // 2nd half: drift with the new velocity, continuity and dissipation, density.
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < N; ++i) {
        if (!fluid(i)) {
          if (p_.kind[i] == Kind::Buffer)
            p_.r[i] += half * p_.v[i];
          continue;
        }
        Vec<D> vt = p_.v[i];
        if (original) {
          vt += half * a_tilde_[i];
          shift_[i] += (half * half) * a_tilde_[i];
        }
        p_.r[i] += half * vt;
      }
      {
        with_beta(o_, [&](auto beta) {
          with_walls([&](auto walls) {
            ops::SecondHalf<D, decltype(beta), decltype(walls)::value> op{
                p_, v_wall(), o_, rho0c0, drho, fd, false, &ap_, beta, n_wall()};
            interact_indexed(nl_, op, fluid_only());
          });
        });
      }
      if (coupled()) { // the walls' dissipation reaction, for the next kick
        ops::WallDissipationReaction<D> op{p_, v_wall(), o_, rho0c0, fd, n_wall()};
        interact(nl_, op, walls_only());
      }
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < N; ++i)
        if (fluid(i))
          p_.rho[i] += half * drho[i];
      tau += dt;
      ++info.substeps;
      ++acoustic_steps_;
    }
    double tv = 0.0, a = 0.0;
#pragma omp parallel for schedule(static) reduction(max : tv, a)
    for (std::size_t i = 0; i < N; ++i) {
      if (!fluid(i))
        continue;
      tv = std::max(tv, shift_[i].norm());
      a = std::max(a, (f_prior_[i] + fd[i]).norm() / p_.m[i]);
    }
    if (original)
      info.tv_max = tv / dt_tv_;
    a_last_max_ = a;
    if (coupled()) {
      auto& fb = p_.vector(f_.f_body);
      for (std::size_t i = 0; i < N; ++i)
        fb[i] = p_.kind[i] == Kind::Wall ? Vec<D>(w_impulse_[i] / Dt) : Vec<D>::Zero();
    }
  }
};

} // namespace sph::wcsph_tvf
