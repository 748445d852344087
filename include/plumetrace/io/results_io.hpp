#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plumetrace/experiment/stats.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/sim/plume_stats.hpp"
#include "plumetrace/sim/probe.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

/// One run's result as a JSON object (keys as documented for `plumetrace run --json`).
std::string result_to_json(const RunResult& result, const RunInfo& info);

/// Probe results as {"points": [...]}; each point's detect_fraction is also its intermittency.
std::string probe_to_json(const std::vector<ProbeResult>& results);

/// A probe report as {"points": [...], "centrelines": [{x, mean_y, std_y, samples, empty}]}.
std::string probe_to_json(const ProbeReport& report);

/// A plume's statistics as one JSON document (docs/plume-statistics.md).
std::string plume_stats_to_json(const PlumeStats& stats);

/// A detection map as {"x": [...], "y": [...], "z": z, "fraction": [[...] per y]}.
std::string detection_map_to_json(const MapGrid& grid,
                                  const std::vector<std::vector<double>>& fraction);

/// Writes one CSV row per stored row (a robot's run): sweep, point, one column per axis key
/// (union over the sweeps), trial, agent, seed, config hash and every metric. Throws IoError
/// naming the file.
void write_runs_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                    const std::vector<RunRow>& rows);

/// Writes one CSV row per team (the robots of one run together, team_outcomes): sweep, point,
/// one column per axis key, trial, then robots, arrivals, first_agent, t_first_arrival and
/// d_t_sum. Throws IoError naming the file.
void write_teams_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                     const std::vector<RunRow>& rows);

/// Writes one CSV row per sweep point with the statistics of docs/experiments.md over trials
/// 0..runs-1. Throws IoError naming the file.
void write_summary_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                       const std::vector<RunRow>& rows, int runs_override);

/// Writes the sweeps, their points with statistics (`stats` over every robot's run, `team` over
/// the teams), and every run as one JSON document; each sweep's file as recorded_path gives it.
void write_results_json(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                        const std::vector<RunRow>& rows, int runs_override);

}  // namespace plumetrace
