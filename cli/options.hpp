#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace plumetrace::cli {

/// The options of every command that reads a scenario: the file, --set and --algorithm.
struct ScenarioOptions {
  std::string path;
  std::vector<std::string> sets;
  std::string algorithm;

  /// Registers them on `cmd` (--algorithm only `with_algorithm`).
  void add_to(CLI::App& cmd, bool with_algorithm);
  /// The scenario they say: the file, then --algorithm, then each --set in order; with `warn`,
  /// its warnings (scenario_warnings) go to stderr.
  Scenario load(bool warn = true) const;
};

/// Prints each of the scenario's warnings (scenario_warnings) on stderr, after `where`.
void print_warnings(const Scenario& scenario, const std::string& where = "");

/// Prints the warnings of the points of `sweeps` on stderr, each with its point's axis values;
/// at most a few points, then how many more warn.
void print_sweep_warnings(const std::vector<ExpandedSweep>& sweeps);

/// The flags `reproduce` and `sensitivity` share.
struct CampaignFlags {
  int threads = 0;
  std::string out = "out";
  std::string experiments;
  bool quiet = false;
  bool fresh = false;
  bool no_share = false;

  /// Registers them on a subcommand.
  void add_to(CLI::App& sub);
  /// The study file: study.toml in the --experiments folder, or the repository's.
  std::string study_file() const;
};

/// The options of the commands that read a store made from sweep files (export, report): the
/// sweep files, --store, --out, --runs and the --set values the sweep ran with.
struct StoredSweepOptions {
  std::vector<std::string> sweep_files;
  std::string store;
  std::string out;
  int runs = 0;
  std::vector<std::string> sets;

  /// Registers them on `sub`, --out with its help and required when `out_required`.
  void add_to(CLI::App& sub, const std::string& out_help, bool out_required);
  /// The sweeps the files and --set values say; without --set, the --set the store recorded
  /// for them (then kept in `sets`, for the commands a report shows), said on stderr.
  std::vector<ExpandedSweep> sweeps();
};

/// --set key=value texts as settings; throws ConfigError for one without '='.
std::vector<Setting> parse_sets(const std::vector<std::string>& sets);

/// A whole number in [0, 2^64) given to `option`; throws ConfigError naming it. why: CLI11
/// would wrap "-1" silently.
std::uint64_t parse_u64(const std::string& option, const std::string& text);

}  // namespace plumetrace::cli
