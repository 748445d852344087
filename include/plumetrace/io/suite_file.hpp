#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plumetrace/sim/scenario.hpp"

namespace plumetrace {

/// One task of a benchmark suite (docs/benchmark.md, "Suite files"): a scenario file and the
/// settings on top of it, with why the task is in the suite and where it comes from.
struct SuiteTask {
  std::string name;           ///< short name, unique in the suite; the sweep's name in the store
  std::string title;          ///< one line for the leaderboard
  std::string why;            ///< what the task tests, for the leaderboard and the docs
  std::string source;         ///< where the task comes from (a citation)
  std::string scenario_path;  ///< base scenario file, resolved from the suite's folder
  std::vector<Setting> scenario_settings;  ///< the base scenario file's settings
  std::vector<Setting> settings;           ///< the task's [task.set] table, in file order
};

/// A benchmark suite: named, versioned tasks, the master seed and runs per cell they are run
/// with, and the controllers a benchmark runs by default.
struct SuiteFile {
  std::string file;        ///< the suite file read
  std::string name;        ///< e.g. "plumetrace-core"; the default output folder out/NAME
  std::string version;     ///< e.g. "1"; a changed task makes a new version
  std::string title;       ///< one line for the leaderboard
  std::uint64_t seed = 1;  ///< master seed of every task
  int runs = 30;           ///< runs per (controller, task) cell
  std::vector<std::string> controllers;  ///< the controllers run by default, in order
  std::vector<std::string> null_models;  ///< those of `controllers` that are null models
  std::vector<SuiteTask> tasks;          ///< in file order
  /// The digest the suite's tasks must give at its own seed and runs (BenchmarkPlan::digest),
  /// when the file records one (`digest = "..."`): planning refuses a suite whose tasks give
  /// another, so that a changed task cannot keep its version. Empty: not checked.
  std::string digest;
};

/// Reads a suite file: `name`, `version`, `title`, `seed`, `runs`, `controllers`,
/// `null_models`, optionally `digest`, and one [[task]] table per task (`name`, `title`, `why`, `source`,
/// `scenario`, [task.set]), and every task's scenario file. Throws ConfigError naming the file
/// and the key: a missing or mistyped key, an unknown key, a task without a name, two tasks of
/// one name, a null model that is not among the controllers, a control character in a text.
SuiteFile read_suite_file(const std::string& path);

}  // namespace plumetrace
