// Parameter values against their specs: type names, coercion (a Real accepts an integer), range and
// choice checks, printing, and conversion to and from JSON.
#pragma once

#include "cases/case.hpp"

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace sph::runner {

// "bool", "int", "real", "string"
std::string type_name(ParamType t);
// "a boolean", "an integer", ...
std::string type_phrase(ParamType t);
// The type a value holds, as a phrase ("a real number").
std::string value_type_phrase(const ParamValue& v);

// Human-readable value: strings quoted, reals in shortest round-trip form ("0.1", "1.0").
std::string format_value(const ParamValue& v);
// Same, strings unquoted (for log lines: visc=visc01).
std::string format_value_plain(const ParamValue& v);
// Shortest round-trip decimal of a double ("0.1", "1e-05"); always has a '.' or 'e' if finite.
std::string format_real(double x);

// Coerces `v` to the spec's type in place (Int -> Real) and checks range and choices.
// Returns an error message ("expected an integer, got 1.5") or nullopt when valid.
std::optional<std::string> check_value(const ParamSpec& spec, ParamValue& v);

// The range/choices of a spec as text: "> 0", "[1, 100]", "one of 'a', 'b'"; "" when free.
std::string constraint_text(const ParamSpec& spec);

nlohmann::json value_to_json(const ParamValue& v);
// Converts JSON to the spec's type; throws std::invalid_argument on a mismatch.
ParamValue value_from_json(const ParamSpec& spec, const nlohmann::json& j);

// The specs a study may name for a case: the case's params, the params of every scheme the case
// runs with, and, when the case lists schemes, the parameter "scheme" (a String with those
// choices, default the first).
std::vector<ParamSpec> study_specs(const CaseInfo& info);
// The specs of one job: the case's params, its scheme's params, and "scheme" when the case has
// schemes. Params given to CaseInfo::run carry exactly these keys.
std::vector<ParamSpec> job_specs(const CaseInfo& info, const std::string& scheme);
// The scheme whose parameter `name` is ("" when it is the case's own or unknown).
std::string scheme_owning(const CaseInfo& info, const std::string& name);
const ParamSpec* find_spec(const std::vector<ParamSpec>& specs, const std::string& name);
std::vector<std::string> spec_names(const std::vector<ParamSpec>& specs);

inline constexpr const char* scheme_param = "scheme";

} // namespace sph::runner
