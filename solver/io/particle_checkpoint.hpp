// Every field of a particle set (positions, velocities, mass, density, pressure, volume, kind, id
// and the scheme's extra named fields) as named arrays of doubles for io::Checkpointer, and back
// (the shared time loop, cases/time_loop.hpp, saves them with the named state of the case and the
// scheme). Doubles round-trip exactly (kind and id are small integers), so a resumed run continues
// bit for bit.
#pragma once

#include "core/particles.hpp"
#include "io/checkpoint.hpp"

#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace sph::io {

using Arrays = std::map<std::string, std::vector<double>>;

namespace detail {
template <int D>
std::vector<double> flatten(const std::vector<Vec<D>>& a) {
  std::vector<double> out;
  out.reserve(a.size() * D);
  for (const auto& x : a)
    for (int k = 0; k < D; ++k)
      out.push_back(x[k]);
  return out;
}
template <int D>
void unflatten(const std::vector<double>& in, std::vector<Vec<D>>& a, const std::string& name) {
  if (in.size() != a.size() * D)
    throw std::runtime_error("checkpoint: array '" + name + "' has " + std::to_string(in.size()) +
                             " values, expected " + std::to_string(a.size() * D));
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < D; ++k)
      a[i][k] = in[i * D + k];
}
template <class T>
void copy_in(const std::vector<double>& in, std::vector<T>& a, const std::string& name) {
  if (in.size() != a.size())
    throw std::runtime_error("checkpoint: array '" + name + "' has " + std::to_string(in.size()) +
                             " values, expected " + std::to_string(a.size()));
  for (std::size_t i = 0; i < a.size(); ++i) {
    if constexpr (std::is_enum_v<T>)
      a[i] = static_cast<T>(static_cast<int>(in[i]));
    else
      a[i] = static_cast<T>(in[i]);
  }
}
} // namespace detail

// The names particle_arrays() writes, for Checkpointer::load.
template <int D>
std::vector<std::string> particle_array_names(const Particles<D>& p) {
  std::vector<std::string> n{"p/r", "p/v", "p/m", "p/rho", "p/p", "p/V", "p/kind", "p/id"};
  for (int k = 0; k < p.scalar_count(); ++k)
    n.push_back("p/scalar/" + p.scalar_name(k));
  for (int k = 0; k < p.vector_count(); ++k)
    n.push_back("p/vector/" + p.vector_name(k));
  return n;
}

template <int D>
void add_particle_arrays(const Particles<D>& p, Arrays& out) {
  out["p/r"] = detail::flatten<D>(p.r);
  out["p/v"] = detail::flatten<D>(p.v);
  out["p/m"] = p.m, out["p/rho"] = p.rho, out["p/p"] = p.p, out["p/V"] = p.V;
  std::vector<double> kind(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    kind[i] = static_cast<double>(static_cast<int>(p.kind[i]));
  out["p/kind"] = std::move(kind);
  out["p/id"] = std::vector<double>(p.id.begin(), p.id.end());
  for (int k = 0; k < p.scalar_count(); ++k)
    out["p/scalar/" + p.scalar_name(k)] = p.scalar(k);
  for (int k = 0; k < p.vector_count(); ++k)
    out["p/vector/" + p.vector_name(k)] = detail::flatten<D>(p.vector(k));
}

// Restores a particle set built with the same extra fields; it takes the saved particle count
// (a case that adds and removes particles, such as an inflow, resumes with the count it saved).
template <int D>
void restore_particle_arrays(Particles<D>& p, const Arrays& in) {
  auto get = [&](const std::string& n) -> const std::vector<double>& {
    auto it = in.find(n);
    if (it == in.end())
      throw std::runtime_error("checkpoint: no array '" + n + "'");
    return it->second;
  };
  p.resize(get("p/m").size());
  detail::unflatten<D>(get("p/r"), p.r, "p/r");
  detail::unflatten<D>(get("p/v"), p.v, "p/v");
  detail::copy_in(get("p/m"), p.m, "p/m"), detail::copy_in(get("p/rho"), p.rho, "p/rho");
  detail::copy_in(get("p/p"), p.p, "p/p"), detail::copy_in(get("p/V"), p.V, "p/V");
  detail::copy_in(get("p/kind"), p.kind, "p/kind"), detail::copy_in(get("p/id"), p.id, "p/id");
  for (int k = 0; k < p.scalar_count(); ++k)
    detail::copy_in(get("p/scalar/" + p.scalar_name(k)), p.scalar(k),
                    "p/scalar/" + p.scalar_name(k));
  for (int k = 0; k < p.vector_count(); ++k)
    detail::unflatten<D>(get("p/vector/" + p.vector_name(k)), p.vector(k),
                         "p/vector/" + p.vector_name(k));
}

} // namespace sph::io
