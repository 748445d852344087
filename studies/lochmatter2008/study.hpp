#pragma once

#include <string>
#include <vector>

#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace {

/// The study of Lochmatter & Martinoli (2008) as its study.toml describes it: the files it runs
/// and what the report draws from (format in docs/experiments.md, "The study folder"). Paths are
/// resolved from the study file's folder.
struct Study {
  /// The study file it was read from.
  std::string file;
  /// Its name ("lochmatter2008").
  std::string name;
  /// The folder of the readings' preset files NAME.toml.
  std::string presets_dir;
  /// The folder of the axis readings' files NAME.toml (lochmatter2008/axes.hpp); may be empty.
  std::string axes_dir;
  /// The experiment sets' sweep files, in the report's order.
  std::vector<std::string> set_files;
  /// The sets (by name) whose fixed-value points give the trajectory figure, the failed runs
  /// examined and each reading's fixed-value statistics: one per algorithm.
  std::vector<std::string> trajectory_sets;
  /// The sweep of the algorithms at their fixed values under several success radii.
  std::string radius_file;
  /// The axes `plumetrace sensitivity` puts in front of every set's own.
  std::vector<Axis> sensitivity_axes;
};

/// The study file of the repository: studies/lochmatter2008/study.toml.
std::string default_study_file();

/// Reads a study file (not yet the sweep files it names); throws ConfigError naming the file
/// and the key.
Study read_study(const std::string& path);

/// The experiment sets, read from their sweep files in order; throws ConfigError when a file
/// cannot be read, two sets share a name, or a trajectory set is not among them.
std::vector<SweepDef> read_sets(const Study& study);

/// The names of the study's experiment sets, in order ("A".."I").
std::vector<std::string> set_names(const std::vector<SweepDef>& sets);

}  // namespace plumetrace
