// Particle storage as a structure of arrays, dimension-generic.
//
// Common fields are named members (positions r, velocities v, mass m, density rho, pressure p,
// volume V, kind and original index id). Schemes add their own per-particle fields with
// add_scalar / add_vector and keep the returned index. reorder() gathers every field through a
// permutation (used by the cell-linked list after its counting sort); it reuses scratch buffers so
// that no allocation happens in the time loop after the first call.
#pragma once

#include "core/vec.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace sph {

// What a particle is; boundary treatments and diagnostics select on it. Solid: the material of an
// elastic body, integrated by a solid scheme (schemes/solid/); fluid schemes do not take it yet.
enum class Kind : std::uint8_t { Fluid = 0, Wall = 1, Body = 2, Buffer = 3, Solid = 4 };

template <int D>
class Particles {
public:
  static constexpr int dim = D;

  std::vector<Vec<D>> r;        // position
  std::vector<Vec<D>> v;        // velocity
  std::vector<double> m;        // mass
  std::vector<double> rho;      // density
  std::vector<double> p;        // pressure
  std::vector<double> V;        // volume m/rho or 1/sum_j W_ij, as the scheme defines it
  std::vector<Kind> kind;       // fluid, wall, body, ...
  std::vector<std::int64_t> id; // index at creation; survives reordering

  std::size_t size() const { return r.size(); }

  // Appends one particle with zero velocity and pressure; returns its index.
  std::size_t add(const Vec<D>& position, double mass, double density, Kind k = Kind::Fluid) {
    r.push_back(position);
    v.push_back(Vec<D>::Zero());
    m.push_back(mass);
    rho.push_back(density);
    p.push_back(0.0);
    V.push_back(density > 0 ? mass / density : 0.0);
    kind.push_back(k);
    id.push_back(static_cast<std::int64_t>(id.size()));
    for (auto& f : scalars_)
      f.data.push_back(0.0);
    for (auto& f : vectors_)
      f.data.push_back(Vec<D>::Zero());
    return r.size() - 1;
  }

  // Appends a copy of particle i, every field and extra field included; returns its index
  // (splitting a particle, boundaries/refinement.hpp).
  std::size_t append_copy(std::size_t i) {
    r.push_back(Vec<D>(r[i])), v.push_back(Vec<D>(v[i])), m.push_back(double(m[i]));
    rho.push_back(double(rho[i])), p.push_back(double(p[i])), V.push_back(double(V[i]));
    kind.push_back(Kind(kind[i])), id.push_back(std::int64_t(id[i]));
    for (auto& f : scalars_)
      f.data.push_back(double(f.data[i]));
    for (auto& f : vectors_)
      f.data.push_back(Vec<D>(f.data[i]));
    return r.size() - 1;
  }

  // Every field, extras included, to n particles (new ones zero-initialised, Kind::Fluid; for
  // restoring a checkpoint of a case that adds and removes particles).
  void resize(std::size_t n) {
    r.resize(n, Vec<D>::Zero()), v.resize(n, Vec<D>::Zero()), m.resize(n, 0.0);
    rho.resize(n, 0.0), p.resize(n, 0.0), V.resize(n, 0.0), kind.resize(n, Kind::Fluid);
    id.resize(n, 0);
    for (auto& f : scalars_)
      f.data.resize(n, 0.0);
    for (auto& f : vectors_)
      f.data.resize(n, Vec<D>::Zero());
  }

  void reserve(std::size_t n) {
    r.reserve(n), v.reserve(n), m.reserve(n), rho.reserve(n), p.reserve(n), V.reserve(n);
    kind.reserve(n), id.reserve(n);
  }

  // Extra named fields, sized like the particle set and reordered with it.
  int add_scalar(const std::string& name, double value = 0.0) {
    scalars_.push_back({name, std::vector<double>(size(), value)});
    return static_cast<int>(scalars_.size()) - 1;
  }
  int add_vector(const std::string& name) {
    vectors_.push_back({name, std::vector<Vec<D>>(size(), Vec<D>::Zero())});
    return static_cast<int>(vectors_.size()) - 1;
  }
  std::vector<double>& scalar(int k) { return scalars_[k].data; }
  const std::vector<double>& scalar(int k) const { return scalars_[k].data; }
  std::vector<Vec<D>>& vector(int k) { return vectors_[k].data; }
  const std::vector<Vec<D>>& vector(int k) const { return vectors_[k].data; }

  // The extra fields by position (names as given to add_scalar / add_vector), for checkpoints.
  int scalar_count() const { return static_cast<int>(scalars_.size()); }
  int vector_count() const { return static_cast<int>(vectors_.size()); }
  const std::string& scalar_name(int k) const { return scalars_[k].name; }
  const std::string& vector_name(int k) const { return vectors_[k].name; }
  // The index of the scalar field `name`, -1 if there is none.
  int find_scalar(const std::string& name) const {
    for (std::size_t k = 0; k < scalars_.size(); ++k)
      if (scalars_[k].name == name)
        return static_cast<int>(k);
    return -1;
  }

  // The index of the vector field `name`, -1 if there is none.
  int find_vector(const std::string& name) const {
    for (std::size_t k = 0; k < vectors_.size(); ++k)
      if (vectors_[k].name == name)
        return static_cast<int>(k);
    return -1;
  }

  // Removes the particles with keep[i] == 0, preserving the order of the others, from every field.
  void keep_only(const std::vector<char>& keep) {
    compact(r, keep), compact(v, keep), compact(m, keep), compact(rho, keep), compact(p, keep);
    compact(V, keep), compact(kind, keep), compact(id, keep);
    for (auto& f : scalars_)
      compact(f.data, keep);
    for (auto& f : vectors_)
      compact(f.data, keep);
  }

  // new[i] = old[perm[i]] for every field.
  void reorder(const std::vector<std::uint32_t>& perm) {
    gather(r, perm, vbuf_), gather(v, perm, vbuf_);
    gather(m, perm, sbuf_), gather(rho, perm, sbuf_), gather(p, perm, sbuf_);
    gather(V, perm, sbuf_);
    gather(kind, perm, kbuf_), gather(id, perm, ibuf_);
    for (auto& f : scalars_)
      gather(f.data, perm, sbuf_);
    for (auto& f : vectors_)
      gather(f.data, perm, vbuf_);
  }

private:
  template <class T>
  struct Field {
    std::string name;
    std::vector<T> data;
  };
  std::vector<Field<double>> scalars_;
  std::vector<Field<Vec<D>>> vectors_;
  std::vector<double> sbuf_;
  std::vector<Vec<D>> vbuf_;
  std::vector<Kind> kbuf_;
  std::vector<std::int64_t> ibuf_;

  template <class T>
  static void compact(std::vector<T>& a, const std::vector<char>& keep) {
    std::size_t w = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (keep[i])
        a[w++] = a[i];
    a.resize(w);
  }
  template <class T>
  static void gather(std::vector<T>& a, const std::vector<std::uint32_t>& perm,
                     std::vector<T>& buf) {
    buf.resize(a.size());
    for (std::size_t i = 0; i < a.size(); ++i)
      buf[i] = a[perm[i]];
    a.swap(buf);
  }
};

} // namespace sph
