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
  /// What draws the report: a module of the plumetrace package, run as `python -m MODULE OUT`,
  /// or a .py file of the study's folder, run as `python FILE OUT` (its path from here); empty:
  /// none.
  std::string report;
  bool report_is_file = false;  ///< `report` is a file of the study's folder, not a module
};

/// Reads FOLDER/study.toml: `name`, `title`, `sets` (sweep files, relative to the folder) and
/// optionally `report`; throws ConfigError naming the file and the key (unknown keys included).
/// Names and titles hold no control character; `report` names a module of the plumetrace
/// package ("plumetrace.studies.meander") or a .py file inside the folder ("report.py"), and
/// nothing else. why: a data file must not run code from elsewhere: `report = "evilmod"` ran
/// any module on the path, the current folder's first (issue 22, G4).
StudyFile read_study_file(const std::string& folder);

}  // namespace plumetrace
