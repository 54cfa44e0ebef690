// Open boundaries for particle schemes: an inflow emitter, an outflow disposer, the Shepard
// pressure extrapolation of buffer particles, and the Lagrangian free-stream boundary condition.
// Pieces any case uses (cases/free_stream_box.cpp, cases/cylinder_free_stream.cpp, and the ALSPH
// channel's buffer pressure, cases/cylinder_channel.cpp); nothing here knows a case.
//
// Why here (solver/boundaries/, DESIGN.md's layout): they are boundary treatments, written once and
// driven by the shared loop (cases/time_loop.hpp): the emitter and the disposer change the particle
// set between steps (a case's before_step, then FlowScheme::particles_changed), the buffer pressure
// and the free stream act inside a scheme's step through Flow's hooks (schemes/scheme.hpp).
//
// Geometry: the stream runs along +x (axis 0). A buffer is a slab of `layers` lattice columns of
// spacing dx; its particles are Kind::Buffer, tagged with their zone in the scalar field
// "buffer_zone" (0: not in a buffer). A scheme does not integrate buffer particles but lets them
// drift with their velocity (wcsph_tvf) and sees them as partners with their own v, p, V.
//
//   Emitter (inflow; Kolukisa et al. 2021's inlet buffer as cases/cylinder_channel.cpp had it, and
//   SPHinXsys' EmitterInflowInjection, src/shared/particle_dynamics/fluid_dynamics/
//   boundary_condition/fluid_boundary.cpp): the slab x in [x_in - layers dx, x_in) holds a lattice
//   moving with the prescribed velocity u_in(r, t); a buffer particle that crosses x_in becomes
//   fluid (keeping v, rho, p) and a new buffer particle enters layers dx upstream of it, on the
//   same row, so the emitted lattice has the spacing dx exactly. Buffer density rho0 (V = m/rho0);
//   pressure p_ref (SPHinXsys' EmitterInflowCondition: p(rho0)) or, with extrapolate_pressure, the
//   Shepard average of the fluid pressures around (BufferPressure below: a zero normal gradient,
//   what a channel driven by its inflow needs).
//   Disposer (outflow; cylinder_channel's outlet and SPHinXsys' DisposerOutflowDeletion): fluid
//   that crosses x_out becomes outlet buffer with its velocity and density frozen and the outlet
//   pressure p_out, drifts on and is deleted at x_out + layers dx; fluid that leaves the keep box
//   (e.g. far outside a free-stream boundary) is deleted and counted as lost.
//   FreeStream (Zhang, Zhang, Zhang & Hu 2023, "A Lagrangian free-stream boundary condition for
//   weakly compressible smoothed particle hydrodynamics", JCP 490, 112303, seed 002 ref. [32];
//   SPHinXsys: SpatialTemporalFreeSurfaceIndication (general_dynamics/surface_indication/
//   surface_indication.cpp), DensitySummationFreeStream (fluid_dynamics/density_summation.h,
//   NearFreeStream) and FreeStreamVelocityCorrection (fluid_boundary.h); FreeStreamCondition in
//   shared_ck/.../free_stream_boundary.hpp is the same velocity rule). The fluid's outer edge is a
//   free surface on which the stream is imposed weakly:
//     surface indicator  pos_div_i = -sum_j dW_ij V_j |r_ij| (D on a full support); particle i is
//                        on the surface (indicator 1) unless pos_div_i > 0.75 D and no fluid or
//                        buffer neighbour within h has pos_div_j < 0.75 D (two layers). Spatio-
//                        temporal filter: pos_div_i < 0.75 D counts only if i or a neighbour was on
//                        the surface the step before (else pos_div_i = 1.5 D), so an interior
//                        void cannot open a surface.
//     density            near the surface (i or a fluid/buffer neighbour indicated), the density
//                        reinitialisation keeps what the continuity equation gave where the
//                        summation's support is truncated:
//                          rho_i = rho_sum + (rho_i - rho_sum) rho0 / rho_i   if rho_sum < rho_i,
//                          rho_i = rho_sum                                   otherwise.
//     velocity           after every velocity update, on surface particles, the stream component
//                          u_i <- U + (u_i - U) min(rho_sum_i / rho0, 1),   U = u_inf(r_i, t),
//                        which pulls a particle whose support is half empty towards the free
//                        stream.
//   The transport-velocity shift skips surface particles (bulk particles only, as SPHinXsys).
#pragma once

#include "core/lattice.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "operators/interact.hpp"
#include "schemes/scheme.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

namespace sph::open_boundary {

// A prescribed velocity field u(r, t) (inflow profile, free stream).
template <int D>
using VelocityField = std::function<Vec<D>(const Vec<D>& r, double t)>;

// The scalar field tagging buffer particles with their zone (0: none); added on first use.
template <int D>
int zone_field(Particles<D>& p) {
  const int k = p.find_scalar("buffer_zone");
  return k >= 0 ? k : p.add_scalar("buffer_zone");
}

// Buffer pressure: particle i (a buffer particle) gets the Shepard average of its fluid
// neighbours' pressures sum_j W_ij p_j / sum_j W_ij when extrapolate(i), else p_ref (also when it
// has no fluid neighbour).
template <int D, class Extrapolate>
struct BufferPressure {
  const std::vector<Kind>& kind;
  std::vector<double>& p;
  Extrapolate extrapolate;
  double p_ref = 0.0;
  struct Acc {
    double num = 0.0, den = 0.0;
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t, const Pair<D>& q, Acc& a) const {
    if (kind[q.j] == Kind::Fluid)
      a.num += q.W * p[q.j], a.den += q.W;
  }
  void finish(std::size_t i, const Acc& a) {
    p[i] = (extrapolate(i) && a.den > 0.0) ? a.num / a.den : p_ref;
  }
};

// Buffer velocity: a buffer particle i (those interact() selects) gets the stream component
// (axis 0) of the Shepard average of its fluid neighbours' velocities, sum_j W_ij v_j,x /
// sum_j W_ij, when it has a fluid neighbour (else it keeps its own): a zero normal gradient of the
// outflow, for an outlet whose flow is not known in advance (a disposer buffer behind fluid that
// starts at rest). The transverse components are dropped and a backflow is cut to zero (u_x >= 0):
// buffer particles are not integrated, so one that followed a recirculation upstream would sweep
// through the fluid (the nozzle's first run diverged so at t = 0.14 s, its outlet inside the
// expansion's recirculation).
template <int D>
struct BufferVelocity {
  const std::vector<Kind>& kind;
  std::vector<Vec<D>>& v;
  struct Acc {
    double num = 0.0, den = 0.0;
  };
  Acc init(std::size_t) const { return {}; }
  void pair(std::size_t, const Pair<D>& q, Acc& a) const {
    if (kind[q.j] == Kind::Fluid)
      a.num += q.W * v[q.j][0], a.den += q.W;
  }
  void finish(std::size_t i, const Acc& a) {
    if (a.den > 0.0) {
      v[i] = Vec<D>::Zero();
      v[i][0] = std::max(a.num / a.den, 0.0);
    }
  }
};

// Inflow: the emitter buffer upstream of x_in (see the header).
template <int D>
class Emitter {
public:
  struct Config {
    double x_in = 0.0; // inlet face: fluid on x >= x_in
    int layers = 4;    // buffer columns (at least one kernel support deep)
    double dx = 0.1;   // lattice spacing
    // Rows: lattice indices of the transverse axes 1..D-1, points (k + 1/2) dx, k in [lo, hi).
    std::array<int, D> lo{}, hi{};
    // Or, when not empty, the rows: each row's transverse position (axis 0 ignored) and particle
    // volume (for a slice of thickness dx), a section that is not a lattice, e.g. the rings of a
    // round inlet (core/axisymmetric_duct.hpp). The lattice rows' volume is dx^D.
    struct Row {
      Vec<D> r;
      double V;
    };
    std::vector<Row> section;
    double rho0 = 1.0;
    VelocityField<D> u_in;
    bool extrapolate_pressure = false; // else p = p_ref
    double p_ref = 0.0;
    int zone = 1;
  };

  explicit Emitter(Config c) : c_(std::move(c)) {}
  const Config& config() const { return c_; }
  double length() const { return c_.layers * c_.dx; }
  double particle_mass() const { return c_.rho0 * std::pow(c_.dx, D); }
  bool in_zone(const Particles<D>& p, std::size_t i, int zone_k) const {
    return p.kind[i] == Kind::Buffer && p.scalar(zone_k)[i] == c_.zone;
  }

  // The initial buffer lattice at time t; next_id numbers new particles (Particles::id).
  void fill(Particles<D>& p, double t, std::int64_t& next_id) const {
    const int zk = zone_field(p);
    if (!c_.section.empty()) {
      for (int l = 0; l < c_.layers; ++l)
        for (const auto& row : c_.section) {
          Vec<D> x = row.r;
          x[0] = c_.x_in - (l + 0.5) * c_.dx;
          add(p, zk, x, c_.rho0 * row.V, t, next_id);
        }
      return;
    }
    std::array<int, D> lo = c_.lo, hi = c_.hi;
    lo[0] = 0, hi[0] = c_.layers;
    for_each_lattice_point<D>(lo, hi, c_.dx, [&](Vec<D> x, const std::array<int, D>&) {
      x[0] = c_.x_in - x[0];
      add(p, zk, x, particle_mass(), t, next_id);
    });
  }

  // Before a step at time t (t_mid: the time at which the buffer's velocity holds over the step):
  // buffer particles past x_in become fluid, each replaced upstream by one of its mass on its
  // row; then every buffer particle gets u_in(r, t_mid), rho0 and (without extrapolation) p_ref.
  // Returns the number emitted.
  std::size_t update(Particles<D>& p, double t_mid, std::int64_t& next_id) {
    const int zk = zone_field(p);
    const std::size_t n0 = p.size();
    std::size_t emitted = 0;
    for (std::size_t i = 0; i < n0; ++i) {
      if (!in_zone(p, i, zk) || p.r[i][0] < c_.x_in)
        continue;
      p.kind[i] = Kind::Fluid;
      p.scalar(zk)[i] = 0.0;
      Vec<D> x = p.r[i];
      x[0] -= length();
      mass_in_ += p.m[i];
      add(p, zk, x, p.m[i], t_mid, next_id);
      ++emitted;
    }
    for (std::size_t i = 0; i < p.size(); ++i)
      if (in_zone(p, i, zk)) {
        p.v[i] = c_.u_in(p.r[i], t_mid);
        p.rho[i] = c_.rho0, p.V[i] = p.m[i] / c_.rho0;
        if (!c_.extrapolate_pressure)
          p.p[i] = c_.p_ref;
      }
    return emitted;
  }

  // Mass turned into fluid so far (the inflow).
  double mass_in() const { return mass_in_; }
  void set_mass_in(double m) { mass_in_ = m; }

private:
  Config c_;
  double mass_in_ = 0.0;

  void add(Particles<D>& p, int zk, const Vec<D>& x, double m, double t,
           std::int64_t& next_id) const {
    const std::size_t k = p.add(x, m, c_.rho0, Kind::Buffer);
    p.v[k] = c_.u_in(x, t);
    p.p[k] = c_.p_ref;
    p.scalar(zk)[k] = c_.zone;
    p.id[k] = next_id++;
  }
};

// Outflow: the disposer buffer downstream of x_out (see the header).
template <int D>
class Disposer {
public:
  struct Config {
    double x_out = 1.0; // outlet face: fluid crossing it becomes buffer
    int layers = 4;     // buffer columns before deletion
    double dx = 0.1;
    double p_out = 0.0;                        // outlet buffer pressure
    Vec<D> keep_lo = Vec<D>::Constant(-1e300); // fluid outside [keep_lo, keep_hi] is deleted
    Vec<D> keep_hi = Vec<D>::Constant(1e300);  // (counted as lost)
    int zone = 2;
  };

  explicit Disposer(Config c) : c_(std::move(c)) {}
  const Config& config() const { return c_; }
  double length() const { return c_.layers * c_.dx; }

  // Before a step: deletes outlet buffer particles past x_out + layers dx and fluid outside the
  // keep box, turns fluid past x_out into outlet buffer. Returns whether particles were removed.
  bool update(Particles<D>& p) {
    const int zk = zone_field(p);
    keep_.assign(p.size(), 1);
    bool removed = false;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const bool mine = p.kind[i] == Kind::Buffer && p.scalar(zk)[i] == c_.zone;
      if (mine && p.r[i][0] >= c_.x_out + length()) {
        keep_[i] = 0, removed = true;
      } else if (p.kind[i] == Kind::Fluid) {
        bool outside = false;
        for (int a = 0; a < D; ++a)
          outside |= p.r[i][a] < c_.keep_lo[a] || p.r[i][a] > c_.keep_hi[a];
        if (outside) {
          keep_[i] = 0, removed = true, mass_lost_ += p.m[i];
        } else if (p.r[i][0] >= c_.x_out) {
          p.kind[i] = Kind::Buffer;
          p.scalar(zk)[i] = c_.zone;
          p.p[i] = c_.p_out;
          mass_out_ += p.m[i];
        }
      }
    }
    if (removed)
      p.keep_only(keep_);
    return removed;
  }

  double mass_out() const { return mass_out_; }   // fluid mass that crossed x_out so far
  double mass_lost() const { return mass_lost_; } // fluid mass deleted outside the keep box
  void set_masses(double out, double lost) { mass_out_ = out, mass_lost_ = lost; }

private:
  Config c_;
  std::vector<char> keep_;
  double mass_out_ = 0.0, mass_lost_ = 0.0;
};

// The Lagrangian free-stream boundary condition (Zhang et al. 2023; see the header).
template <int D>
class FreeStream {
public:
  struct Config {
    double rho0 = 1.0;
    double h = 0.13;             // smoothing length (the two-layer rule's distance)
    int axis = 0;                // stream direction: the velocity component corrected
    VelocityField<D> u_inf;      // the free stream U(r, t)
    double threshold = 0.75 * D; // pos_div below this: surface
  };

  // Adds the fields "surface_indicator" and "surface_indicator_prev" (1 for every particle at
  // the start, as SPHinXsys, so the first step uses the spatial rule alone).
  FreeStream(Particles<D>& p, Config c) : c_(std::move(c)) {
    ind_ = p.add_scalar("surface_indicator");
    prev_ = p.add_scalar("surface_indicator_prev", 1.0);
  }
  int indicator_field() const { return ind_; }

  // Wires the three hooks and the indicator field into a flow (schemes/scheme.hpp).
  void attach(Flow<D>& f) {
    f.before_density = [this](Particles<D>& p, const NeighborList<D>& nl) { indicate(p, nl); };
    f.after_density = [this](Particles<D>& p, const NeighborList<D>& nl) { density(p, nl); };
    f.after_kick = [this](Particles<D>& p, double t) { velocity(p, t); };
    f.surface_indicator = ind_;
  }

  // Position divergence, spatio-temporal filter, indicator (fluid and buffer particles); keeps the
  // densities before the summation.
  void indicate(Particles<D>& p, const NeighborList<D>& nl) {
    const std::size_t N = p.size();
    pos_div_.assign(N, 2.0 * c_.threshold);
    rho_prev_ = p.rho;
    auto open = [&](std::size_t i) {
      return p.kind[i] == Kind::Fluid || p.kind[i] == Kind::Buffer;
    };
    PositionDivergence div{p, p.scalar(prev_), c_.threshold, pos_div_};
    interact(nl, div, open);
    Indicator ind{p, pos_div_, c_.threshold, c_.h, p.scalar(ind_), p.scalar(prev_)};
    interact(nl, ind, open);
  }

  // The near-surface density rule after the summation (fluid particles); keeps rho_sum / rho0.
  void density(Particles<D>& p, const NeighborList<D>& nl) {
    ratio_.assign(p.size(), 1.0);
    NearSurfaceDensity op{p, p.scalar(ind_), rho_prev_, c_.rho0, ratio_};
    interact(nl, op, [&](std::size_t i) { return p.kind[i] == Kind::Fluid; });
  }

  // The free-stream velocity correction of surface particles at time t.
  void velocity(Particles<D>& p, double t) {
    const auto& ind = p.scalar(ind_);
    const int a = c_.axis;
    const std::size_t N = p.size();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < N; ++i) {
      if (p.kind[i] != Kind::Fluid || ind[i] == 0.0)
        continue;
      const double U = c_.u_inf(p.r[i], t)[a];
      p.v[i][a] = U + (p.v[i][a] - U) * std::min(ratio_[i], 1.0);
    }
  }

private:
  Config c_;
  int ind_ = -1, prev_ = -1;
  std::vector<double> pos_div_, rho_prev_, ratio_; // per step, in the step's particle order

  static bool open_kind(Kind k) {
    return k == Kind::Fluid || k == Kind::Buffer;
  }

  // pos_div_i = -sum_j dW_ij V_j |r_ij| over every partner (walls included, as SPHinXsys'
  // contact part); the spatio-temporal filter needs a fluid/buffer neighbour on the last surface.
  struct PositionDivergence {
    const Particles<D>& p;
    const std::vector<double>& prev;
    double thr;
    std::vector<double>& out;
    struct Acc {
      double d = 0.0;
      bool near_prev = false;
    };
    Acc init(std::size_t) const { return {}; }
    void pair(std::size_t, const Pair<D>& q, Acc& a) const {
      a.d -= q.dW * p.V[q.j] * q.r;
      a.near_prev |= open_kind(p.kind[q.j]) && prev[q.j] == 1.0;
    }
    void finish(std::size_t i, const Acc& a) {
      out[i] = (a.d < thr && prev[i] != 1.0 && !a.near_prev) ? 2.0 * thr : a.d;
    }
  };
  struct Indicator {
    const Particles<D>& p;
    const std::vector<double>& pos_div;
    double thr, h;
    std::vector<double>& ind;
    std::vector<double>& prev;
    struct Acc {
      bool very_near = false;
    };
    Acc init(std::size_t) const { return {}; }
    void pair(std::size_t, const Pair<D>& q, Acc& a) const {
      a.very_near |= open_kind(p.kind[q.j]) && q.r < h && pos_div[q.j] < thr;
    }
    void finish(std::size_t i, const Acc& a) {
      ind[i] = (pos_div[i] > thr && !a.very_near) ? 0.0 : 1.0;
      prev[i] = ind[i];
    }
  };
  struct NearSurfaceDensity {
    Particles<D>& p;
    const std::vector<double>& ind;
    const std::vector<double>& rho_prev;
    double rho0;
    std::vector<double>& ratio;
    struct Acc {
      bool near = false;
    };
    Acc init(std::size_t i) const { return {ind[i] != 0.0}; }
    void pair(std::size_t, const Pair<D>& q, Acc& a) const {
      a.near |= open_kind(p.kind[q.j]) && ind[q.j] != 0.0;
    }
    void finish(std::size_t i, const Acc& a) {
      const double rs = p.rho[i], rp = rho_prev[i];
      ratio[i] = rs / rho0;
      if (a.near && rs < rp) {
        p.rho[i] = rs + (rp - rs) * rho0 / rp;
        p.V[i] = p.m[i] / p.rho[i];
      }
    }
  };
};

} // namespace sph::open_boundary
