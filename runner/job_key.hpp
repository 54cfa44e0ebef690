// Job identity: the canonical JSON of a job (case, scheme, identity parameters, numerics version,
// keys sorted, reals printed round-trip exactly) and its SHA-256, the job key. Same parameters,
// same key, whatever study file they came from.
#pragma once

#include "cases/case.hpp"

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace sph::runner {

std::string sha256_hex(std::string_view data);

// {"name": value} of the identity parameters, sorted by name; Real values are doubles.
nlohmann::json identity_params_json(const std::vector<ParamSpec>& specs, const Params& params);
// identity_params_json(specs, params).dump(), byte for byte, written without a JSON tree (the
// expansion of a million jobs writes a million).
std::string identity_params_text(const std::vector<ParamSpec>& specs, const Params& params);
// {"name": value} of all parameters (identity or not), sorted by name.
nlohmann::json all_params_json(const Params& params);

// {"case":..., "numerics_version":N, "params":{...}, "scheme":...} dumped compactly.
std::string canonical_job_json(const std::string& case_name, const std::string& scheme,
                               const nlohmann::json& identity_params, int numerics);

// The same text from the identity parameters already dumped (identity_params_json(...).dump()).
std::string canonical_job_text(const std::string& case_name, const std::string& scheme,
                               const std::string& identity_params_text, int numerics);

std::string job_key(const std::string& canonical_json);

} // namespace sph::runner
