#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "lochmatter2008/claims.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace plumetrace {

/// The names of the paper's nine experiment sets, "A".."I", as the repository's study file
/// lists them (studies/lochmatter2008/study.toml).
std::vector<std::string> experiment_set_names();

/// What to evaluate: the experiment sets of a folder under one reading of the unknowns.
struct CalibrationOptions {
  /// Folder holding the sweep files NAME.toml (studies/lochmatter2008/sets).
  std::string sets_dir;
  /// Which sets to run (empty: all nine, as experiment_set_names).
  std::vector<std::string> sets;
  /// Settings applied on top of every sweep's own, as `--set` would (they may not name an axis).
  std::vector<Setting> overrides;
  /// Runs per value (0: each sweep file's own).
  int runs = 0;
  /// Master seed of every sweep (0: each sweep file's own).
  std::uint64_t seed = 0;
  /// Worker threads (0: all cores).
  int threads = 0;
  /// Set from outside (a signal handler) to stop dispatching new runs.
  const std::atomic<bool>* stop = nullptr;
  /// Called from the calling thread about every 0.25 s while the runs are computed.
  std::function<void(const Progress&)> on_progress;
};

/// The statistics and claims of one evaluation.
struct CalibrationResult {
  /// Per-set statistics, keyed by name ("A".."I"), of the sets that were run.
  std::map<std::string, SetStats> sets;
  /// Claims 1-11 (those whose sets were not run are unclear, saying so).
  std::vector<ClaimResult> claims;
  /// Runs computed.
  std::int64_t runs = 0;
  /// Seconds spent.
  double elapsed = 0.0;
  /// Stopped before every run was computed (sets and claims are then left empty).
  bool interrupted = false;
};

/// The sweeps an evaluation runs: each set's sweep file read from `sets_dir`, its seed and runs
/// replaced where the options say so, expanded under the overrides. Throws ConfigError.
std::vector<ExpandedSweep> calibration_sweeps(const CalibrationOptions& options);

/// Runs the sets in memory (no store, shared plumes) and evaluates the claims: the statistics
/// equal those a `plumetrace sweep` of the same files, seed and runs would give.
CalibrationResult evaluate_sets(const CalibrationOptions& options);

}  // namespace plumetrace
