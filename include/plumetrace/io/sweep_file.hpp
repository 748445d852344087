#pragma once

#include <string>
#include <vector>

#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace {

/// Reads a sweep file, and the scenario file it names into the definition's scenario settings;
/// throws ConfigError naming the file and the problem (unknown key, empty axis, value of the
/// wrong type, ...). The scenario path is resolved from the file's folder.
SweepDef read_sweep_file(const std::string& path);

/// The identity of a campaign (its sweeps, points and resolved configs; not the runs per point)
/// as canonical JSON: stores refuse to mix results of different definitions.
std::string campaign_definition(const std::vector<ExpandedSweep>& sweeps);

}  // namespace plumetrace
