// The 20 liquids of seed 003, Table 1 (Parshikov, Medin, Rublev & Dyachkov, "Adjusting the
// numerical viscosity in the Godunov-like SPH method at modeling compressible flows"): density
// rho0, sound speed c0 and the physical dynamic viscosity eta, which the paper takes from
// I. S. Grigoryev, E. Z. Meilikhov (Eds.), Physical Quantities: the Handbook, Energoatomizdat,
// Moscow, 1991 (its ref. [22]).
//
// Only these inputs are here. The paper's measured numerical viscosities (the last column of
// Table 1) are reference values: they are in docs/contact.md, never in code that computes results.
//
// Notes on two rows:
// - paraffin: Table 1 gives eta = 25-80 mPa s; we use 80 mPa s, the value implied by the paper's
//   own cylinder runs (Table 2: Re = 0.005, d = 0.1 mm, U = 4.40 mm/s, rho = 910 kg/m^3).
// - lithium fluoride and corundum: Table 1 gives no eta ("-"); eta_known = false and eta = 0
//   (an inviscid liquid) unless the study sets eta explicitly.
// "uranus" is the paper's spelling of uranium; the key is "uranium".
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sph {

struct Material {
  const char* key;
  const char* name;
  double rho0; // kg/m^3
  double c0;   // m/s
  double eta;  // Pa s
  bool eta_known;
};

inline constexpr std::array<Material, 20> table1_materials{{
    {"lithium", "Lithium", 534.0, 4718.0, 0.566e-3, true},
    {"benzene", "Benzene", 880.0, 1571.8, 0.604e-3, true},
    {"paraffin", "Paraffin", 910.0, 895.6, 80e-3, true},
    {"water", "Water", 1000.0, 1483.0, 1.004e-3, true},
    {"nitromethane", "Nitromethane", 1128.0, 1144.7, 0.63e-3, true},
    {"glycerol", "Glycerol", 1250.0, 1902.6, 1480e-3, true},
    {"sodium_chloride", "Sodium chloride", 2160.0, 3496.0, 1.03e-3, true},
    {"silica", "Silica", 2480.0, 4181.18, 10.0e-3, true},
    {"lithium_fluoride", "Lithium fluoride", 2650.0, 5132.2, 0.0, false},
    {"aluminum", "Aluminum", 2688.9, 5416.0, 1.24e-3, true},
    {"corundum", "Corundum", 3920.0, 5779.8, 0.0, false},
    {"titanium", "Titanium", 4510.0, 4924.0, 4.42e-3, true},
    {"zinc", "Zinc", 6577.0, 3057.0, 3.737e-3, true},
    {"iron", "Iron", 7880.0, 4660.0, 5.22e-3, true},
    {"nickel", "Nickel", 8902.0, 4999.9, 5.01e-3, true},
    {"copper", "Copper", 8920.0, 4118.5, 3.92e-3, true},
    {"lead", "Lead", 11350.0, 1931.7, 2.3e-3, true},
    {"tantalum", "Tantalum", 16600.0, 3481.5, 8.5e-3, true},
    {"uranium", "Uranium", 19100.0, 3056.88, 6.5e-3, true},
    {"tungsten", "Tungsten", 19350.0, 3937.5, 7.0e-3, true},
}};

inline const Material* find_material(std::string_view key) {
  for (const auto& m : table1_materials)
    if (key == m.key)
      return &m;
  return nullptr;
}

// The material `key`, or std::invalid_argument "<who>: unknown material '<key>'".
inline const Material& material_or_throw(std::string_view key, const std::string& who) {
  const Material* m = find_material(key);
  if (!m)
    throw std::invalid_argument(who + ": unknown material '" + std::string(key) + "'");
  return *m;
}

// The physical viscosity of a liquid: eta_param when >= 0 (a study's override), else the
// material's; it must be > 0 (std::invalid_argument naming <who> and the material otherwise).
inline double liquid_viscosity(double eta_param, const Material& m, const std::string& who) {
  const double eta = eta_param >= 0.0 ? eta_param : m.eta;
  if (!(eta > 0.0))
    throw std::invalid_argument(who + ": the liquid needs a viscosity eta > 0 (material '" + m.key +
                                "' has none in Table 1: set eta)");
  return eta;
}

inline std::vector<std::string> material_keys() {
  std::vector<std::string> k;
  for (const auto& m : table1_materials)
    k.emplace_back(m.key);
  return k;
}

} // namespace sph
