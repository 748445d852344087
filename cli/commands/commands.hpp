#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "errors.hpp"
#include "options.hpp"
#include "plumetrace/distributed/distributed.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/io/benchmark.hpp"
#include "plumetrace/sim/plume_stats.hpp"
#include "plumetrace/sim/probe.hpp"
#include "plumetrace/view/viewer.hpp"

// One struct per subcommand: its options, `add` (registers them) and `run` (after parsing).
namespace plumetrace::cli {

/// A subcommand of plumetrace.
class Command {
 public:
  virtual ~Command() = default;
  /// Registers the subcommand and its options on `app`; returns it.
  virtual CLI::App* add(CLI::App& app) = 0;
  /// Runs it after a successful parse; returns the exit code (errors are thrown).
  virtual int run() = 0;
  /// Whether it may run across the processes of an MPI job.
  virtual bool runs_on_ranks() const { return false; }
  /// What to change when it runs out of memory, for the message (issue 22, G8).
  virtual std::string memory_advice() const {
    return "lower plume.capacity or plume.release_rate, or raise the memory limit";
  }
};

/// `plumetrace run [SCENARIO] ...`: one run, its metrics, and its trace or view if asked.
struct RunCommand final : Command {
  ScenarioOptions scenario;
  std::string seed = "1";
  std::string trial = "0";
  std::string trace_path;
  double snapshot_interval = 1.0;
  CLI::Option* snapshot_option = nullptr;
  bool json = false;
  std::string view_path;

  CLI::App* add(CLI::App& app) override;
  int run() override;
};

/// `plumetrace view TRACE.json ...`: the viewer or the figure of a recorded run.
struct ViewCommand final : Command {
  std::string trace;
  std::string output;
  ViewerOptions options;

  CLI::App* add(CLI::App& app) override;
  int run() override;
  std::string memory_advice() const override {
    return "the trace is held in memory with its page: lower --max-frames and --max-snapshots, or "
           "view a shorter trace";
  }
};

/// `plumetrace probe [SCENARIO] --points ...`: the plume alone, sampled at points.
struct ProbeCommand final : Command {
  ScenarioOptions scenario;
  std::string points;
  ProbeOptions options;
  std::string seed = "1";
  bool json = false;
  std::string centreline;
  std::string map;
  bool plume_stats = false;
  PlumeStatsOptions stats;
  std::string offsets;
  std::string across;

  CLI::App* add(CLI::App& app) override;
  int run() override;
};

/// `plumetrace config [SCENARIO] ...`: the fully resolved configuration.
struct ConfigCommand final : Command {
  ScenarioOptions scenario;
  bool json = false;

  CLI::App* add(CLI::App& app) override;
  int run() override;
};

/// What a sweep command (or a benchmark) works on, read alike on every rank: its campaign, the
/// shard computed, and where the store and the exports go.
struct SweepPlan {
  std::string name;   ///< the sweep's (the suite's) name
  std::string label;  ///< "sweep NAME", "benchmark NAME": how messages name it
  std::string file;   ///< the file it was read from
  std::vector<ExpandedSweep> sweeps;
  Shard shard;
  std::string out;         ///< the exports' folder
  std::string store_path;  ///< the results store

  /// The progress bar's label: `label`, and the shard when there is one.
  std::string progress_label() const;
  /// Sets `out` (the option, else out/NAME) and `store_path` (the option, else OUT/results.sqlite
  /// or, for a shard, OUT/part-I-of-N.sqlite); throws ConfigError when NAME is no folder name.
  void place(const std::string& out_option, const std::string& store_option);
};

/// `plumetrace sweep SWEEP.toml ...`: a sweep file's grid of runs into a results store, across
/// the ranks under mpirun.
struct SweepCommand : Command {
  std::string file;
  int runs = 0;
  int threads = 0;
  std::string store;
  std::string out;
  std::vector<std::string> sets;
  bool quiet = false;
  bool fresh = false;
  bool no_share = false;
  std::string shard;
  /// The MPI job, joined by run() and left when the command is destroyed: after main has
  /// reported any error.
  std::optional<Ranks> ranks;

  CLI::App* add(CLI::App& app) override;
  int run() override;
  std::string memory_advice() const override { return kMemoryAdvice; }
  bool runs_on_ranks() const override { return true; }
  /// Registers the options a sweep and a benchmark share (--runs, --threads, --store, --out,
  /// --set, --shard, --quiet, --fresh, --no-share-plumes) on `sub`.
  void add_campaign_options(CLI::App& sub, const std::string& runs_help,
                            const std::string& set_help);
  /// Reads the files and plans the campaign (on every rank); throws ConfigError.
  virtual SweepPlan plan() const;
  /// After every run is in (on rank 0): the exports and what else the command writes, or for a
  /// shard what its store holds; `where` says on how many ranks it ran. Returns the exit code.
  virtual int finish(const SweepPlan& plan, const Store& store, const CampaignResult& result,
                     const std::string& where) const;
};

/// `plumetrace benchmark [SUITE] ...`: every chosen controller on every task of a suite, into a
/// results store (as a sweep: across the ranks under mpirun, or a shard), then the leaderboard
/// (docs/benchmark.md); `--compare A B` compares two results. A controller given as a .py file
/// hands the whole command to Python (python -m plumetrace.benchmark), which registers it.
struct BenchmarkCommand final : SweepCommand {
  std::vector<std::string> controllers;
  std::vector<std::string> tasks;
  bool only = false;
  bool no_leaderboard = false;
  std::vector<std::string> compare;
  bool allow_runs = false;
  /// The words after "benchmark" on the command line, handed to Python as they are.
  std::vector<std::string> words;

  BenchmarkCommand(int argc, char** argv);
  /// The options' choice of controllers, tasks, runs and settings.
  BenchmarkChoice choice() const;
  CLI::App* add(CLI::App& app) override;
  int run() override;
  SweepPlan plan() const override;
  int finish(const SweepPlan& plan, const Store& store, const CampaignResult& result,
             const std::string& where) const override;
};

/// `plumetrace export SWEEP.toml... --store FILE --out DIR`: a store's exports.
struct ExportCommand final : Command {
  StoredSweepOptions from;

  CLI::App* add(CLI::App& app) override;
  int run() override;
  std::string memory_advice() const override {
    return "the store's runs are read into memory: export on a machine with more memory";
  }
};

/// `plumetrace report SWEEP.toml... --store FILE [--out DIR]`: the report of any sweep.
struct ReportCommand final : Command {
  StoredSweepOptions from;

  CLI::App* add(CLI::App& app) override;
  int run() override;
  std::string memory_advice() const override {
    return "the store's runs are read into memory: report on a machine with more memory";
  }
};

/// `plumetrace merge PART... --store FILE`: the shards' stores into one.
struct MergeCommand final : Command {
  std::vector<std::string> parts;
  std::string store;

  CLI::App* add(CLI::App& app) override;
  int run() override;
  std::string memory_advice() const override {
    return "the parts' runs are read into memory: merge fewer parts at a time";
  }
};

/// `plumetrace reproduce ...`: the paper's study (studies/lochmatter2008) and its report.
struct ReproduceCommand final : Command {
  std::string preset = "default";
  std::string presets;
  std::string axes;
  int runs = 0;
  CampaignFlags flags;
  /// The command line, recorded in summary.json.
  std::string command_line;

  explicit ReproduceCommand(std::string line) : command_line(std::move(line)) {}
  CLI::App* add(CLI::App& app) override;
  int run() override;
  std::string memory_advice() const override { return kMemoryAdvice; }
};

/// `plumetrace sensitivity ...`: the study's sets under every sensitivity combination.
struct SensitivityCommand final : Command {
  int runs = 10;
  CampaignFlags flags;

  CLI::App* add(CLI::App& app) override;
  int run() override;
  std::string memory_advice() const override { return kMemoryAdvice; }
};

/// `plumetrace study FOLDER ...`: a study's sweep files as one campaign, its exports and report.
struct StudyCommand final : Command {
  std::string folder;
  int runs = 0;
  CampaignFlags flags;
  CLI::Option* out_option = nullptr;

  CLI::App* add(CLI::App& app) override;
  int run() override;
  std::string memory_advice() const override { return kMemoryAdvice; }
};

}  // namespace plumetrace::cli
