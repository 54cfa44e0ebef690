// Canonical job JSON and SHA-256 job keys (OpenSSL EVP).
#include "job_key.hpp"

#include "params.hpp"

#include <openssl/evp.h>
#include <stdexcept>

namespace sph::runner {

std::string sha256_hex(std::string_view data) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  if (EVP_Digest(data.data(), data.size(), digest, &len, EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("SHA-256 failed (OpenSSL EVP_Digest)");
  static const char* hex = "0123456789abcdef";
  std::string out(2 * len, '0');
  for (unsigned int i = 0; i < len; ++i) {
    out[2 * i] = hex[digest[i] >> 4];
    out[2 * i + 1] = hex[digest[i] & 15];
  }
  return out;
}

nlohmann::json identity_params_json(const std::vector<ParamSpec>& specs, const Params& params) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& s : specs) {
    if (!s.identity || s.name == scheme_param)
      continue;
    auto it = params.find(s.name);
    if (it == params.end())
      throw std::logic_error("unresolved parameter '" + s.name + "'");
    ParamValue v = it->second;
    if (s.type == ParamType::Real)
      if (auto i = std::get_if<std::int64_t>(&v))
        v = static_cast<double>(*i);
    if (s.neutral_default) {
      // At its declared neutral default the parameter leaves the key as it was before the
      // parameter existed (the finished jobs of the case keep their keys).
      ParamValue d = s.default_value;
      if (s.type == ParamType::Real)
        if (auto i = std::get_if<std::int64_t>(&d))
          d = static_cast<double>(*i);
      if (v == d)
        continue;
    }
    j[s.name] = value_to_json(v);
  }
  return j;
}

nlohmann::json all_params_json(const Params& params) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : params)
    j[k] = value_to_json(v);
  return j;
}

std::string canonical_job_text(const std::string& case_name, const std::string& scheme,
                               const std::string& identity_params_text, int numerics) {
  // Exactly what canonical_job_json dumps (keys sorted: case, numerics_version, params, scheme;
  // compact), without building a second JSON tree per job.
  return "{\"case\":" + nlohmann::json(case_name).dump() +
         ",\"numerics_version\":" + std::to_string(numerics) +
         ",\"params\":" + identity_params_text + ",\"scheme\":" + nlohmann::json(scheme).dump() +
         "}";
}

std::string canonical_job_json(const std::string& case_name, const std::string& scheme,
                               const nlohmann::json& identity_params, int numerics) {
  nlohmann::json j = nlohmann::json::object();
  j["case"] = case_name;
  j["scheme"] = scheme;
  j["params"] = identity_params;
  j["numerics_version"] = numerics;
  return j.dump(); // std::map-backed objects: keys come out sorted
}

std::string job_key(const std::string& canonical_json) {
  return sha256_hex(canonical_json);
}

} // namespace sph::runner
