// A rectangular free-stream domain assembled from the open-boundary pieces
// (boundaries/open_boundary.hpp): fluid in [0, L] x [0, H] (x [0, W] in 3D) on the cell-centred
// lattice of spacing dx, an emitter upstream of x = 0, a disposer downstream of x = L, and the
// Lagrangian free-stream boundary on the lateral sides (Zhang et al. 2023), the stream being
// u_in(r, t) both at the inlet and in the far field. SPHinXsys' test_2d_free_stream_around_cylinder
// is the same arrangement (emitter, disposer, free surfaces with the free-stream correction).
//
// Used by cases/free_stream_box.cpp (the empty domain) and cases/cylinder_free_stream.cpp
// (boundary = "free_stream"). The case calls, in this order:
//   fill(p, inside)        in build(): the fluid lattice where inside(r) and the inlet buffer
//   attach(p, flow)        in build(): a non-periodic box and the free-stream hooks
//   before_step(p, t_mid)  before each step; when it returns true the case calls
//                          FlowScheme::particles_changed()
//   save_state/load_state  its counters (masses in, out, lost; the next particle id)
// Mass balance: mass_in() (emitted), mass_out() (crossed x = L), mass_lost() (deleted beyond the
// lateral keep margin), cumulative.
// Two resolution levels (band_rows > 0; issue 19, section 2): the fine band |y - H/2| < band_rows
// dx along the whole domain holds particles of spacing dx / 2 (2^D per lattice cell, mass
// rho0 (dx/2)^D), the rest spacing dx. Each level is emitted on its own rows (an emitted particle
// has the level of where it is created: one emitter for the band, one each side of it), and
// particles that cross the band's edges are split or merged (boundaries/refinement.hpp, hysteresis
// one coarse spacing), which also writes h_i = h (m_i / (rho0 dx^D))^(1/D) into the field "h"
// that attach() hands to the flow. The lateral free surfaces are coarse: the free-stream rule uses
// h.
#pragma once

#include "boundaries/open_boundary.hpp"
#include "boundaries/refinement.hpp"
#include "io/checkpoint.hpp"

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>

namespace sph::open_boundary {

template <int D>
class FreeStreamDomain {
public:
  struct Config {
    std::array<int, D> n{}; // lattice cells per axis: L = n[0] dx, H = n[1] dx, ...
    double dx = 0.1;
    double rho0 = 1.0;
    double h = 0.13;           // smoothing length (free-stream surface rule)
    int layers = 4;            // buffer columns of the emitter and of the disposer
    double lateral_margin = 1; // fluid beyond this distance outside the lateral sides is deleted
    VelocityField<D> u_in;     // inflow and free stream
    bool extrapolate_inlet_pressure = false;
    int band_rows = 0; // half-width of the fine band in rows of dx (0: one level)
  };

  explicit FreeStreamDomain(Config c) : c_(std::move(c)), disposer_(disposer_config(c_)) {
    if (c_.band_rows <= 0) {
      emitters_.emplace_back(emitter_config(c_, c_.dx, 0, c_.n[1], 1));
      return;
    }
    const int n1 = c_.n[1], lo = n1 / 2 - c_.band_rows, hi = (n1 + 1) / 2 + c_.band_rows;
    if (n1 % 2 != 0 || lo < 1 || hi > n1 - 1)
      throw std::invalid_argument("FreeStreamDomain: the fine band needs an even number of rows "
                                  "and a coarse row on each side of it");
    emitters_.emplace_back(emitter_config(c_, c_.dx, 0, lo, 1));
    emitters_.emplace_back(emitter_config(c_, 0.5 * c_.dx, 2 * lo, 2 * hi, 3));
    emitters_.emplace_back(emitter_config(c_, c_.dx, hi, n1, 4));
  }

  double length() const { return c_.n[0] * c_.dx; }
  const refinement::TwoLevels<D>* levels() const { return levels_.get(); }
  const Disposer<D>& disposer() const { return disposer_; }
  const FreeStream<D>& free_stream() const { return *fs_; }

  // The fluid lattice (where inside(r)) with u_in(r, 0), and the inlet buffer.
  template <class Inside>
  void fill(Particles<D>& p, Inside inside) {
    zone_field(p);
    const double m = c_.rho0 * std::pow(c_.dx, D);
    auto add = [&](const Vec<D>& x, double mass) {
      if (!inside(x))
        return;
      const std::size_t k = p.add(x, mass, c_.rho0);
      p.v[k] = c_.u_in(x, 0.0);
    };
    std::array<int, D> lo{};
    for_each_lattice_point<D>(lo, c_.n, c_.dx, [&](const Vec<D>& x, const std::array<int, D>&) {
      if (!(in_band(x[1]) > 0.0))
        return add(x, m);
      for (int s = 0; s < (1 << D); ++s) // the cell's 2^D fine points
        add(refinement::fine_point<D>(x, c_.dx, s), m / (1 << D));
    });
    next_id_ = static_cast<std::int64_t>(p.size());
    for (const auto& e : emitters_)
      e.fill(p, 0.0, next_id_);
    if (c_.band_rows > 0) {
      typename refinement::TwoLevels<D>::Config rc;
      rc.dx_fine = 0.5 * c_.dx, rc.rho0 = c_.rho0, rc.h_over_dx = c_.h / c_.dx;
      rc.depth = [this](const Vec<D>& x) { return in_band(x[1]); };
      rc.margin = c_.dx;
      levels_ = std::make_unique<refinement::TwoLevels<D>>(p, rc);
      levels_->set_h(p);
    }
  }

  // A non-periodic box, the free-stream hooks and (optionally) the inlet pressure extrapolation.
  void attach(Particles<D>& p, Flow<D>& f) {
    typename FreeStream<D>::Config fc;
    fc.rho0 = c_.rho0, fc.h = c_.h, fc.axis = 0, fc.u_inf = c_.u_in;
    fs_ = std::make_unique<FreeStream<D>>(p, fc);
    fs_->attach(f);
    f.box.lo = Vec<D>::Zero();
    for (int a = 0; a < D; ++a)
      f.box.hi[a] = c_.n[a] * c_.dx, f.box.periodic[a] = false;
    if (levels_)
      f.h = levels_->h_field();
    if (c_.extrapolate_inlet_pressure) {
      std::vector<int> zones;
      for (const auto& e : emitters_)
        zones.push_back(e.config().zone);
      f.buffer_pressure = [zones](Particles<D>& q, const NeighborList<D>& nl) {
        const int zk = zone_field(q);
        const auto& z = q.scalar(zk);
        auto mine = [&](std::size_t i) {
          return q.kind[i] == Kind::Buffer &&
                 std::find(zones.begin(), zones.end(), static_cast<int>(z[i])) != zones.end();
        };
        BufferPressure<D, decltype(mine)> op{q.kind, q.p, mine, 0.0};
        interact(nl, op, mine);
      };
    }
  }

  // Before a step (t_mid: the time at which the inlet velocity holds over it): disposer, then
  // emitters, then the levels' splits and merges. True when particles were added or removed.
  bool before_step(Particles<D>& p, double t_mid) {
    bool changed = disposer_.update(p);
    for (auto& e : emitters_)
      changed |= e.update(p, t_mid, next_id_) > 0;
    if (levels_) // also gives the emitted particles their h
      changed |= levels_->update(p, next_id_) > 0;
    return changed;
  }

  double mass_in() const {
    double m = 0.0;
    for (const auto& e : emitters_)
      m += e.mass_in();
    return m;
  }
  double mass_out() const { return disposer_.mass_out(); }
  double mass_lost() const { return disposer_.mass_lost(); }

  std::vector<std::string> state_names(const std::string& prefix) const {
    if (levels_)
      return {prefix + "/open_boundary", prefix + "/refinement"};
    return {prefix + "/open_boundary"};
  }
  void save_state(StateArrays& out, const std::string& prefix) const {
    out[prefix + "/open_boundary"] = {mass_in(), mass_out(), mass_lost(),
                                      static_cast<double>(next_id_)};
    if (levels_)
      out[prefix + "/refinement"] = {static_cast<double>(levels_->splits()),
                                     static_cast<double>(levels_->merges())};
  }
  void load_state(const StateArrays& in, const std::string& prefix) {
    const auto& a = in.at(prefix + "/open_boundary");
    io::expect_state_size(a, 4, "checkpoint array " + prefix + "/open_boundary");
    for (auto& e : emitters_) // the total is kept by the first emitter
      e.set_mass_in(&e == &emitters_.front() ? a[0] : 0.0);
    disposer_.set_masses(a[1], a[2]);
    next_id_ = static_cast<std::int64_t>(a[3]);
    if (levels_) {
      const auto& r = in.at(prefix + "/refinement");
      io::expect_state_size(r, 2, "checkpoint array " + prefix + "/refinement");
      levels_->set_counts(static_cast<std::size_t>(r[0]), static_cast<std::size_t>(r[1]));
    }
  }

private:
  Config c_;
  std::vector<Emitter<D>> emitters_;
  Disposer<D> disposer_;
  std::unique_ptr<refinement::TwoLevels<D>> levels_;
  std::unique_ptr<FreeStream<D>> fs_;
  std::int64_t next_id_ = 0;

  // Signed distance into the fine band (negative outside; -1 without a band).
  double in_band(double y) const {
    if (c_.band_rows <= 0)
      return -1.0;
    return c_.band_rows * c_.dx - std::abs(y - 0.5 * c_.n[1] * c_.dx);
  }

  // The emitter of rows [lo, hi) (axis 1, in units of its spacing dx_e) of zone `zone`.
  static typename Emitter<D>::Config emitter_config(const Config& c, double dx_e, int lo, int hi,
                                                    int zone) {
    typename Emitter<D>::Config e;
    e.x_in = 0.0, e.layers = c.layers, e.dx = dx_e, e.rho0 = c.rho0, e.zone = zone;
    for (int a = 1; a < D; ++a)
      e.hi[a] = static_cast<int>(std::lround(c.n[a] * c.dx / dx_e));
    e.lo[1] = lo, e.hi[1] = hi;
    e.u_in = c.u_in, e.extrapolate_pressure = c.extrapolate_inlet_pressure;
    return e;
  }
  static typename Disposer<D>::Config disposer_config(const Config& c) {
    typename Disposer<D>::Config d;
    d.x_out = c.n[0] * c.dx, d.layers = c.layers, d.dx = c.dx;
    for (int a = 1; a < D; ++a)
      d.keep_lo[a] = -c.lateral_margin, d.keep_hi[a] = c.n[a] * c.dx + c.lateral_margin;
    return d;
  }
};

} // namespace sph::open_boundary
