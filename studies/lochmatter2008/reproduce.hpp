#pragma once

#include <optional>
#include <string>
#include <vector>

#include "lochmatter2008/axes.hpp"
#include "lochmatter2008/study.hpp"
#include "lochmatter2008/summary.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/scenario_io.hpp"

namespace plumetrace {

/// What `plumetrace reproduce` runs: the readings and the sweeps of every one.
struct Reproduction {
  std::vector<Reading> readings;      ///< the main reading first, then the others
  /// The axis readings whose sets run under the main reading (kSetsAxes is the main sets).
  std::vector<AxisReading> axis_readings;
  std::vector<SweepDef> sets;         ///< the study's experiment sets as their files say
  std::vector<ExpandedSweep> sweeps;  ///< what runs, in the order plan_reproduction says
  std::string radius;                 ///< the radius sweep's name
};

/// The reproduction of `study` under the reading `main` and the readings `others` (every
/// preset file of the study when not given; each reading once): the main reading's sets and
/// the radius sweep (without the reading's keys that are its axes), then the other readings'
/// sets, then the sets each axis reading of `axes` changes (every axis reading file when not
/// given), under the main reading. Throws ConfigError naming an unknown preset or axis reading.
Reproduction plan_reproduction(const Study& study, const std::string& main,
                               const std::optional<std::vector<std::string>>& others,
                               const std::optional<std::vector<std::string>>& axes = {});

/// Writes runs.csv, summary.csv, results.json and summary.json (build_summary) of a
/// reproduction into the folder `out`; `info` need not say the sets, the trajectory sets, the
/// radius sweep, the readings nor the base configuration: they are taken from the study.
void write_reproduction(const std::string& out, const Study& study, const Reproduction& plan,
                        const std::vector<RunRow>& rows, ReproduceInfo info);

/// The sweeps of `plumetrace sensitivity`: every set with the study's sensitivity axes in front
/// of its own, at `runs` runs per point.
std::vector<ExpandedSweep> sensitivity_campaign(const Study& study, int runs);

/// Writes sensitivity.json and sensitivity.md into the folder `out`; returns the Markdown.
std::string write_sensitivity(const std::string& out, const Study& study,
                              const std::vector<ExpandedSweep>& sweeps,
                              const std::vector<RunRow>& rows, int runs, double elapsed);

}  // namespace plumetrace
