// Total-Lagrangian SPH for an elastic solid (scheme "elastic_solid"; docs/solid.md).
//
// What it follows (formulas read from the papers and from SPHinXsys' solid dynamics; this code is
// our own):
//   - Zhang, Rezavand & Hu, "A multi-resolution SPH method for fluid-structure interactions",
//     J. Comput. Phys. 429 (2021) 110028 (seed 002 ref. [38]), section 2: the solid in its
//     reference configuration, kernel gradient corrected by B, deformation gradient F, first
//     Piola-Kirchhoff stress, momentum equation in the reference configuration.
//   - SPHinXsys (github.com/Xiangyu-Hu/SPHinXsys), src/shared/particle_dynamics/solid_dynamics/
//     elastic_dynamics.{h,cpp} (LinearGradientCorrectionMatrix, DeformationGradientBySummation,
//     Integration1stHalfPK2, AcousticTimeStep) and src/shared/materials/elastic_solid.{h,cpp}
//     (SaintVenantKirchhoffSolid, NumericalDampingRightCauchy).
//   - Bonet & Wood, "Nonlinear continuum mechanics for finite element analysis" (2nd ed., 2008),
//     sections 6.4-6.5: the Saint Venant-Kirchhoff and compressible neo-Hookean laws.
//
// Equations (every sum over the neighbours j of i in the reference configuration r0, which never
// changes: the neighbour list, grad W0_ij = grad_i W(r0_i - r0_j) and V_j = m_j / rho0 are
// computed once):
//   B_i   = ( sum_j V_j (r0_j - r0_i) (x) grad W0_ij )^-1                 (correction matrix)
//   F_i   = ( sum_j V_j (x_j - x_i) (x) grad W0_ij ) B_i                   (deformation gradient)
//   dF_i  = ( sum_j V_j (v_j - v_i) (x) grad W0_ij ) B_i                   (its rate)
//   E = (F^T F - I) / 2,  dE = (dF^T F + F^T dF) / 2
//   S = S_law(F) + eta dE,  eta = damping rho0 c_p h                      (Kelvin-Voigt damping)
//   P = F S                                                               (first Piola-Kirchhoff)
//   rho0 dv_i/dt = sum_j V_j (P_i B_i^T + P_j B_j^T) grad W0_ij + rho0 g + f_i / V_i
//   (f_i: an external force on particle i, Options::external_force, e.g. the fluid's pressure and
//   viscous force on a coupled solid, coupling/fsi.hpp, as Zhang et al. 2021 section 3: the kick
//   adds f_i / m_i)
// The transpose B^T in the momentum equation is what makes its elastic part the exact negative
// gradient of the discrete strain energy sum_i V_i psi(F_i) when F_i is written as above (the
// same transpose as SPHinXsys' Integration1stHalfPK2, "correction matrix in a form of
// transpose"); with it, and F computed by summation from the current positions, the scheme
// conserves linear momentum (pairwise antisymmetric terms) and angular momentum (F P^T = F S F^T
// symmetric for any symmetric S, damping included) to round-off; see docs/solid.md.
//   Laws (2D: the 3D laws with F_zz = 1, a plane-strain slab; lambda, G the 3D Lame constants):
//     Saint Venant-Kirchhoff  S = lambda tr(E) I + 2 G E,   psi = lambda/2 tr(E)^2 + G E:E
//     neo-Hookean (compressible, Bonet & Wood eq. 6.28)
//                             S = G (I - C^-1) + lambda ln J C^-1,
//                             psi = G/2 (tr C + 3 - D - 3) - G ln J + lambda/2 (ln J)^2
//   Damping: the Kelvin-Voigt numerical damping of SPHinXsys' NumericalDampingRightCauchy
//     (a viscous PK2 stress proportional to the Green-Lagrange strain rate, scaled by rho0 c h),
//     here with one coefficient for every component (SPHinXsys: 0.5 rho0 c h dE with c the bulk
//     sound speed for the normal components and the shear-wave speed for the others, times 0.125
//     in Integration1stHalfPK2RightCauchy). In the stress, S stays symmetric: torque-free.
//   Time step (acoustic, as SPHinXsys' AcousticTimeStep): dt = cfl h / (c_p + |v|max),
//     c_p = sqrt((lambda + 2 G) / rho0) the P-wave speed (the fastest wave of the solid).
//   Time integration: velocity Verlet (kick-drift-kick): v += dt/2 a; x += dt v; F, dF (dF from
//     the half-step velocity), P, a; v += dt/2 a. Wall particles (the clamp) keep their reference
//     positions and zero velocity; their F and P are computed like every other particle's, so
//     they are part of the body that holds the beam (as SPHinXsys' FixBodyPartConstraint).
#pragma once

#include "core/cell_list.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "operators/correction_matrix.hpp"
#include "operators/interact.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph::solid {

// Isotropic linear-elastic constants from Young's modulus E and Poisson ratio nu (3D).
struct Elastic {
  double E = 0.0, nu = 0.0;
  double lambda() const { return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); }
  double G() const { return E / (2.0 * (1.0 + nu)); }
  // P-wave (longitudinal) speed sqrt((lambda + 2 G) / rho0).
  double c_p(double rho0) const { return std::sqrt((lambda() + 2.0 * G()) / rho0); }
  // Plane-strain modulus E / (1 - nu^2): the bending stiffness per unit depth of a 2D slab is
  // E' H^3 / 12.
  double plane_strain_E() const { return E / (1.0 - nu * nu); }
};

// Saint Venant-Kirchhoff: S = lambda tr(E) I + 2 G E, E = (F^T F - I) / 2.
template <int D>
struct SaintVenantKirchhoff {
  double lambda = 0.0, G = 0.0;
  static constexpr const char* name = "svk";
  Mat<D> pk2(const Mat<D>& F) const {
    const Mat<D> E = 0.5 * (F.transpose() * F - Mat<D>::Identity());
    return lambda * E.trace() * Mat<D>::Identity() + 2.0 * G * E;
  }
  double energy(const Mat<D>& F) const {
    const Mat<D> E = 0.5 * (F.transpose() * F - Mat<D>::Identity());
    const double tr = E.trace();
    return 0.5 * lambda * tr * tr + G * E.squaredNorm();
  }
};

// Compressible neo-Hookean (Bonet & Wood eq. 6.28): S = G (I - C^-1) + lambda ln J C^-1.
template <int D>
struct NeoHookean {
  double lambda = 0.0, G = 0.0;
  static constexpr const char* name = "neo_hookean";
  Mat<D> pk2(const Mat<D>& F) const {
    const Mat<D> Ci = (F.transpose() * F).inverse();
    const double lnJ = std::log(F.determinant());
    return G * (Mat<D>::Identity() - Ci) + lambda * lnJ * Ci;
  }
  double energy(const Mat<D>& F) const {
    const double lnJ = std::log(F.determinant());
    const double trC = (F.transpose() * F).trace() + (3 - D); // C_zz = 1 in 2D (plane strain)
    return 0.5 * G * (trC - 3.0) - G * lnJ + 0.5 * lambda * lnJ * lnJ;
  }
};

namespace ops {

// F_i, its rate, the stress term A_i = P_i B_i^T of the momentum equation and the strain-energy
// density psi_i (see the file header), for every particle.
template <int D, class Law>
struct Deformation {
  const std::vector<double>& V; // reference volumes
  const std::vector<Vec<D>>& x; // current positions
  const std::vector<Vec<D>>& v; // velocities (the half-step velocity inside a step)
  const std::vector<Mat<D>>& B; // correction matrices of the reference configuration
  Law law;
  double eta;                    // Kelvin-Voigt viscosity of the numerical damping
  double rho0;                   // reference density
  std::vector<Mat<D>>& F;        // out: deformation gradient
  std::vector<Mat<D>>& A;        // out: P_i B_i^T
  std::vector<double>& psi;      // out: strain-energy density (per reference volume)
  std::vector<double>& rho;      // out: density rho0 / J
  std::vector<double>& pressure; // out: -tr(sigma) / D, sigma = F S F^T / J (damping included)

  struct Acc {
    Mat<D> dx = Mat<D>::Zero(), dv = Mat<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    const Vec<D> g = V[q.j] * q.grad();
    a.dx.noalias() += (x[q.j] - x[i]) * g.transpose();
    a.dv.noalias() += (v[q.j] - v[i]) * g.transpose();
  }
  void finish(std::size_t i, const Acc& a) {
    const Mat<D> Fi = a.dx * B[i], dF = a.dv * B[i];
    const Mat<D> dE = 0.5 * (dF.transpose() * Fi + Fi.transpose() * dF);
    const Mat<D> S = law.pk2(Fi) + eta * dE;
    const double J = Fi.determinant();
    F[i] = Fi;
    A[i].noalias() = (Fi * S) * B[i].transpose();
    psi[i] = law.energy(Fi);
    rho[i] = rho0 / J;
    pressure[i] = -(S * (Fi.transpose() * Fi)).trace() / (D * J); // tr(F S F^T) = tr(S C)
  }
};

// Internal acceleration a_i = (1 / rho0) sum_j V_j (A_i + A_j) grad W0_ij (stress and damping).
template <int D>
struct StressDivergence {
  const std::vector<double>& V;
  const std::vector<Mat<D>>& A;
  double inv_rho0;
  std::vector<Vec<D>>& a_int; // out

  struct Acc {
    Vec<D> f = Vec<D>::Zero();
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    a.f.noalias() += V[q.j] * ((A[i] + A[q.j]) * q.grad());
  }
  void finish(std::size_t i, const Acc& a) { a_int[i] = inv_rho0 * a.f; }
};

} // namespace ops

// The cross product's magnitude-carrying part: x0 y1 - x1 y0 in 2D, the vector in 3D.
template <int D>
auto cross(const Vec<D>& a, const Vec<D>& b) {
  if constexpr (D == 2)
    return Eigen::Matrix<double, 1, 1>(a[0] * b[1] - a[1] * b[0]);
  else
    return Vec<3>(a.cross(b));
}

enum class Law { SaintVenantKirchhoff, NeoHookean };

struct Options {
  std::string kernel = "wendland_c2";
  double h_over_dx = 1.3;
  Law law = Law::SaintVenantKirchhoff;
  double cfl = 0.6;
  double damping = 0.05;
  // Physical, from the flow: reference density, Young's modulus, Poisson ratio, spacing, h.
  double rho0 = 1.0, E = 0.0, nu = 0.0, dx = 0.0, h = 0.0;
  // Vector field of an external force on each particle (-1: none; Flow::external_force).
  int external_force = -1;
};

// Sums of the internal forces m_i a_i over every particle (clamp included): with exact pairwise
// antisymmetry and F P^T symmetric they vanish to round-off (the scales are the sums of the
// magnitudes, for relative values).
template <int D>
struct InternalSums {
  double force = 0.0, force_scale = 0.0, torque = 0.0, torque_scale = 0.0;
};

// The scheme on one particle set: Solid particles are integrated, Wall particles are held at their
// reference positions. K: the kernel, L: the law (SaintVenantKirchhoff<D> or NeoHookean<D>).
template <int D, class K, class L>
class Scheme {
public:
  Scheme(Particles<D>& p, const Options& o, const K& kernel)
      : p_(p), o_(o), W_(kernel), r0_(p.add_vector("solid/r0")), a_(p.add_vector("solid/a")) {
    const Elastic el{o.E, o.nu};
    if (!(o.E > 0.0) || !(o.nu > -1.0 && o.nu < 0.5))
      throw std::invalid_argument("elastic_solid: needs E > 0 and -1 < nu < 0.5");
    law_.lambda = el.lambda(), law_.G = el.G();
    c_p_ = el.c_p(o.rho0);
    eta_ = o.damping * o.rho0 * c_p_ * o.h;
    for (Kind k : p.kind)
      if (k != Kind::Solid && k != Kind::Wall)
        throw std::invalid_argument("elastic_solid: the particle set holds particles that are "
                                    "neither Solid nor Wall (fluid schemes do not couple yet)");
  }

  // The reference configuration is the current one: particles sorted by cell once, the neighbour
  // list, grad W0 and B_i of the reference positions, and the initial accelerations.
  void init() {
    p_.vector(r0_) = p_.r;
    CellList<D> cells(Domain<D>{}, W_.support());
    cells.build(p_); // reorders every field; never again (the pairs are those of r0)
    reference(cells);
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (p_.kind[i] == Kind::Wall)
        p_.v[i] = Vec<D>::Zero();
    forces();
  }
  // After a checkpoint restored the fields (r, v, solid/r0, solid/a, in the order of init's sort):
  // the reference pairs and B again, F and psi of the restored positions.
  void resume() {
    CellList<D> cells(Domain<D>{}, W_.support());
    cells.index_sorted(p_.vector(r0_));
    reference(cells);
    const std::vector<Vec<D>> a = p_.vector(a_);
    forces();          // F, A, psi of the restored state
    p_.vector(a_) = a; // the accelerations of the step that was saved (from v^{n-1/2})
  }

  double c_p() const { return c_p_; }
  double eta() const { return eta_; }
  // dt = cfl h / (c_p + |v|max) over the Solid particles.
  double stable_dt() const {
    double vmax = 0.0;
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (p_.kind[i] == Kind::Solid)
        vmax = std::max(vmax, p_.v[i].norm());
    return o_.cfl * o_.h / (c_p_ + vmax);
  }

  // One velocity-Verlet step of at most dt_max; returns the step taken.
  double step(double dt_max) {
    const double dt = std::min(stable_dt(), dt_max);
    kick(0.5 * dt);
    const std::size_t N = p_.size();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < N; ++i)
      if (p_.kind[i] == Kind::Solid)
        p_.r[i] += dt * p_.v[i];
    forces();
    kick(0.5 * dt);
    ++steps_;
    return dt;
  }

  void set_body_acceleration(const Vec<D>& g) {
    g_ = g;
  }
  const NeighborList<D>& neighbors() const {
    return nl_;
  }
  long steps() const {
    return steps_;
  }
  void set_steps(long n) {
    steps_ = n;
  }

  const std::vector<Mat<D>>& F() const {
    return F_;
  }
  const std::vector<Mat<D>>& B() const {
    return B_;
  }
  const std::vector<Mat<D>>& stress_term() const {
    return A_;
  } // P_i B_i^T
  const std::vector<Vec<D>>& internal_acceleration() const {
    return p_.vector(a_);
  }
  const std::vector<Vec<D>>& reference_positions() const {
    return p_.vector(r0_);
  }
  const L& law() const {
    return law_;
  }

  // sum_i V_i psi(F_i) over every particle (the clamp included: its F sees the beam move).
  double elastic_energy() const {
    double e = 0.0;
    for (std::size_t i = 0; i < p_.size(); ++i)
      e += p_.V[i] * psi_[i];
    return e;
  }
  double kinetic_energy() const {
    double e = 0.0;
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (p_.kind[i] == Kind::Solid)
        e += 0.5 * p_.m[i] * p_.v[i].squaredNorm();
    return e;
  }
  InternalSums<D> internal_sums() const {
    const auto& a = p_.vector(a_);
    Vec<D> f = Vec<D>::Zero();
    decltype(cross<D>(f, f)) tq = decltype(tq)::Zero();
    InternalSums<D> s;
    for (std::size_t i = 0; i < p_.size(); ++i) {
      const Vec<D> fi = p_.m[i] * a[i];
      f += fi, tq += cross<D>(p_.r[i], fi);
      s.force_scale += fi.norm(), s.torque_scale += p_.r[i].norm() * fi.norm();
    }
    s.force = f.norm(), s.torque = tq.norm();
    return s;
  }

  // F, A, psi and the internal accelerations of the current positions and velocities (with the
  // density rho0 / J and the pressure -tr(sigma) / D into p.rho and p.p, for the outputs).
  void forces() {
    ops::Deformation<D, L> def{p_.V,    p_.r, p_.v, B_,   law_,   eta_,
                               o_.rho0, F_,   A_,   psi_, p_.rho, p_.p};
    interact(nl_, def);
    ops::StressDivergence<D> div{p_.V, A_, 1.0 / o_.rho0, p_.vector(a_)};
    interact(nl_, div);
  }

private:
  Particles<D>& p_;
  Options o_;
  K W_;
  L law_;
  int r0_, a_;
  double c_p_ = 0.0, eta_ = 0.0;
  Vec<D> g_ = Vec<D>::Zero();
  long steps_ = 0;
  NeighborList<D> nl_;
  std::vector<Mat<D>> B_, F_, A_;
  std::vector<double> psi_, trace_;

  void reference(const CellList<D>& cells) {
    nl_.build(cells, p_.vector(r0_), W_);
    const std::size_t N = p_.size();
    B_.resize(N), F_.resize(N), A_.resize(N), psi_.resize(N), trace_.resize(N);
    // CorrectionMatrix gives gamma_i = (sum_j V_j grad W0_ij (x) (r0_j - r0_i))^-1 = B_i^T.
    std::vector<Mat<D>> gamma(N);
    CorrectionMatrix<D> cm{p_.V, gamma, trace_};
    interact(nl_, cm);
    for (std::size_t i = 0; i < N; ++i)
      B_[i] = gamma[i].transpose();
  }
  void kick(double h) {
    const auto& a = p_.vector(a_);
    const std::size_t N = p_.size();
    if (o_.external_force >= 0) {
      const auto& f = p_.vector(o_.external_force);
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < N; ++i)
        if (p_.kind[i] == Kind::Solid)
          p_.v[i] += h * (a[i] + g_ + f[i] / p_.m[i]);
      return;
    }
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < N; ++i)
      if (p_.kind[i] == Kind::Solid)
        p_.v[i] += h * (a[i] + g_);
  }
};

} // namespace sph::solid
