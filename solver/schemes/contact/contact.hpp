// Scheme "contact": Godunov-type contact SPH for compressible viscous fluids with the
// numerical-viscosity correction factor zeta (seed 003: Parshikov, Medin, Rublev & Dyachkov,
// "Adjusting the numerical viscosity in the Godunov-like SPH method at modeling compressible
// flows"; the inviscid method is Parshikov & Medin 2002, J. Comput. Phys. 180, 358).
//
// Per particle: linear equation of state (4) P = c0^2 (rho - rho0); size D_i = (m_i/rho_i)^(1/d)
// (11); per-pair smoothing length h_ij = alpha (D_i + D_j) (12). Per pair: the acoustic Riemann
// solution (8)-(9) and the viscous contact stresses (27)-(32) of the physical viscosity eta and,
// with the opposite sign, of the numerical viscosity zeta eta_num (eq. 26; eta_num from eq. 37 or
// given). Rates: strain rate (33), momentum (35), total energy (36); density by the exponential
// update (34). Several materials in one run: every particle carries rho0, c0, eta.
//
// The pair terms in vector form (e = e^R from i to j, s = e . grad_i W_ij(h_ij) = -dW/dr >= 0):
//   tau_ij  = (eta_ij - eta_ij^num) / |r_ij| [ (U_j - U_i) + 1/3 ((U_j - U_i) . e) e ]   (30)-(32)
//   F_ij    = P*_ij e - tau_ij                                   (the bracket of eq. 35)
//   Uc_ij   = U*R e + (1 - e e) U*(eta) - [U*(zeta eta_num) - U*(eta)]   contact velocity
//   deps_i/dt = -2 sum_j m_j/rho_j (U_i - Uc_ij) . e s                                    (33)
//   dU_i/dt   = -2 sum_j m_j/(rho_i rho_j) F_ij s                                         (35)
//   dE_i/dt   = -2 sum_j m_j/(rho_i rho_j) F_ij . Uc_ij s                                 (36)
// where U*(eta) is the contact velocity (27) and U*R the Riemann velocity (9). Reading of the
// "num" velocities of (33) and (36): taken literally from (27) they are contact velocities (means
// of U_i, U_j), and U_i^R - U*R + U*R,num would then not be Galilean invariant; we read them as
// the shift of the contact velocity that substituting zeta eta_num for eta in (27) causes. It is
// zero for one material and only matters at an interface of two fluids (docs/contact.md).
// F_ij and Uc_ij are exactly antisymmetric / symmetric under i <-> j, so momentum and total energy
// are conserved to round-off.
//
// Time integration: midpoint predictor-corrector, one neighbour search per step. The step is the
// named stage list stage_names(): neighbours, eos, rates, predict, ghosts, eos, rates, correct,
// ghosts. Between the search and the end of the step positions move; pair vectors are updated
// from the displacements, r_ij = r_ij(search) + (d_i - d_j), and the search radius carries a skin.
//
// Kernel of h_ij: the core kernels take a fixed h in their constructor; the scheme keeps one
// unit-h kernel object K(1) and scales it per pair, W_h(r) = W_1(r/h) / h^d and
// dW_h/dr = W_1'(r/h) / h^(d+1), which is exactly the kernel of smoothing length h.
//
// Slip walls: planes normal to a non-periodic axis, by mirror particles (Kind::Wall) that copy the
// state of their source particle with the normal position and velocity reflected. The set of
// mirrored particles is chosen at init() (all particles within one search radius of the wall) and
// kept: right for flows along the wall (the shear layer), not for flows that move particles
// towards or away from a wall by more than the skin.
//
// Solid bodies (no-slip, at rest): particles of Kind::Wall added before init() (src = -1), a
// layer at least one search radius thick. In a pair (i fluid, j solid) particle j takes the state
// that makes the contact a no-slip wall at rest: U_j = -U_i (so the contact velocity of (9) and
// (27) is zero for equal impedances and viscosities), P_j = P_i + rho_i g . (r_j - r_i) (the
// pressure of i carried to j by the body force, as in Adami, Hu & Adams 2012, J. Comput. Phys.
// 231, 7057, eq. 27), and i's impedance and viscosities. The correction zeta eta_num acts on these
// pairs as on fluid pairs. The force the solids exert on particle i is kept (solid_force()).
//
// Body force: a constant acceleration g (Options::g) added to dU/dt of (35), its power g . U_i to
// dE/dt of (36). Per-particle body force (optional field "g_factor", set by a case): particle i
// feels g_i = g * g_factor_i (in (35), (36) and the solid-wall pressure above), e.g. the reduced
// gravity of the falling ball: 0 on the liquid and 1 - rho_f / rho_b on the ball, the liquid's
// hydrostatic pressure subtracted (solver/cases/falling_ball.cpp). Without the field: g for all.
//
// Per-particle correction (optional field "zeta_factor", set by a case): particle i's numerical
// viscosity is corrected by zeta * zeta_factor_i instead of zeta, e.g. 0 on a body the correction
// must not act on (the falling ball of seed 003 section 5.3: "the correction to numerical
// viscosity tensor is then applied only for liquid particles"). Without the field: zeta for all.
#pragma once

#include "core/cell_list.hpp"
#include "core/domain.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "io/checkpoint.hpp"
#include "operators/interact.hpp"
#include "schemes/contact/riemann.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph::contact {

// Eq. (37): numerical viscosity of the scheme in the shear test (Wendland C2), Pa s, for particle
// size D0 (m), impedance Z = rho0 c0 (kg m^-2 s^-1) and smoothing-length factor alpha.
inline double eta_num_eq37(double D0, double Z, double alpha) {
  return alpha <= 0.55 ? D0 * Z * (0.47142 * alpha - 0.14629)
                       : D0 * Z * (0.18093 * alpha + 0.01347);
}

struct Options {
  double alpha = 0.5;                     // h_ij = alpha (D_i + D_j), eq. (12)
  double zeta = 0.0;                      // fraction of the numerical viscosity removed, eq. (26)
  double eta_num = -1.0;                  // Pa s; < 0: eq. (37) per particle
  double cfl = 0.3;                       // dt = cfl min D_i / (c0_i + |U_i|)
  double skin = 1.1;                      // search radius / largest pair support
  std::array<double, 3> g{0.0, 0.0, 0.0}; // body force per unit mass, m/s^2 (first D components)
  std::string kernel = "wendland_c2";     // the unit-h kernel K(1) scaled per pair
  std::string eta_num_text = "eq37";      // parameter eta_num as given ("eq37" or Pa s): eta_num
};

// A slip wall (core/domain.hpp): the plane x_axis = position, fluid on the side `side`.
using sph::SlipWall;

// Indices of the scheme's extra per-particle fields.
struct Fields {
  int rho0 = -1, c0 = -1, eta = -1, e = -1, src = -1;
  int zeta_factor = -1; // optional per-particle factor on zeta (-1: none, zeta for every particle)
  int g_factor = -1;    // optional per-particle factor on the body force (-1: none, g for all)
  template <int D>
  static Fields add_to(Particles<D>& p) {
    Fields f;
    f.rho0 = p.add_scalar("rho0");
    f.c0 = p.add_scalar("c0");
    f.eta = p.add_scalar("eta");
    f.e = p.add_scalar("e");     // specific internal energy, J/kg
    f.src = p.add_scalar("src"); // Wall: id of the mirrored particle; -1 otherwise
    return f;
  }
  // The fields of particles a case set up: the material fields rho0, c0 and eta by name (they must
  // exist), e and src found or added.
  template <int D>
  static Fields find_in(Particles<D>& p) {
    Fields f;
    auto need = [&](const char* name) {
      const int k = p.find_scalar(name);
      if (k < 0)
        throw std::invalid_argument(std::string("contact: the particles have no field '") + name +
                                    "' (per-particle material: rho0, c0, eta)");
      return k;
    };
    auto find_or_add = [&](const char* name) {
      const int k = p.find_scalar(name);
      return k >= 0 ? k : p.add_scalar(name);
    };
    f.rho0 = need("rho0"), f.c0 = need("c0"), f.eta = need("eta");
    f.e = find_or_add("e"), f.src = find_or_add("src");
    f.zeta_factor = p.find_scalar("zeta_factor");
    f.g_factor = p.find_scalar("g_factor");
    return f;
  }
};

// Per-particle quantities of the current stage (scratch, in the order of the last search).
template <int D>
struct Work {
  std::vector<Vec<D>> disp;           // r - r(search)
  std::vector<double> size, Z;        // D_i (11), rho_i c0_i
  std::vector<ViscousSide> phys, num; // eta_i and zeta eta_num_i
  std::vector<Vec<D>> dvdt;           // eq. (35)
  std::vector<Vec<D>> dvdt_solid;     // the part of (35) from pairs with solid particles
  std::vector<double> depsdt, dEdt;   // eqs. (33), (36)
  std::vector<char> solid;            // 1: a no-slip solid particle at rest (Wall, src < 0)
};

// Phase struct of the pair loop: eqs. (8)-(9), (27)-(36) for one particle i.
template <int D, class K>
struct ContactRates {
  const Particles<D>& p;
  Work<D>& w;
  const K& unit; // kernel of h = 1
  double alpha;
  Vec<D> g;               // body force per unit mass
  const double* g_factor; // per-particle factor on g, or nullptr (1 for every particle)
  Vec<D> g_of(std::size_t i) const { return g_factor ? Vec<D>(g_factor[i] * g) : g; }

  struct Acc {
    Vec<D> dv = Vec<D>::Zero();
    Vec<D> dv_solid = Vec<D>::Zero();
    double deps = 0.0, dE = 0.0;
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t i, const Pair<D>& q, Acc& a) const {
    const std::uint32_t j = q.j;
    const Vec<D> rij = q.r_ij + (w.disp[i] - w.disp[j]);
    const double r = rij.norm();
    const double h = alpha * (w.size[i] + w.size[j]);
    const double qh = r / h;
    if (qh >= K::support_factor || r <= 0.0)
      return;
    double hp = h; // h^(D+1)
    for (int k = 0; k < D; ++k)
      hp *= h;
    const double s = -unit.dW(qh) / hp; // e . grad_i W_ij
    const Vec<D> e = rij * (-1.0 / r);
    const Vec<D>& vi = p.v[i];
    const bool solid = w.solid[j];
    // A solid neighbour takes the no-slip wall state seen from i (see the file comment).
    const Vec<D> vj = solid ? Vec<D>(-vi) : p.v[j];
    const double Pj = solid ? p.p[i] - p.rho[i] * g_of(i).dot(rij) : p.p[j];
    const std::uint32_t js = solid ? static_cast<std::uint32_t>(i) : j;
    const double Zi = w.Z[i], Zj = w.Z[js];
    const RiemannSolution rs = acoustic_riemann(p.p[i], vi.dot(e), Zi, Pj, vj.dot(e), Zj);
    const double eta_c =
        contact_viscosity(w.phys[i], w.phys[js]) - contact_viscosity(w.num[i], w.num[js]);
    const Vec<D> dU = vj - vi;
    const Vec<D> tau = (eta_c / r) * (dU + (dU.dot(e) / 3.0) * e);
    const Vec<D> F = rs.P * e - tau;
    const double wp = contact_weight(w.phys[i], w.phys[js], Zi, Zj);
    const double wn = contact_weight(w.num[i], w.num[js], Zi, Zj);
    const Vec<D> Up = wp * vi + (1.0 - wp) * vj;
    const Vec<D> Un = wn * vi + (1.0 - wn) * vj;
    const Vec<D> Uc = rs.U * e + (Up - Up.dot(e) * e) - (Un - Up);
    const double c = 2.0 * p.m[j] / p.rho[j] * s;
    a.dv -= c * F;
    if (solid)
      a.dv_solid -= c * F;
    a.deps -= c * (vi - Uc).dot(e);
    a.dE -= c * F.dot(Uc);
  }
  void finish(std::size_t i, const Acc& a) {
    const Vec<D> gi = g_of(i);
    w.dvdt[i] = a.dv / p.rho[i] + gi;
    w.dvdt_solid[i] = a.dv_solid / p.rho[i];
    w.depsdt[i] = a.deps;
    w.dEdt[i] = a.dE / p.rho[i] + gi.dot(p.v[i]);
  }
};

// Search radius for largest particle size Dmax: skin alpha 2 Dmax support_factor.
template <class K>
double search_radius(const Options& o, double Dmax) {
  return o.skin * o.alpha * 2.0 * Dmax * K::support_factor;
}

template <int D, class K>
class Scheme {
public:
  Scheme(Particles<D>& p, const Fields& f, const Domain<D>& box, const Options& o,
         std::vector<SlipWall> walls = {})
      : p_(p), f_(f), box_(box), o_(o), walls_(std::move(walls)), unit_(1.0) {}

  // The step: an ordered list of named stages, each a member run with the step size dt.
  struct Stage {
    const char* name;
    void (Scheme::*run)(double dt);
  };
  static const std::vector<Stage>& stages() {
    static const std::vector<Stage> s{
        {"neighbours", &Scheme::neighbours}, {"eos", &Scheme::eos},
        {"rates", &Scheme::rates},           {"predict", &Scheme::predict},
        {"ghosts", &Scheme::ghosts},         {"eos", &Scheme::eos},
        {"rates", &Scheme::rates},           {"correct", &Scheme::correct},
        {"ghosts", &Scheme::ghosts}};
    return s;
  }
  static std::vector<std::string> stage_names() {
    std::vector<std::string> n;
    for (const auto& st : stages())
      n.emplace_back(st.name);
    return n;
  }

  // Creates the mirror particles of the slip walls (call once, after the fluid is set up).
  void init() {
    const double R = search_radius<K>(o_, max_size());
    const std::size_t n = p_.size();
    for (const auto& wall : walls_)
      for (std::size_t i = 0; i < n; ++i) {
        if (p_.kind[i] != Kind::Fluid)
          continue;
        const double d = (p_.r[i][wall.axis] - wall.position) * wall.side;
        if (d < 0.0 || d >= R)
          continue;
        Vec<D> x = p_.r[i];
        x[wall.axis] = 2.0 * wall.position - x[wall.axis];
        const std::size_t g = p_.add(x, p_.m[i], p_.rho[i], Kind::Wall);
        p_.scalar(f_.src)[g] = static_cast<double>(p_.id[i]);
        ghost_axis_.push_back(wall.axis), ghost_pos_.push_back(wall.position);
      }
    for (std::size_t i = 0; i < n; ++i)
      p_.scalar(f_.src)[i] = -1.0;
    // Ghost k (in creation order) has id n + k; its wall is ghost_axis_[k], ghost_pos_[k].
    first_ghost_id_ = n;
    index_.resize(p_.size());
    for (std::size_t i = 0; i < p_.size(); ++i)
      index_[p_.id[i]] = static_cast<std::uint32_t>(i);
    ghosts();
  }

  std::size_t num_ghosts() const { return ghost_axis_.size(); }

  // The body force per unit mass from the next rate evaluation on (Options::g).
  void set_body_force(const Vec<D>& g) {
    for (int k = 0; k < D; ++k)
      o_.g[k] = g[k];
  }
  const Options& options() const { return o_; }

  // Largest stable step: acoustic cfl D / (c0 + |U|) and viscous 0.125 D^2 rho / eta.
  double stable_dt() const {
    double dt = std::numeric_limits<double>::infinity();
    const auto& c0 = p_.scalar(f_.c0);
    const auto& eta = p_.scalar(f_.eta);
    for (std::size_t i = 0; i < p_.size(); ++i) {
      if (p_.kind[i] != Kind::Fluid)
        continue;
      const double Di = size(i);
      dt = std::min(dt, o_.cfl * Di / (c0[i] + p_.v[i].norm()));
      const double visc = eta[i] + zeta(i) * eta_num(i, Di);
      if (visc > 0.0)
        dt = std::min(dt, 0.125 * Di * Di * p_.rho[i] / visc);
    }
    return dt;
  }

  // One step of size dt through the stage list.
  void step(double dt) {
    for (const auto& st : stages())
      (this->*st.run)(dt);
  }

  // The correction factor of particle i: zeta, times its zeta_factor if the particles carry one.
  double zeta(std::size_t i) const {
    return f_.zeta_factor >= 0 ? o_.zeta * p_.scalar(f_.zeta_factor)[i] : o_.zeta;
  }
  // Numerical viscosity of particle i before the factor zeta: given, or eq. (37).
  double eta_num(std::size_t i, double Di) const {
    if (o_.eta_num >= 0.0)
      return o_.eta_num;
    return eta_num_eq37(Di, p_.scalar(f_.rho0)[i] * p_.scalar(f_.c0)[i], o_.alpha);
  }
  double size(std::size_t i) const { return std::pow(p_.m[i] / p_.rho[i], 1.0 / D); }

  // Force the solid particles exert on the fluid, sum_i m_i (dU_i/dt from solid pairs), from the
  // last rate evaluation (the midpoint of the last step). Minus this is the drag on the solids.
  Vec<D> solid_force() const {
    Vec<D> F = Vec<D>::Zero();
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (fluid(i))
        F += p_.m[i] * w_.dvdt_solid[i];
    return F;
  }
  std::size_t num_solids() const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < p_.size(); ++i)
      n += p_.kind[i] == Kind::Wall && p_.scalar(f_.src)[i] < 0.0;
    return n;
  }

  const NeighborList<D>& neighbors() const { return nl_; }
  const Work<D>& work() const { return w_; }
  std::size_t searches() const { return searches_; }

  // What the scheme carries across steps besides the particle fields (for checkpoints): the
  // search count and the cell list's radius (it is re-created only when particles grow, so a
  // resumed run must sort with the same cells). Restore after init() and the particles; every
  // step starts from the particles alone.
  std::vector<double> carried_state() const {
    return {static_cast<double>(searches_), cells_ ? cells_->support() : 0.0};
  }
  void restore_carried_state(const std::vector<double>& c) {
    io::expect_state_size(c, 2, "contact: checkpoint state");
    searches_ = static_cast<std::size_t>(c[0]);
    cells_ = c[1] > 0.0 ? std::make_unique<CellList<D>>(box_, c[1]) : nullptr;
  }

private:
  Particles<D>& p_;
  Fields f_;
  Domain<D> box_;
  Options o_;
  std::vector<SlipWall> walls_;
  K unit_;
  std::unique_ptr<CellList<D>> cells_;
  NeighborList<D> nl_;
  Work<D> w_;
  std::vector<Vec<D>> r0_, v0_;
  std::vector<double> rho0n_, E0_;
  std::vector<std::uint32_t> index_; // id -> current index
  std::vector<int> ghost_axis_;
  std::vector<double> ghost_pos_;
  std::size_t first_ghost_id_ = 0;
  std::size_t searches_ = 0;

  struct NoKernel { // the neighbour list's cached W, dW are unused (h varies per pair)
    double W(double) const { return 0.0; }
    double dW(double) const { return 0.0; }
  };

  double max_size() const {
    double m = 0.0;
    for (std::size_t i = 0; i < p_.size(); ++i)
      m = std::max(m, size(i));
    return m;
  }

  bool fluid(std::size_t i) const { return p_.kind[i] == Kind::Fluid; }

  void predict(double dt) { advance(0.5 * dt, false); }
  void correct(double dt) { advance(dt, true); }

  // Cell list (re-created when particles grew past its radius), sort, neighbour list; saves the
  // state at the start of the step.
  void neighbours(double = 0.0) {
    const double R = search_radius<K>(o_, max_size());
    if (!cells_ || cells_->support() < R / o_.skin * 1.0000001)
      cells_ = std::make_unique<CellList<D>>(box_, R);
    cells_->build(p_);
    nl_.build(*cells_, p_.r, NoKernel{});
    ++searches_;
    const std::size_t N = p_.size();
    index_.resize(N);
    for (std::size_t i = 0; i < N; ++i)
      index_[p_.id[i]] = static_cast<std::uint32_t>(i);
    r0_ = p_.r, v0_ = p_.v, rho0n_ = p_.rho;
    E0_.resize(N);
    const auto& e = p_.scalar(f_.e);
    for (std::size_t i = 0; i < N; ++i)
      E0_[i] = e[i] + 0.5 * p_.v[i].squaredNorm();
    w_.disp.assign(N, Vec<D>::Zero());
    w_.size.resize(N), w_.Z.resize(N), w_.phys.resize(N), w_.num.resize(N);
    w_.dvdt.resize(N), w_.depsdt.resize(N), w_.dEdt.resize(N);
    w_.dvdt_solid.assign(N, Vec<D>::Zero());
    w_.solid.resize(N);
    const auto& src = p_.scalar(f_.src);
    for (std::size_t i = 0; i < N; ++i)
      w_.solid[i] = p_.kind[i] == Kind::Wall && src[i] < 0.0;
  }

  // Equation of state (4) and the per-particle factors of the pair terms.
  void eos(double = 0.0) {
    const auto& rho0 = p_.scalar(f_.rho0);
    const auto& c0 = p_.scalar(f_.c0);
    const auto& eta = p_.scalar(f_.eta);
    const std::size_t N = p_.size();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < N; ++i) {
      p_.p[i] = c0[i] * c0[i] * (p_.rho[i] - rho0[i]);
      p_.V[i] = p_.m[i] / p_.rho[i];
      const double Di = size(i);
      w_.size[i] = Di;
      w_.Z[i] = p_.rho[i] * c0[i];
      w_.phys[i] = viscous_side(eta[i], p_.rho[i]);
      w_.num[i] = viscous_side(zeta(i) * eta_num(i, Di), p_.rho[i]);
    }
  }

  void rates(double = 0.0) {
    Vec<D> g;
    for (int k = 0; k < D; ++k)
      g[k] = o_.g[k];
    const double* gf = f_.g_factor >= 0 ? p_.scalar(f_.g_factor).data() : nullptr;
    ContactRates<D, K> op{p_, w_, unit_, o_.alpha, g, gf};
    interact(nl_, op, [this](std::size_t i) { return fluid(i); });
  }

  // Fluid particles from the start-of-step state by tau with the current rates (predict: half step,
  // drift with U^n; correct: full step, drift with the midpoint velocity, energy update).
  void advance(double tau, bool final) {
    auto& e = p_.scalar(f_.e);
    const std::size_t N = p_.size();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < N; ++i) {
      if (!fluid(i))
        continue;
      const Vec<D> vdrift = p_.v[i]; // U^n in predict, U^(n+1/2) in correct
      p_.v[i] = v0_[i] + tau * w_.dvdt[i];
      p_.r[i] = r0_[i] + tau * vdrift;
      p_.rho[i] = rho0n_[i] * std::exp(-tau * w_.depsdt[i]);
      if (final)
        e[i] = E0_[i] + tau * w_.dEdt[i] - 0.5 * p_.v[i].squaredNorm();
      w_.disp[i] = p_.r[i] - r0_[i];
    }
  }

  // Mirror particles copy their source's state, reflected across their wall.
  void ghosts(double = 0.0) {
    const std::size_t N = p_.size();
    const auto& src = p_.scalar(f_.src);
    for (std::size_t g = 0; g < N; ++g) {
      if (p_.kind[g] != Kind::Wall || src[g] < 0.0)
        continue;
      const std::size_t k = static_cast<std::size_t>(p_.id[g]) - first_ghost_id_;
      const std::size_t i = index_[static_cast<std::size_t>(src[g])];
      const int a = ghost_axis_[k];
      p_.r[g] = p_.r[i];
      p_.r[g][a] = 2.0 * ghost_pos_[k] - p_.r[i][a];
      p_.v[g] = p_.v[i];
      p_.v[g][a] = -p_.v[i][a];
      p_.rho[g] = p_.rho[i], p_.p[g] = p_.p[i], p_.m[g] = p_.m[i];
      for (int fi : {f_.rho0, f_.c0, f_.eta, f_.e, f_.zeta_factor, f_.g_factor})
        if (fi >= 0)
          p_.scalar(fi)[g] = p_.scalar(fi)[i];
      if (!r0_.empty())
        w_.disp[g] = p_.r[g] - r0_[g];
    }
  }
};

} // namespace sph::contact
