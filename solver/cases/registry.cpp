// Registry of cases: one line per case.
#include "cases/case.hpp"

#include <stdexcept>

namespace sph {

CaseInfo make_patch_test_case();
CaseInfo make_shear_layer_case();
CaseInfo make_lid_driven_cavity_case();
CaseInfo make_cavity_cylinder_case();
CaseInfo make_cylinder_channel_case();
CaseInfo make_checkpoint_demo_case();
CaseInfo make_taylor_green_case();
CaseInfo make_cylinder_array_case();
CaseInfo make_cylinder_free_stream_case();

const std::vector<CaseInfo>& case_registry() {
  static const std::vector<CaseInfo> cases{
      make_patch_test_case(),      make_shear_layer_case(),      make_lid_driven_cavity_case(),
      make_cavity_cylinder_case(), make_cylinder_channel_case(), make_checkpoint_demo_case(),
      make_taylor_green_case(),    make_cylinder_array_case(),   make_cylinder_free_stream_case(),
  };
  return cases;
}

const CaseInfo* find_case(const std::string& name) {
  for (const auto& c : case_registry())
    if (c.name == name)
      return &c;
  return nullptr;
}

namespace {
template <class T>
const T& get(const Params& p, const std::string& key, const char* type) {
  auto it = p.find(key);
  if (it == p.end())
    throw std::invalid_argument("parameter '" + key + "' is missing");
  if (auto v = std::get_if<T>(&it->second))
    return *v;
  throw std::invalid_argument("parameter '" + key + "' is not " + type);
}
} // namespace

double get_real(const Params& p, const std::string& key) {
  auto it = p.find(key);
  if (it != p.end())
    if (auto v = std::get_if<std::int64_t>(&it->second))
      return static_cast<double>(*v);
  return get<double>(p, key, "a real number");
}
std::int64_t get_int(const Params& p, const std::string& key) {
  return get<std::int64_t>(p, key, "an integer");
}
bool get_bool(const Params& p, const std::string& key) {
  return get<bool>(p, key, "a boolean");
}
const std::string& get_string(const Params& p, const std::string& key) {
  return get<std::string>(p, key, "a string");
}

} // namespace sph
