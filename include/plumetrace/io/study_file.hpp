#pragma once

#include <string>
#include <vector>

namespace plumetrace {

/// A study beyond the paper's (docs/experiments.md, "Studies"): a folder whose study.toml names
/// its sweep files, run together as one campaign, and the Python module that draws its report.
struct StudyFile {
  std::string file;               ///< the study file read
  std::string name;               ///< short name, e.g. "meander"
  std::string title;              ///< one line for reports
  std::vector<std::string> sets;  ///< its sweep files, resolved from the study's folder
  std::string report;             ///< module run as `python -m MODULE OUT`; empty: none
};

/// Reads FOLDER/study.toml: `name`, `title`, `sets` (sweep files, relative to the folder) and
/// optionally `report`; throws ConfigError naming the file and the key (unknown keys included).
StudyFile read_study_file(const std::string& folder);

}  // namespace plumetrace
