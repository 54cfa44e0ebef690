// Canonical job JSON (as a JSON tree, and as text written directly, byte for byte the same) and
// SHA-256 job keys (OpenSSL EVP).
#include "job_key.hpp"

#include "params.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

namespace sph::runner {

std::string sha256_hex(std::string_view data) {
  // Fetched once: EVP_sha256() in EVP_Digest fetches the implementation again at every call
  // (OpenSSL 3), a third of the cost of hashing a job's canonical text.
  static EVP_MD* const md = EVP_MD_fetch(nullptr, "SHA256", nullptr);
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  if (!md || EVP_Digest(data.data(), data.size(), digest, &len, md, nullptr) != 1)
    throw std::runtime_error("SHA-256 failed (OpenSSL EVP_Digest)");
  static const char* hex = "0123456789abcdef";
  std::string out(2 * len, '0');
  for (unsigned int i = 0; i < len; ++i) {
    out[2 * i] = hex[digest[i] >> 4];
    out[2 * i + 1] = hex[digest[i] & 15];
  }
  return out;
}

namespace {

// Appends what nlohmann::json(s).dump() gives: plain printable ASCII directly, anything else
// (escapes, UTF-8) through nlohmann.
void append_json_string(std::string& out, const std::string& s) {
  for (char c : s)
    if (c < 0x20 || c > 0x7e || c == '"' || c == '\\') {
      out += nlohmann::json(s).dump();
      return;
    }
  out += '"';
  out += s;
  out += '"';
}

// Appends what value_to_json(v).dump() gives (a Real holding an integer as a double).
void append_json_value(std::string& out, const ParamValue& v, bool real) {
  char buf[64];
  if (const auto* d = std::get_if<double>(&v);
      d || (real && std::holds_alternative<std::int64_t>(v))) {
    const double x = d ? *d : static_cast<double>(std::get<std::int64_t>(v));
    if (!std::isfinite(x)) {
      out += "null";
      return;
    }
    out.append(buf, nlohmann::detail::to_chars(buf, buf + sizeof buf, x));
  } else if (const auto* i = std::get_if<std::int64_t>(&v)) {
    out.append(buf, std::to_chars(buf, buf + sizeof buf, *i).ptr);
  } else if (const auto* b = std::get_if<bool>(&v)) {
    out += *b ? "true" : "false";
  } else {
    append_json_string(out, std::get<std::string>(v));
  }
}

// A parameter that enters the job key, and whether it is a Real (an integer value is a double).
struct IdentityItem {
  const std::string* name;
  const ParamValue* value;
  bool real;
};

// The identity parameters of a job (in spec order), without the neutral defaults.
std::vector<IdentityItem> identity_items(const std::vector<ParamSpec>& specs,
                                         const Params& params) {
  std::vector<IdentityItem> items;
  items.reserve(specs.size());
  for (const auto& s : specs) {
    if (!s.identity || s.name == scheme_param)
      continue;
    auto it = params.find(s.name);
    if (it == params.end())
      throw std::logic_error("unresolved parameter '" + s.name + "'");
    const bool real = s.type == ParamType::Real;
    if (s.neutral_default) {
      // At its declared neutral default the parameter leaves the key as it was before the
      // parameter existed (the finished jobs of the case keep their keys).
      ParamValue v = it->second, d = s.default_value;
      for (ParamValue* x : {&v, &d})
        if (auto i = std::get_if<std::int64_t>(x); i && real)
          *x = static_cast<double>(*i);
      if (v == d)
        continue;
    }
    items.push_back({&s.name, &it->second, real});
  }
  return items;
}

} // namespace

nlohmann::json identity_params_json(const std::vector<ParamSpec>& specs, const Params& params) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& item : identity_items(specs, params)) {
    const auto* i = std::get_if<std::int64_t>(item.value);
    j[*item.name] =
        item.real && i ? nlohmann::json(static_cast<double>(*i)) : value_to_json(*item.value);
  }
  return j;
}

std::string identity_params_text(const std::vector<ParamSpec>& specs, const Params& params) {
  std::vector<IdentityItem> items = identity_items(specs, params);
  // A JSON object's keys in std::map order.
  std::sort(items.begin(), items.end(),
            [](const IdentityItem& a, const IdentityItem& b) { return *a.name < *b.name; });
  std::string out = "{";
  out.reserve(32 * items.size() + 2);
  for (const auto& item : items) {
    if (out.size() > 1)
      out += ',';
    append_json_string(out, *item.name);
    out += ':';
    append_json_value(out, *item.value, item.real);
  }
  out += '}';
  return out;
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
  std::string out;
  out.reserve(identity_params_text.size() + case_name.size() + scheme.size() + 64);
  out += "{\"case\":";
  append_json_string(out, case_name);
  out += ",\"numerics_version\":" + std::to_string(numerics) + ",\"params\":";
  out += identity_params_text;
  out += ",\"scheme\":";
  append_json_string(out, scheme);
  out += '}';
  return out;
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
