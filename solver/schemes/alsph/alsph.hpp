// ALSPH: augmented-Lagrangian SPH for incompressible flow (seed 004: Kolukisa, Ozbulut & Yildiz
// 2021, Symmetry 13, 472, section 2; Fatehi et al. 2019, Comput. Fluids 185).
//
// One time step n -> n+1, with iterations m = 0, 1, ... (u^{n+1,0} = u^n, p^{n+1,0} = p^n):
//   r_AL = C_BV u_max^2 dt                                  (after eq. 8; fixed during the step)
//   u*   = u^n + r_AL dt <grad(div u^{m})> + nu dt <lap u^{m}> + g dt                  (eq. 8)
//   p^{m+1} = p^m - r_AL rho ( <div u*> - dt/rho <lap p^m> )                            (eq. 10)
//   p on body particles: p_s = p + (dp/dn) r_s, dp/dn = rho (Du_s/Dt) . n               (eq. 20)
//   u^{m+1} = u* - dt/rho <grad p^{m+1}>                                                (eq. 11)
//   r^{m+1} = r^n + (u^n + u^{m+1}) dt / 2                                              (eq. 12)
//   stop when max_i |<div u^{m+1}>| <= epsilon (eq. 13) or after max_iterations updates;
//   then artificial particle displacement (eq. 18) with the Taylor correction of u, p (eq. 19).
// Derivatives (eqs. 15-17): V_i = 1/sum_j W_ij (after eq. 14, SummationDensity), alpha_i (eq. 17)
// inverted as Gamma_i (CorrectionMatrix), gradient sum_j V_j (f_j - f_i) Gamma_i grad_i W_ij
// (eq. 15, CorrectedGradient), divergence its trace, Laplacian in the kernel-corrected Morris form
//   lap f_i = 2 sum_j V_j (f_i - f_j) (r_ij . Gamma_i grad_i W_ij) / (r_ij^2 + eta^2),
// which is how we read eq. (16) (its printed tensor form does not contract to a scalar; this is
// the same operator as VISC-04 of seed 001, eq. 20, second-order on a regular lattice).
//
// One neighbour search per step: the NeighborList built on r^n is reused by every iteration, and
// so are the pair coefficients of the derivatives (ops::PairCoefficients: V_j Gamma_i grad_i W_ij
// and the Laplacian coefficient, computed with V and Gamma in geometry(), stored in double or, with
// coefficients = "float", in single precision), so that the loops of the inner iterations are
// multiply-adds on cached values (interact_indexed).
//   algorithm 2: derivatives on r^n (the cached W, dW, Gamma, V and coefficients unchanged);
//   algorithm 1: derivatives on r^{n+1,m}: before iteration m >= 1 the cached pair list is kept
//     but r_ij, r, W, dW are recomputed from the moved positions (r_ij += dr_i - dr_j, so periodic
//     images stay correct), then V, Gamma and the coefficients are recomputed. Pairs that enter the
//     support during the step are missed (displacements within a step are <= u_max dt, a few % of
//     dx here).
// Particle roles by Kind: Fluid is integrated; Body is fixed (u = 0) and gets eq. (20); Buffer
// keeps its velocity (inlet/outlet zones, pressure set by the case's hook); Wall are mirror ghosts
// (MirrorGhosts) synchronised after every update.
#pragma once

#include "core/neighbor_list.hpp"
#include "core/pair_array.hpp"
#include "core/particles.hpp"
#include "io/checkpoint.hpp"
#include "operators/correction_matrix.hpp"
#include "operators/interact.hpp"
#include "operators/summation_density.hpp"
#include "schemes/alsph/mirror_ghosts.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <omp.h>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph::alsph {

// Process CPU time in seconds (all threads).
inline double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Settings {
  double c_bv = 100.0;     // C_BV in r_AL = C_BV u_max^2 dt
  double epsilon = 1e-3;   // eq. (13) tolerance on max |div u| (1 / time unit)
  int max_iterations = 5;  // updates per step at most
  int algorithm = 1;       // 1: derivatives on r^{n+1,m}; 2: on r^n
  double nu = 1e-2;        // kinematic viscosity
  double rho = 1.0;        // density (constant)
  double dt = 1e-3;        // time step
  double eta_over_h = 0.1; // singularity guard eta in r^2 + eta^2 of the Laplacian
  bool shifting = true;    // eq. (18)-(19)
};

struct StepStats {
  int iterations = 0;     // updates done (eqs. 8-12)
  bool converged = false; // eq. (13) met before max_iterations
  double div_max = 0.0;   // max |div u| over fluid at the end of the step
  double div_mean = 0.0;  // mean |div u| over fluid at the end of the step
  double r_al = 0.0;
  double u_max = 0.0;
};

// Process CPU seconds (summed over threads; on a shared machine this, unlike wall time, does not
// grow with other users' load) spent in the parts of the step, accumulated over steps.
struct Timers {
  double geometry = 0.0;   // V, Gamma on the pairs of the fresh search (once per step)
  double iterations = 0.0; // eqs. (8)-(12), the convergence check and the final evaluation;
                           // algorithm 1: also the pair refresh and V, Gamma of every iteration
  double refresh = 0.0;    // algorithm 1: the part of `iterations` spent on refresh + geometry
  double shifting = 0.0;   // eqs. (18)-(19) (with the pair refresh they need)
  long evaluations = 0;    // derivative evaluations of the velocity (one per iteration + final)
  double particle_iterations = 0.0; // sum over steps of N x iterations
  double particle_steps = 0.0;      // sum over steps of N
};

namespace ops {

// The per-pair coefficients of the derivatives (eqs. 15-16), cached once per neighbour
// configuration (once per step for algorithm 2, after every pair refresh for algorithm 1) and read
// by every inner-iteration loop, for pair k = (i, j) of the list:
//   gw_k = V_j Gamma_i grad_i W_ij,  so that <grad f>_i = sum_k (f_j - f_i) gw_k       (eq. 15),
//   lap_k = 2 V_j (r_ij . Gamma_i grad_i W_ij) / (r_ij^2 + eta^2),
//                                    so that <lap f>_i = sum_k lap_k (f_i - f_j)        (eq. 16),
// stored as Real: double, or float to halve the bytes the memory-bound inner loops stream (the
// sums and the fields stay in double; the scheme parameter `coefficients`).
// Gamma_i needs only the row of i, so a caller may compute it and the row's coefficients in one
// pass over the rows (Scheme::gamma_and_coefficients): the row is still in cache.
template <int D, class Real = double>
struct PairCoefficients {
  using RVec = Eigen::Matrix<Real, D, 1>;
  PairArray<RVec> gw;
  PairArray<Real> lap;

  void resize(const NeighborList<D>& nl) { gw.resize(nl.num_pairs()), lap.resize(nl.num_pairs()); }

  // Pair k's coefficients in double (the loops sum in double).
  Vec<D> gw_of(std::uint32_t k) const { return gw[k].template cast<double>(); }
  double lap_of(std::uint32_t k) const { return static_cast<double>(lap[k]); }

  // The coefficients of the pairs of particle i (after resize()).
  void row(const NeighborList<D>& nl, const std::vector<double>& V, const Mat<D>& gamma_i,
           double eta2, std::size_t i) {
    for (std::uint32_t k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
      const Pair<D> q = nl.pair(k);
      const Vec<D> g = V[q.j] * (gamma_i * q.grad());
      gw[k] = g.template cast<Real>();
      lap[k] = static_cast<Real>(2.0 * q.r_ij.dot(g) / (q.r * q.r + eta2));
    }
  }

  void compute(const NeighborList<D>& nl, const std::vector<double>& V,
               const std::vector<Mat<D>>& gamma, double eta2) {
    const std::size_t N = nl.num_particles();
    resize(nl);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::size_t i = 0; i < N; ++i)
      row(nl, V, gamma[i], eta2, i);
  }
};

// <grad u>, <div u> = tr <grad u>, <lap u> (eqs. 15-17), on the cached pair coefficients
// (interact_indexed).
template <int D, class Real = double>
struct VelocityDerivatives {
  const PairCoefficients<D, Real>& c;
  const std::vector<Vec<D>>& u;
  std::vector<Mat<D>>& grad_u;
  std::vector<double>& div;
  std::vector<Vec<D>>& lap_u;

  struct Acc {
    Mat<D> g = Mat<D>::Zero();
    Vec<D> lap = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, std::uint32_t j, std::uint32_t k, Acc& a) const {
    const Vec<D> du = u[j] - u[i];
    a.g.noalias() += du * c.gw_of(k).transpose();
    a.lap -= c.lap_of(k) * du;
  }
  void finish(std::size_t i, const Acc& a) {
    grad_u[i] = a.g;
    div[i] = a.g.trace();
    lap_u[i] = a.lap;
  }
};

// <grad(div u)> and the intermediate velocity u* (eq. 8); on body particles the pseudo
// acceleration Du_s/Dt = (u*_s - 0) / dt used by eq. (20).
template <int D, class Real = double>
struct Predict {
  const PairCoefficients<D, Real>& c;
  const std::vector<double>& div;
  const std::vector<Vec<D>>& lap_u;
  const std::vector<Vec<D>>& u_n;
  const std::vector<Kind>& kind;
  double r_al, nu, dt;
  Vec<D> g;
  std::vector<Vec<D>>& u_star;
  std::vector<Vec<D>>& a_s;

  struct Acc {
    Vec<D> gd = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, std::uint32_t j, std::uint32_t k, Acc& a) const {
    a.gd += (div[j] - div[i]) * c.gw_of(k);
  }
  void finish(std::size_t i, const Acc& a) {
    const Vec<D> acc = r_al * a.gd + nu * lap_u[i];
    if (kind[i] == Kind::Body) {
      a_s[i] = acc;
      u_star[i] = Vec<D>::Zero();
    } else {
      u_star[i] = u_n[i] + dt * (acc + g);
    }
  }
};

// Pressure update (eq. 10) into p_new.
template <int D, class Real = double>
struct PressureUpdate {
  const PairCoefficients<D, Real>& c;
  const std::vector<Vec<D>>& u_star;
  const std::vector<double>& p;
  double r_al, rho, dt;
  std::vector<double>& p_new;
  std::vector<double>& div_star;

  struct Acc {
    double div = 0.0, lap = 0.0;
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, std::uint32_t j, std::uint32_t k, Acc& a) const {
    a.div += (u_star[j] - u_star[i]).dot(c.gw_of(k));
    a.lap += c.lap_of(k) * (p[i] - p[j]);
  }
  void finish(std::size_t i, const Acc& a) {
    div_star[i] = a.div;
    p_new[i] = p[i] - r_al * rho * (a.div - dt / rho * a.lap);
  }
};

// Body pressure, eq. (20): p_s = p_j + (dp/dn) (r_s - r_j) . n, dp/dn = rho (Du_s/Dt) . n,
// averaged over the fluid neighbours j with weights W_sj.
template <int D>
struct BodyPressure {
  const std::vector<Kind>& kind;
  const std::vector<Vec<D>>& a_s;
  const std::vector<Vec<D>>& normal;
  double rho;
  std::vector<double>& p;

  struct Acc {
    double num = 0.0, den = 0.0, dpdn = 0.0;
    Vec<D> n = Vec<D>::Zero();
  };
  Acc init(std::size_t i) const {
    Acc a;
    a.n = normal[i];
    a.dpdn = rho * a_s[i].dot(a.n);
    return a;
  }
  void pair(std::size_t, const Pair<D>& q, Acc& a) const {
    if (kind[q.j] != Kind::Fluid)
      return;
    a.num += q.W * (p[q.j] + a.dpdn * q.r_ij.dot(a.n));
    a.den += q.W;
  }
  void finish(std::size_t i, const Acc& a) { p[i] = a.den > 0.0 ? a.num / a.den : 0.0; }
};

// Velocity update (eq. 11) with the corrected pressure gradient (eq. 15).
template <int D, class Real = double>
struct Correct {
  const PairCoefficients<D, Real>& c;
  const std::vector<double>& p;
  const std::vector<Vec<D>>& u_star;
  double dt_over_rho;
  std::vector<Vec<D>>& grad_p;
  std::vector<Vec<D>>& u;

  struct Acc {
    Vec<D> g = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, std::uint32_t j, std::uint32_t k, Acc& a) const {
    a.g += (p[j] - p[i]) * c.gw_of(k);
  }
  void finish(std::size_t i, const Acc& a) {
    grad_p[i] = a.g;
    u[i] = u_star[i] - dt_over_rho * a.g;
  }
};

// Artificial particle displacement, eq. (18):
//   dr_i = sum_j r_ij / r_ij^3 r0^2 u_v dt,  r0 = mean_j r_ij,
//   u_v = || sum_j (u_i - u_j) W_ij || / sum_j W_ij.
template <int D>
struct Displacement {
  const std::vector<Vec<D>>& u;
  double dt;
  std::vector<Vec<D>>& dr;

  struct Acc {
    Vec<D> s = Vec<D>::Zero(), du = Vec<D>::Zero();
    double rsum = 0.0, w = 0.0;
    int n = 0;
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    a.s += q.r_ij / (q.r * q.r * q.r);
    a.du += (u[i] - u[q.j]) * q.W;
    a.w += q.W;
    a.rsum += q.r;
    ++a.n;
  }
  void finish(std::size_t i, const Acc& a) {
    if (a.n == 0 || a.w <= 0.0) {
      dr[i] = Vec<D>::Zero();
      return;
    }
    const double r0 = a.rsum / a.n;
    const double u_v = a.du.norm() / a.w;
    dr[i] = a.s * (r0 * r0 * u_v * dt);
  }
};

} // namespace ops

// Real: the storage precision of the cached pair coefficients (ops::PairCoefficients).
template <int D, class Kernel, class Real = double>
class Scheme {
public:
  Scheme(const Kernel& kernel, const Settings& s) : kernel_(kernel), s_(s) {
    eta2_ = std::pow(s.eta_over_h * kernel.h, 2);
  }

  const Settings& settings() const { return s_; }
  const Timers& timers() const { return timers_; }
  // The pair coefficients of the last geometry() (ops::PairCoefficients).
  using Coefficients = ops::PairCoefficients<D, Real>;
  const Coefficients& coefficients() const { return coef_; }

  // What the scheme carries across steps (for checkpoints): only its timers and counters; the
  // work arrays are recomputed from the particles at every step.
  std::vector<double> carried_state() const {
    const Timers& t = timers_;
    return {t.geometry,
            t.iterations,
            t.refresh,
            t.shifting,
            static_cast<double>(t.evaluations),
            t.particle_iterations,
            t.particle_steps};
  }
  void restore_carried_state(const std::vector<double>& c) {
    io::expect_state_size(c, 7, "alsph: checkpoint state");
    timers_ = Timers{c[0], c[1], c[2], c[3], static_cast<long>(c[4]), c[5], c[6]};
  }

  // Per-particle work arrays (sized to the particle count at each step; no allocation once the
  // count has reached its maximum). Public for diagnostics: after step(), div holds <div u>,
  // grad_p <grad p>, a_s the body pseudo-acceleration.
  std::vector<Vec<D>> r_n, u_n, r_prev, u_star, lap_u, a_s, grad_p, dr;
  std::vector<Mat<D>> gamma, grad_u;
  std::vector<double> div, div_star, p_new, trace_b;

  // Advances one step of size settings().dt. nl must have been built on p.r (after the cell list
  // build); ghosts lists the mirror ghosts in the current order; normal holds the outward normal
  // of body particles; buffer_pressure(p, nl) sets the pressure of Buffer particles.
  template <class BufferPressure>
  StepStats step(Particles<D>& p, NeighborList<D>& nl, const MirrorGhosts<D>& ghosts,
                 const std::vector<Vec<D>>& normal, BufferPressure&& buffer_pressure,
                 const Vec<D>& g = Vec<D>::Zero()) {
    const std::size_t N = p.size();
    resize(N);
    const auto& kind = p.kind;
    auto is_fluid = [&](std::size_t i) { return kind[i] == Kind::Fluid; };
    auto fluid_or_body = [&](std::size_t i) {
      return kind[i] == Kind::Fluid || kind[i] == Kind::Body;
    };
    auto not_ghost = [&](std::size_t i) { return kind[i] != Kind::Wall; };
    auto is_body = [&](std::size_t i) { return kind[i] == Kind::Body; };

    StepStats st;
    double umax2 = 0.0;
    for (std::size_t i = 0; i < N; ++i) {
      r_n[i] = p.r[i], u_n[i] = p.v[i], r_prev[i] = p.r[i];
      if (kind[i] == Kind::Fluid)
        umax2 = std::max(umax2, p.v[i].squaredNorm());
    }
    const double dt = s_.dt;
    st.u_max = std::sqrt(umax2);
    st.r_al = s_.c_bv * umax2 * dt;

    const double t0 = cpu_seconds();
    geometry(p, nl, &ghosts);
    const double t1 = cpu_seconds();
    timers_.geometry += t1 - t0;

    int m = 0;
    for (;; ++m) {
      if (s_.algorithm == 1 && m > 0) {
        // The pair refresh with V_i of each refreshed row, then Gamma and the coefficients.
        const double ta = cpu_seconds();
        SummationDensity<D, Kernel> sd{p, kernel_};
        refresh_pairs(p, nl, [&](std::size_t i) { interact_row(nl, sd, i); });
        gamma_and_coefficients(p, nl, &ghosts);
        timers_.refresh += cpu_seconds() - ta;
      }
      // <grad u>, <div u>, <lap u> on the current iterate (eq. 13 check and input of eq. 8).
      ops::VelocityDerivatives<D, Real> da{coef_, p.v, grad_u, div, lap_u};
      interact_indexed(nl, da, not_ghost);
      ++timers_.evaluations;
      for (std::size_t i = 0; i < N; ++i)
        if (kind[i] == Kind::Body)
          div[i] = 0.0; // rigid body
      ghosts.copy_scalar(div);
      fluid_divergence(p, st);
      if (m > 0 && st.div_max <= s_.epsilon) {
        st.converged = true;
        break;
      }
      if (m >= s_.max_iterations)
        break;

      // eq. (8): u*; buffers keep their velocity; body u* = 0 (no slip).
      for (std::size_t i = 0; i < N; ++i)
        if (kind[i] == Kind::Buffer)
          u_star[i] = p.v[i];
      ops::Predict<D, Real> pr{coef_, div, lap_u, u_n, kind, st.r_al, s_.nu, dt, g, u_star, a_s};
      interact_indexed(nl, pr, fluid_or_body);
      ghosts.copy_vector(u_star);

      // eq. (10) on fluid, then eq. (20) on the body, buffers (case), ghosts.
      ops::PressureUpdate<D, Real> pu{coef_, u_star, p.p, st.r_al, s_.rho, dt, p_new, div_star};
      interact_indexed(nl, pu, is_fluid);
      for (std::size_t i = 0; i < N; ++i)
        if (kind[i] == Kind::Fluid)
          p.p[i] = p_new[i];
      ops::BodyPressure<D> bp{kind, a_s, normal, s_.rho, p.p};
      interact(nl, bp, is_body);
      buffer_pressure(p, nl);
      ghosts.copy_scalar(p.p);

      // eq. (11), eq. (12).
      ops::Correct<D, Real> co{coef_, p.p, u_star, dt / s_.rho, grad_p, p.v};
      interact_indexed(nl, co, is_fluid);
      ghosts.copy_vector(p.v);
      for (std::size_t i = 0; i < N; ++i)
        if (kind[i] == Kind::Fluid || kind[i] == Kind::Buffer)
          p.r[i] = r_n[i] + 0.5 * dt * (u_n[i] + p.v[i]);
      ghosts.copy_positions(p.r);
    }
    st.iterations = m;
    const double t2 = cpu_seconds();
    timers_.iterations += t2 - t1;
    timers_.particle_iterations += static_cast<double>(N) * m;
    timers_.particle_steps += static_cast<double>(N);

    if (s_.shifting) {
      // eq. (18) on the final positions (algorithm 2 has its pairs still on r^n: each row is
      // refreshed and, for a fluid particle, read while in cache), eq. (19).
      ops::Displacement<D> ds{p.v, dt, dr};
      if (s_.algorithm != 1 || m == 0)
        refresh_pairs(p, nl, [&](std::size_t i) {
          if (is_fluid(i))
            interact_row(nl, ds, i);
        });
      else
        interact(nl, ds, is_fluid);
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < N; ++i) {
        if (kind[i] != Kind::Fluid)
          continue;
        p.r[i] += dr[i];
        p.v[i] += grad_u[i] * dr[i];
        p.p[i] += grad_p[i].dot(dr[i]);
      }
      timers_.shifting += cpu_seconds() - t2;
    }
    return st;
  }

  struct NoRowWork {
    void operator()(std::size_t) const {}
  };
  // Recomputes r_ij, r, W, dW of the cached pairs from the particles' displacement since the last
  // refresh (or since r^n); no new search. row_done(i) is called on each row right after it is
  // refreshed (a per-row operator reading the row while it is in cache; it must read only that
  // row's pairs, the other rows may not be refreshed yet).
  template <class RowDone = NoRowWork>
  void refresh_pairs(const Particles<D>& p, NeighborList<D>& nl, RowDone&& row_done = {}) {
    const std::size_t N = nl.num_particles();
#pragma omp parallel for schedule(dynamic, 256)
    for (std::size_t i = 0; i < N; ++i) {
      const Vec<D> di = p.r[i] - r_prev[i];
      for (std::uint32_t k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
        const std::uint32_t j = nl.j[k];
        const Vec<D> rij = nl.r_ij[k] + di - (p.r[j] - r_prev[j]);
        const double r = std::max(rij.norm(), 1e-12 * kernel_.h);
        nl.r_ij[k] = rij, nl.r[k] = r, nl.W[k] = kernel_.W(r), nl.dW[k] = kernel_.dW(r);
      }
      row_done(i);
    }
    for (std::size_t i = 0; i < N; ++i)
      r_prev[i] = p.r[i];
  }

  // V_i = 1 / sum_j W_ij (after eq. 14) and Gamma_i = alpha_i^{-1} (eq. 17) on the pairs' geometry.
  // A mirror ghost takes the volume of its source: its own kernel sum is truncated (no particles
  // lie beyond one support behind the wall), the source's is complete.
  void geometry(Particles<D>& p, const NeighborList<D>& nl,
                const MirrorGhosts<D>* ghosts = nullptr) {
    SummationDensity<D, Kernel> sd{p, kernel_};
    interact(nl, sd);
    gamma_and_coefficients(p, nl, ghosts);
  }

  // With V of every particle: the ghosts' V from their sources, then row by row Gamma_i
  // (CorrectionMatrix on the row of i) and the row's pair coefficients (ops::PairCoefficients).
  void gamma_and_coefficients(Particles<D>& p, const NeighborList<D>& nl,
                              const MirrorGhosts<D>* ghosts) {
    if (ghosts)
      ghosts->copy_scalar(p.V);
    CorrectionMatrix<D> cm{p.V, gamma, trace_b};
    coef_.resize(nl);
    const std::size_t N = nl.num_particles();
#pragma omp parallel for schedule(dynamic, 256)
    for (std::size_t i = 0; i < N; ++i) {
      interact_row(nl, cm, i);
      coef_.row(nl, p.V, gamma[i], eta2_, i);
    }
  }

private:
  Kernel kernel_;
  Settings s_;
  double eta2_ = 0.0;
  Timers timers_;
  Coefficients coef_; // of the current pair geometry (geometry())

  void resize(std::size_t N) {
    for (auto* a : {&r_n, &u_n, &r_prev, &u_star, &lap_u, &a_s, &grad_p, &dr})
      a->resize(N, Vec<D>::Zero());
    gamma.resize(N, Mat<D>::Identity());
    grad_u.resize(N, Mat<D>::Zero());
    for (auto* a : {&div, &div_star, &p_new, &trace_b})
      a->resize(N, 0.0);
  }

  void fluid_divergence(const Particles<D>& p, StepStats& st) const {
    double mx = 0.0, sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.kind[i] == Kind::Fluid) {
        const double a = std::abs(div[i]);
        mx = std::max(mx, a), sum += a, ++n;
      }
    st.div_max = mx;
    st.div_mean = n ? sum / n : 0.0;
  }
};

} // namespace sph::alsph
