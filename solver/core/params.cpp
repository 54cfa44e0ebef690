// Typed access to resolved parameters (core/params.hpp).
#include "core/params.hpp"

namespace sph {
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
