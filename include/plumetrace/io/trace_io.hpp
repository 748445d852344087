#pragma once

#include <cstdint>
#include <string>

#include "plumetrace/io/results_io.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/trace.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

/// Checks a trace path before a run: a .csv or .json name (ConfigError otherwise) whose files
/// can be created (IoError naming the file otherwise).
void check_trace_path(const std::string& path);

/// Writes a trace (format 3, docs/architecture.md "Trace format"): `.json` as one object, robot
/// 0's table (`result`, the run's, and its steps) at the top and its teammates' in `teammates`;
/// `.csv` as the steps of every robot in one table (an `agent` column first), with the filament
/// snapshots beside it in `<stem>.filaments.csv` and the controllers' in
/// `<stem>.controller.csv`. Throws IoError naming the file.
void write_trace(const std::string& path, const Trace& trace, const Scenario& scenario,
                 const RunResult& result, const RunInfo& info);

/// Rounds a trace's filaments and wind grid as write_trace stores them in a `.json` trace (each
/// filament column to 16-bit steps over its range, the wind to 1e-6 m/s; the steps are stored
/// exactly), so that a view drawn from it equals one drawn from the file read back.
void round_as_stored(Trace& trace);

/// A run read back from a `.json` trace: what it ran, how it ended and what it recorded.
struct RecordedRun {
  Scenario scenario;    ///< the fully resolved scenario of the run
  RunResult result;     ///< its metrics (robot 0's: the run's)
  RunInfo info;         ///< algorithm, seed, trial and agent (of `result`'s robot)
  std::string version;  ///< the plumetrace version that wrote the trace
  Trace trace;          ///< every robot's steps, filament and controller snapshots
};

/// The largest trace file read (2 GiB): a run of 1e7 steps (kMaxSteps) with snapshots fits.
inline constexpr std::uint64_t kMaxTraceBytes = 2ull << 30;

/// Reads a trace written by write_trace as `.json`, of any format so far (formats 1 and 2 as one
/// robot, its start the first step's pose); throws IoError naming the file when it cannot be
/// read, ConfigError when it is not a plumetrace JSON trace (a `.csv` trace carries no
/// configuration and is refused with that reason).
RecordedRun read_trace(const std::string& path);

}  // namespace plumetrace
