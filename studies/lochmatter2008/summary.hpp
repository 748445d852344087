#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "lochmatter2008/axes.hpp"
#include "lochmatter2008/claims.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"

namespace plumetrace {

/// The statistics of a single-axis sweep as an experiment set (docs/experiments.md); the varied
/// values must be numbers. `points` selects a subset of the sweep's points (all when empty) and
/// `axis` which axis is the varied one.
SetStats set_stats(const ExpandedSweep& sweep, const std::vector<RunRow>& rows, int runs,
                   const std::vector<int>& points = {}, std::size_t axis = 0);

/// The store name of experiment set `set` under a reading: the set's own name ("A") for the
/// main reading, "READING/SET" ("plugin/A") for the others.
std::string reading_sweep_name(const std::string& reading, bool main, const std::string& set);

/// The experiment sets under a reading: each definition expanded with the reading's settings as
/// overrides and named by reading_sweep_name. Throws ConfigError when the reading sets a key
/// that is an axis of a set (naming the preset file and the key).
std::vector<ExpandedSweep> reading_sets(const std::vector<SweepDef>& sets, const Reading& reading,
                                        bool main);

/// Failed runs re-run per algorithm at the fixed values (of the main reading) at most.
inline constexpr int kFailuresExamined = 25;

/// Trials (plumes) of each reading's plume statistics in summary.json (docs/plume-statistics.md):
/// a handful, so that the reproduction stays about as fast (docs/report.md).
inline constexpr int kPlumeStatsTrials = 4;

/// What `reproduce` hands to the report beyond the store's rows.
struct ReproduceInfo {
  std::vector<std::string> sets;             ///< the experiment sets' names, in order
  std::vector<std::string> trajectory_sets;  ///< the sets whose fixed values give Fig. 6
  std::string radius;                        ///< the success-radius sweep's name
  std::string command;                       ///< the command line
  std::string preset;                        ///< the main reading's name
  std::vector<Reading> readings;             ///< every reading run, the main one first
  std::vector<AxisReading> axis_readings;    ///< the axis readings run, kSetsAxes first
  int runs_override = 0;                     ///< --runs (0: the sweep files')
  int threads = 0;                           ///< worker threads used
  double elapsed = 0.0;                      ///< seconds spent running (this call)
  std::int64_t computed = -1;                ///< runs computed by this call (-1: not known)
  std::string base_config;                   ///< the resolved base scenario (TOML)
};

/// Builds summary.json for the report (schema in docs/report.md): the sets' statistics, the
/// claims, the sensitivity rows (of the radius sweep), one successful and one failed trajectory
/// per trajectory set at its fixed values (re-run from seed and trial), the plume's detection
/// map, where failed runs end (up to kFailuresExamined re-run per trajectory set), and for each
/// reading its claims, its fixed-value statistics, its detection map and its plume statistics
/// (kPlumeStatsTrials plumes of the sets' master seed).
std::string build_summary(const std::vector<ExpandedSweep>& sweeps, const std::vector<RunRow>& rows,
                          const ReproduceInfo& info);

/// One row of the sensitivity claims matrix.
struct SensitivityRow {
  std::vector<ConfigValue> values;  ///< one per sensitivity axis
  std::vector<ClaimResult> claims;  ///< claims 1-11 under this combination
};

/// The sensitivity claims matrix: one row per combination of the axes' values.
struct SensitivityMatrix {
  std::vector<Axis> axes;            ///< the sensitivity axes
  std::vector<SensitivityRow> rows;  ///< the first axis varying slowest
};

/// The sensitivity study's sweeps: each set with the axes `front` put in front of its own and
/// `runs` runs per point (docs/experiments.md, `plumetrace sensitivity`).
std::vector<SweepDef> sensitivity_sweeps(const std::vector<SweepDef>& sets,
                                         const std::vector<Axis>& front, int runs);

/// The claims matrix from the sensitivity sweeps' rows; the first `front` axes of every sweep
/// are the sensitivity axes.
SensitivityMatrix sensitivity_matrix(const std::vector<ExpandedSweep>& sweeps,
                                     const std::vector<RunRow>& rows, int runs, std::size_t front);

/// sensitivity.json (schema in docs/report.md): a row names each axis by its key's last part.
std::string sensitivity_json(const SensitivityMatrix& matrix, int runs, double elapsed);

/// The claims matrix as a Markdown table.
std::string sensitivity_markdown(const SensitivityMatrix& matrix, int runs, double elapsed);

}  // namespace plumetrace
