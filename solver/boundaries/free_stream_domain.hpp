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
#pragma once

#include "boundaries/open_boundary.hpp"
#include "io/checkpoint.hpp"

#include <memory>
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
  };

  explicit FreeStreamDomain(Config c)
      : c_(std::move(c)), emitter_(emitter_config(c_)), disposer_(disposer_config(c_)) {}

  double length() const { return c_.n[0] * c_.dx; }
  const Emitter<D>& emitter() const { return emitter_; }
  const Disposer<D>& disposer() const { return disposer_; }
  const FreeStream<D>& free_stream() const { return *fs_; }

  // The fluid lattice (where inside(r)) with u_in(r, 0), and the inlet buffer.
  template <class Inside>
  void fill(Particles<D>& p, Inside inside) {
    zone_field(p);
    const double m = c_.rho0 * std::pow(c_.dx, D);
    std::array<int, D> lo{};
    for_each_lattice_point<D>(lo, c_.n, c_.dx, [&](const Vec<D>& x, const std::array<int, D>&) {
      if (!inside(x))
        return;
      const std::size_t k = p.add(x, m, c_.rho0);
      p.v[k] = c_.u_in(x, 0.0);
    });
    next_id_ = static_cast<std::int64_t>(p.size());
    emitter_.fill(p, 0.0, next_id_);
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
    if (c_.extrapolate_inlet_pressure) {
      const int zone = emitter_.config().zone;
      f.buffer_pressure = [zone](Particles<D>& q, const NeighborList<D>& nl) {
        const int zk = zone_field(q);
        const auto& z = q.scalar(zk);
        auto mine = [&](std::size_t i) { return q.kind[i] == Kind::Buffer && z[i] == zone; };
        BufferPressure<D, decltype(mine)> op{q.kind, q.p, mine, 0.0};
        interact(nl, op, mine);
      };
    }
  }

  // Before a step (t_mid: the time at which the inlet velocity holds over it): disposer, then
  // emitter. True when particles were added or removed.
  bool before_step(Particles<D>& p, double t_mid) {
    const bool removed = disposer_.update(p);
    const bool added = emitter_.update(p, t_mid, next_id_) > 0;
    return removed || added;
  }

  double mass_in() const { return emitter_.mass_in(); }
  double mass_out() const { return disposer_.mass_out(); }
  double mass_lost() const { return disposer_.mass_lost(); }

  std::vector<std::string> state_names(const std::string& prefix) const {
    return {prefix + "/open_boundary"};
  }
  void save_state(StateArrays& out, const std::string& prefix) const {
    out[prefix + "/open_boundary"] = {mass_in(), mass_out(), mass_lost(),
                                      static_cast<double>(next_id_)};
  }
  void load_state(const StateArrays& in, const std::string& prefix) {
    const auto& a = in.at(prefix + "/open_boundary");
    io::expect_state_size(a, 4, "checkpoint array " + prefix + "/open_boundary");
    emitter_.set_mass_in(a[0]);
    disposer_.set_masses(a[1], a[2]);
    next_id_ = static_cast<std::int64_t>(a[3]);
  }

private:
  Config c_;
  Emitter<D> emitter_;
  Disposer<D> disposer_;
  std::unique_ptr<FreeStream<D>> fs_;
  std::int64_t next_id_ = 0;

  static typename Emitter<D>::Config emitter_config(const Config& c) {
    typename Emitter<D>::Config e;
    e.x_in = 0.0, e.layers = c.layers, e.dx = c.dx, e.hi = c.n, e.rho0 = c.rho0;
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
