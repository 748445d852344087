#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "plumetrace/probe.hpp"
#include "plumetrace/scenario.hpp"
#include "plumetrace/stats.hpp"
#include "plumetrace/sweep.hpp"
#include "plumetrace/trace.hpp"
#include "plumetrace/world.hpp"

namespace plumetrace {

/// A file that cannot be read or written; the message names the file.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The program version.
std::string_view version();

/// Every file this library writes is written whole or not at all: into `PATH.part`, renamed
/// over `PATH` once complete (a reader, or a process killed while writing, never sees half a
/// file; nothing is left behind on an error). Writes `text` to `path` so; throws IoError naming
/// the file.
void write_text_file(const std::string& path, std::string_view text);

/// Throws IoError naming `path` when it cannot be written (it tries, and leaves nothing behind).
void check_writable(const std::string& path);

/// The most dotted segments a key in a TOML file may have (config keys have two): deeper keys
/// are refused, naming the file and the key, before they are walked.
inline constexpr int kMaxKeyDepth = 16;

/// Reads a TOML scenario file into settings (one per key, in file order); throws ConfigError
/// naming the file when it cannot be read or is not valid TOML (with line and column).
std::vector<Setting> read_scenario_file(const std::string& path);

/// A reading of what the paper leaves unsaid (docs/fidelity.md): a preset file's keys, applied
/// on top of every experiment set as command-line-layer overrides.
struct Reading {
  std::string name;               ///< kDefaultReading or the preset file's name without .toml
  std::string file;               ///< the preset file (empty for kDefaultReading)
  std::vector<Setting> settings;  ///< its keys in file order, layer kCommandLine
};

/// The reading that adds nothing to the sets' own scenario (the built-in defaults).
inline constexpr const char* kDefaultReading = "default";

/// The names of the preset files (NAME.toml) in `folder`, sorted; none when it does not exist.
std::vector<std::string> preset_names(const std::string& folder);

/// Reads the reading `name`: kDefaultReading (no settings) or `folder`/NAME.toml, a partial
/// scenario file whose keys become command-line-layer settings. Every key is checked. Throws
/// ConfigError naming the unknown reading and the ones there are, or naming the file and key.
Reading read_reading(const std::string& folder, const std::string& name);

/// Builds the scenario from an optional file (empty path: defaults) and then the overrides.
Scenario load_scenario(const std::string& path, const std::vector<Setting>& overrides);

/// The fully resolved scenario as TOML that reads back to the same scenario.
std::string scenario_to_toml(const Scenario& scenario);

/// The fully resolved scenario as a JSON object, nested by table.
std::string scenario_to_json(const Scenario& scenario);

/// Identifies a run: what the trace and the JSON output carry besides the result.
struct RunInfo {
  std::string algorithm;    ///< algorithm name
  std::uint64_t seed = 0;   ///< master seed
  std::uint64_t trial = 0;  ///< trial index
};

/// One run's result as a JSON object (keys as documented for `plumetrace run --json`).
std::string result_to_json(const RunResult& result, const RunInfo& info);

/// Probe results as {"points": [...]}.
std::string probe_to_json(const std::vector<ProbeResult>& results);

/// Checks a trace path before a run: a .csv or .json name (ConfigError otherwise) whose files
/// can be created (IoError naming the file otherwise).
void check_trace_path(const std::string& path);

/// Writes a trace: `.json` as one object; `.csv` as the step table, with the filament
/// snapshots beside it in `<stem>.filaments.csv`. Throws IoError naming the file.
void write_trace(const std::string& path, const Trace& trace, const Scenario& scenario,
                 const RunResult& result, const RunInfo& info);

/// A run read back from a `.json` trace: what it ran, how it ended and what it recorded.
struct RecordedRun {
  Scenario scenario;    ///< the fully resolved scenario of the run
  RunResult result;     ///< its metrics
  RunInfo info;         ///< algorithm, seed and trial
  std::string version;  ///< the plumetrace version that wrote the trace
  Trace trace;          ///< steps and filament snapshots
};

/// Reads a trace written by write_trace as `.json`; throws IoError naming the file when it cannot
/// be read, ConfigError when it is not a plumetrace JSON trace (a `.csv` trace carries no
/// configuration and is refused with that reason).
RecordedRun read_trace(const std::string& path);

/// Reads a sweep file; throws ConfigError naming the file and the problem (unknown key, empty
/// axis, value of the wrong type, ...). The scenario path is resolved from the file's folder.
SweepDef read_sweep_file(const std::string& path);

/// The identity of a campaign (its sweeps, points and resolved configs; not the runs per point)
/// as canonical JSON: stores refuse to mix results of different definitions.
std::string campaign_definition(const std::vector<ExpandedSweep>& sweeps);

/// Writes one CSV row per stored run: sweep, point, one column per axis key (union over the
/// sweeps), trial, seed, config hash and every metric. Throws IoError naming the file.
void write_runs_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                    const std::vector<RunRow>& rows);

/// Writes one CSV row per sweep point with the statistics of docs/experiments.md over trials
/// 0..runs-1. Throws IoError naming the file.
void write_summary_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                       const std::vector<RunRow>& rows, int runs_override);

/// A file's path as results record it (results.json, summary.json): lexically normal ("./a/../b"
/// is "b") and, when it lies inside the current folder, relative to it; a path outside it is kept
/// as given. So results do not depend on how a path was spelled, and a path typed relative never
/// becomes an absolute path of this machine.
std::string recorded_path(const std::string& path);

/// Writes the sweeps, their points with statistics, and every run as one JSON document; each
/// sweep's file as recorded_path gives it.
void write_results_json(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                        const std::vector<RunRow>& rows, int runs_override);

}  // namespace plumetrace
