#pragma once

#include <string>
#include <vector>

#include "plumetrace/sim/scenario.hpp"

namespace plumetrace {

/// Reads a TOML scenario file into settings (one per key, in file order); throws ConfigError
/// naming the file when it cannot be read or is not valid TOML (with line and column).
std::vector<Setting> read_scenario_file(const std::string& path);

/// A reading of what the paper leaves unsaid (docs/fidelity.md): a preset file's keys, applied
/// on top of every experiment set as command-line-layer overrides.
struct Reading {
  std::string name;               ///< kDefaultReading or the preset file's name without .toml
  std::string file;               ///< the preset file (empty for kDefaultReading)
  std::vector<Setting> settings;  ///< its keys in file order, layer kCommandLine
};

/// The reading that adds nothing to the sets' own scenario (the built-in defaults).
inline constexpr const char* kDefaultReading = "default";

/// The names of the preset files (NAME.toml) in `folder`, sorted; none when it does not exist.
std::vector<std::string> preset_names(const std::string& folder);

/// Reads the reading `name`: kDefaultReading (no settings) or `folder`/NAME.toml, a partial
/// scenario file whose keys become command-line-layer settings. Every key is checked. Throws
/// ConfigError naming the unknown reading and the ones there are, or naming the file and key.
Reading read_reading(const std::string& folder, const std::string& name);

/// Builds the scenario from an optional file (empty path: defaults) and then the overrides.
Scenario load_scenario(const std::string& path, const std::vector<Setting>& overrides);

/// The fully resolved scenario as a JSON object, nested by table.
std::string scenario_to_json(const Scenario& scenario);

}  // namespace plumetrace
