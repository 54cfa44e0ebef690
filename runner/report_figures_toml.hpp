// The [[figures]] parser on a toml++ node, shared by the study parser (which validates figures
// with the rest of the file) and load_figures(). Internal: only for files that use toml++.
#pragma once

#include "diagnostics.hpp"
#include "report_figures.hpp"

#include <toml++/toml.h>

namespace sph::runner {

// Validates the `figures` node of a study file against the study's parameter specs, adding one
// diagnostic per problem; returns the figures that parsed. `file` locates CSV references.
std::vector<FigureSpec> parse_figures_node(const toml::node& figures,
                                           const std::vector<ParamSpec>& specs,
                                           const std::string& file, Diagnostics& diag);

} // namespace sph::runner
