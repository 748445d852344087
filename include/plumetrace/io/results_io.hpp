#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plumetrace/experiment/stats.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/sim/probe.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

/// One run's result as a JSON object (keys as documented for `plumetrace run --json`).
std::string result_to_json(const RunResult& result, const RunInfo& info);

/// Probe results as {"points": [...]}.
std::string probe_to_json(const std::vector<ProbeResult>& results);

/// Writes one CSV row per stored run: sweep, point, one column per axis key (union over the
/// sweeps), trial, seed, config hash and every metric. Throws IoError naming the file.
void write_runs_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                    const std::vector<RunRow>& rows);

/// Writes one CSV row per sweep point with the statistics of docs/experiments.md over trials
/// 0..runs-1. Throws IoError naming the file.
void write_summary_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                       const std::vector<RunRow>& rows, int runs_override);

/// Writes the sweeps, their points with statistics, and every run as one JSON document; each
/// sweep's file as recorded_path gives it.
void write_results_json(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                        const std::vector<RunRow>& rows, int runs_override);

}  // namespace plumetrace
