#pragma once

#include <map>
#include <string>
#include <vector>

#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace {

/// An axis reading: other values for the axes of some experiment sets, chosen by evidence as a
/// model reading is (docs/fidelity.md, "The axes"). The paper does not publish its axes; the set
/// files hold the project's (the reading kSetsAxes).
struct AxisReading {
  std::string name;                  ///< kSetsAxes, or the file's name without .toml
  std::string file;                  ///< its file (empty for kSetsAxes)
  std::string title;                 ///< one line for reports
  std::map<std::string, Axis> axes;  ///< set name -> the axis that replaces the set file's
};

/// The axis reading of the set files themselves (the axes of version 0.3.0).
inline constexpr const char* kSetsAxes = "sets";

/// The names of the axis readings' files (NAME.toml) in `folder`, sorted; none when it does not
/// exist.
std::vector<std::string> axis_reading_names(const std::string& folder);

/// Reads the axis reading `name` from `folder`/NAME.toml (`title`, then one table per set
/// with `values` and optionally `fixed`), checked against the study's `sets`: each table names
/// a set, its values are increasing numbers and its fixed value is one of them. kSetsAxes gives
/// the set files' axes. Throws ConfigError naming the file and the key.
AxisReading read_axis_reading(const std::string& folder, const std::string& name,
                              const std::vector<SweepDef>& sets);

/// The name of set `set` under the axis reading `reading` in a store: "@READING/SET".
std::string axis_sweep_name(const std::string& reading, const std::string& set);

/// The sets an axis reading changes, with its axes and named axis_sweep_name.
std::vector<SweepDef> axis_reading_sets(const std::vector<SweepDef>& sets,
                                        const AxisReading& reading);

}  // namespace plumetrace
