#pragma once
// Reading TOML input files: scenario, preset and sweep files, and studies' files (toml++).

#include <toml++/toml.h>

#include <optional>
#include <string>
#include <vector>

#include "plumetrace/sim/scenario.hpp"

namespace plumetrace::detail {

/// The most dotted segments a key in a TOML file may have (config keys have two): deeper keys
/// are refused, naming the file and the key, before they are walked.
inline constexpr int kMaxKeyDepth = 16;

/// Parses the TOML file at `path` (a regular file; `what` names it in messages, e.g. "sweep
/// file"); throws ConfigError naming the file, with line and column for invalid TOML, and for a
/// key of more than kMaxKeyDepth dotted parts.
toml::table parse_toml_file(const std::string& path, const std::string& what);

/// Appends the table's keys as settings of `layer`, dotted from `prefix`, in file order; throws
/// ConfigError naming `path` for a key nested deeper than kMaxKeyDepth.
void flatten(const toml::table& table, const std::string& prefix, const std::string& path,
             Layer layer, std::vector<Setting>& out, int depth = 1);

/// A TOML scalar as a config value; nullopt for an array, a table, a date or a time.
std::optional<ConfigValue> toml_scalar(const toml::node& node);

}  // namespace plumetrace::detail
