// A registry of named entries (cases, schemes) filled by registrars that sit beside each class,
// as LAMMPS keeps `PairStyle(lj/cut, PairLJCut)` in its pair's header: adding a case is one file.
//
//   namespace { const Registrar<CaseInfo> reg(make_my_case()); }   // in the case's .cpp
//
// The solver is an object library, so the linker keeps every registrar's translation unit.
// Entries are listed by name (the order of static initialisation is the link order, which is not
// an interface).
#pragma once

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph {

template <class Entry>
class Registry {
public:
  static std::vector<Entry>& entries() {
    static std::vector<Entry> e;
    return e;
  }
  static void add(Entry e) {
    auto& v = entries();
    for (const auto& x : v)
      if (x.name == e.name)
        throw std::logic_error("registry: '" + e.name + "' registered twice");
    auto at = std::lower_bound(v.begin(), v.end(), e,
                               [](const Entry& a, const Entry& b) { return a.name < b.name; });
    v.insert(at, std::move(e));
  }
  static const Entry* find(const std::string& name) {
    for (const auto& x : entries())
      if (x.name == name)
        return &x;
    return nullptr;
  }
};

// An entry with a `source` member (CaseInfo) learns the file that registers it (its solver
// fingerprint, core/fingerprint.hpp).
template <class Entry>
struct Registrar {
  explicit Registrar(Entry e, const char* file = __builtin_FILE()) {
    if constexpr (requires { e.source; })
      if (e.source.empty())
        e.source = file;
    Registry<Entry>::add(std::move(e));
  }
};

} // namespace sph
