#pragma once

#include <string>
#include <vector>

#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace {

/// Reads a sweep file, and the scenario file it names into the definition's scenario settings;
/// throws ConfigError naming the file and the problem (unknown key, empty axis, value of the
/// wrong type, ...). The scenario path is resolved from the file's folder.
SweepDef read_sweep_file(const std::string& path);

/// Checks a sweep as read_sweep_file checks a file's (for sweeps built in code, such as a
/// Python dict of axes): a name, at least one axis, none empty or given twice, every value
/// valid for its key; throws ConfigError naming `where`, the axis and the key.
void check_sweep_def(const SweepDef& def, const std::string& where);

}  // namespace plumetrace
