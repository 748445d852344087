#pragma once

#include <array>
#include <atomic>
#include <concepts>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

/// The most grid points one sweep may have: 1e5. why: every point's scenario is resolved,
/// hashed and stored before the first run (about 0.3 ms and 4 KB of store a point: 30 s and
/// 400 MB at the limit); a larger grid expanded for minutes without a word, and 16 axes of 16
/// values overflowed the count to 0 points (issue 13, F10).
inline constexpr std::int64_t kMaxGridPoints = 100'000;

/// The most runs one command may define, points times runs per point over all its sweeps (and so
/// the most runs per point): 1e7. why: the list of runs to do is built before the first run
/// (about 220 bytes a run: 2.2 GB at the limit) and the store and the exports hold every run; at
/// the default scenario's 0.15 s a run it is 17 core-days (issue 13, F3: 1e8 runs took 7 GB
/// and aborted).
inline constexpr std::int64_t kMaxCampaignRuns = 10'000'000;

/// One varied config key and its values.
struct Axis {
  /// Dotted config key.
  std::string key;
  /// Values in sweep order.
  std::vector<ConfigValue> values;
  /// Axis label for reports (defaults to the key).
  std::string label;
  /// The paper's fixed value of this parameter, if it is among the values (for reports).
  std::optional<ConfigValue> fixed;
};

/// A sweep: a base scenario, axes forming a grid, runs per point and a master seed.
struct SweepDef {
  /// Short name ("A"), unique within a campaign.
  std::string name;
  /// One-line title for reports.
  std::string title;
  /// Base scenario file (empty: built-in defaults), as resolved from the sweep file's folder.
  std::string scenario_path;
  /// The base scenario file's settings, in file order (read with the sweep file).
  std::vector<Setting> scenario_settings;
  /// Fixed settings applied on top of the base scenario (the sweep file's [set] table).
  std::vector<Setting> settings;
  /// Varied keys; several form a grid, the first varying slowest.
  std::vector<Axis> axes;
  /// Runs (trials 0..runs-1) per point.
  int runs = 10;
  /// Master seed of every run.
  std::uint64_t seed = 1;
  /// The file it was read from (for messages and reports).
  std::string file;
};

/// One grid point of a sweep with its fully resolved scenario.
struct SweepPoint {
  /// Index in the sweep's grid order.
  int index = 0;
  /// One value per axis.
  std::vector<ConfigValue> values;
  /// The resolved scenario.
  Scenario scenario;
  /// Hash of the resolved scenario (hex, scenario_hash), stored with every run.
  std::string config_hash;
};

/// A sweep with its points expanded.
struct ExpandedSweep {
  SweepDef def;                    ///< the definition
  std::vector<SweepPoint> points;  ///< grid points
  /// The overrides given with `--set` (or from Python) as KEY=VALUE texts, in order: a store
  /// records them, so that exporting it needs them not again (issue 22).
  std::vector<std::string> sets;
};

/// The number of grid points of a sweep (the product of its axes' sizes, computed without
/// overflow); throws ConfigError naming the file and the count when it is above kMaxGridPoints.
std::int64_t grid_points(const SweepDef& def);

/// Expands a sweep into its grid points (none before grid_points has checked their number);
/// `overrides` (--set) apply after the sweep's own settings and may not name an axis key. Throws
/// ConfigError naming the sweep, axis and value.
ExpandedSweep expand_sweep(const SweepDef& def, const std::vector<Setting>& overrides);

/// The identity of a campaign as canonical JSON: each sweep's name, master seed, axes and the
/// hash of every point's resolved scenario (not the runs per point).
std::string campaign_definition(const std::vector<ExpandedSweep>& sweeps);

/// A point's axis values as a store records them: "key = value, ..." in axis order.
std::string axis_values_text(const SweepDef& def, const SweepPoint& point);

/// FNV-1a 64-bit hash of a text, as 16 hex digits.
std::string hash_text(const std::string& text);

/// What identifies a run of a scenario, a sweep point's config_hash: the hash of its canonical
/// values (canonical_config with ConfigKeys::kOfTheRun), not of its TOML, so that editing a
/// key's help or a comment changes no hash.
std::string scenario_hash(const Scenario& scenario);

/// What identifies a plume: every config key it depends on and its wind field's identity
/// (wind_identity), hashed from their canonical values (runs whose scenarios share this key and
/// whose (seed, trial) match meet bit for bit the same plume).
std::string plume_key(const Scenario& scenario);

/// Runs several teams in one shared environment, a World of one team per scenario (docs/model.md
/// section 10: the plume does not depend on the robots); every scenario must have the same
/// plume_key. The results, every team's robots in order, equal run_team of each scenario, bit
/// for bit.
std::vector<RunResult> run_shared(const std::vector<const Scenario*>& scenarios, std::uint64_t seed,
                                  std::uint64_t trial, const ControllerFactory& factory = {});

/// The names of the run key's columns, in order: what identifies a row of a campaign in every
/// format (RunRow::key_fields gives their values).
inline constexpr std::array<std::string_view, 4> kRunKeyFields{"sweep", "point", "trial", "agent"};

/// One robot's run of a campaign and its result.
struct RunRow {
  std::string sweep;        ///< sweep name
  int point = 0;            ///< point index in the sweep
  std::uint64_t trial = 0;  ///< trial index
  int agent = 0;            ///< the robot's index in its team (0 for a robot alone)
  std::string config_hash;  ///< hash of the point's resolved scenario (scenario_hash)
  RunResult result;         ///< metrics (with seed, trial and agent)

  /// The run key's members, in kRunKeyFields order, as a tuple of references: orders and
  /// compares rows (`RunRow::key_of(a) < RunRow::key_of(b)`).
  template <class Row>
  requires std::same_as<std::remove_const_t<Row>, RunRow>
  static auto key_of(Row& r) { return std::tie(r.sweep, r.point, r.trial, r.agent); }

  /// The one list of the run key, in column order: calls `v(name, value)` for sweep, point,
  /// trial and agent. The store's runs table (its columns, primary key and order), runs.csv,
  /// teams.csv, the row message and the Python columns take their key columns from it.
  template <class Row, class Visitor>
  requires std::same_as<std::remove_cvref_t<Row>, RunRow>
  static void key_fields(Row&& r, Visitor&& v) {
    std::apply(
        [&](auto&... member) {
          std::size_t k = 0;
          (v(kRunKeyFields[k++], member), ...);
        },
        key_of(r));
  }
};

static_assert(std::tuple_size_v<decltype(RunRow::key_of(std::declval<const RunRow&>()))> ==
                  kRunKeyFields.size(),
              "every member of the run key has a name");

/// Identifies a row of a campaign: the values of its run key (RunRow::key_of).
using RunKey = std::tuple<std::string, int, std::uint64_t, int>;

/// The run key of a row.
inline RunKey run_key(const RunRow& r) { return RunRow::key_of(r); }

/// The runs (tasks) whose rows these are: a task yields one row per robot of its team, robot 0
/// among them, so its rows count once however many robots it has.
std::int64_t runs_of(const std::vector<RunRow>& rows);

/// Progress of a campaign.
struct Progress {
  std::int64_t done = 0;   ///< runs finished in this call
  std::int64_t total = 0;  ///< runs to do in this call
  double elapsed = 0.0;    ///< seconds since the start of this call
};

/// The most worker threads a campaign may ask for (--threads, threads=). why: runs are
/// CPU-bound, so threads beyond the hardware threads only add a World's memory each; the largest
/// machines have 768 hardware threads, and per-user thread limits (ulimit -u) are often 4096.
inline constexpr int kMaxThreads = 1024;

/// How to run a campaign.
struct CampaignOptions {
  /// Worker threads (0: all cores; at most kMaxThreads).
  int threads = 0;
  /// Set from outside (a signal handler) to stop dispatching new runs.
  const std::atomic<bool>* stop = nullptr;
  /// Called from the calling thread about every `progress_interval` seconds and at the end.
  std::function<void(const Progress&)> on_progress;
  /// Seconds between progress calls and between store commits.
  double progress_interval = 0.25;
  /// Simulate one plume per (plume configuration, seed, trial) and drive every robot that uses
  /// it on it (results are bit-identical to separate runs; only faster).
  bool share_plumes = true;
  /// Builds each run's controller (empty: the scenario's built-in algorithm). It is called
  /// from the worker threads.
  ControllerFactory make_controller;
};

/// What a campaign call did, in runs: a run is one trial of a point, every robot of its team
/// (one row per robot).
struct CampaignResult {
  std::int64_t total = 0;     ///< runs the campaign defines
  std::int64_t skipped = 0;   ///< already in the store
  std::int64_t computed = 0;  ///< computed and stored by this call
  bool interrupted = false;   ///< stopped before all were computed
  double elapsed = 0.0;       ///< seconds
};

/// Where finished runs go: called from the calling thread with batches, in any order.
using RowSink = std::function<void(const std::vector<RunRow>&)>;

/// A run to do: sweep index, point index, trial.
struct RunTask {
  int sweep = 0;            ///< index into the campaign's sweeps
  int point = 0;            ///< point index
  std::uint64_t trial = 0;  ///< trial index
};

/// Runs the tasks on `threads` workers and hands results to `sink` in batches; each run is a
/// pure function of its (point, trial), so the rows do not depend on the thread count. Throws
/// ConfigError for threads outside 0..kMaxThreads; when a run throws (a controller's error), the
/// rows finished before are handed to `sink`, then the run's exception is rethrown here.
CampaignResult run_tasks(const std::vector<ExpandedSweep>& sweeps,
                         const std::vector<RunTask>& tasks, const CampaignOptions& options,
                         const RowSink& sink);

/// Something that computes a campaign's tasks and hands their rows to a sink, as run_tasks does
/// with the threads of this process (the distributed runner does it across processes).
using TaskRunner =
    std::function<CampaignResult(const std::vector<ExpandedSweep>&, const std::vector<RunTask>&,
                                 const CampaignOptions&, const RowSink&)>;

/// Tasks that meet one plume: the same plume configuration, master seed and trial.
using TaskGroup = std::vector<RunTask>;

/// Groups tasks by the plume they meet (plume_key, master seed, trial), groups in the order of
/// their first task; with `share` false every task is a group of its own.
std::vector<TaskGroup> plume_groups(const std::vector<ExpandedSweep>& sweeps,
                                    const std::vector<RunTask>& tasks, bool share);

/// Where there are fewer groups than `wanted`, splits each into parts so that every worker has
/// work (each part simulates its plume again: the same rows, more work); otherwise unchanged.
std::vector<TaskGroup> split_groups(std::vector<TaskGroup> groups, std::size_t wanted);

/// The groups a runner of `workers` workers queues: plume_groups, split (split_groups, to twice
/// the workers) only where there are fewer groups than workers. With a group for every worker to
/// start with, none is split: a part simulates its plume again, which costs more than the last
/// wave's idle workers (docs/performance.md, "Scaling past two cores").
std::vector<TaskGroup> work_groups(const std::vector<ExpandedSweep>& sweeps,
                                   const std::vector<RunTask>& tasks, bool share,
                                   std::size_t workers);

/// Runs a group on one shared plume: its rows in task order, each task's robots in index order.
std::vector<RunRow> run_group(const std::vector<ExpandedSweep>& sweeps, const TaskGroup& group,
                              const ControllerFactory& factory);

/// Worker threads that run task groups from a queue as they are added; the caller takes the
/// finished rows. A class because the threads, the queue and the counts change together.
class GroupPool {
 public:
  /// Rows taken from the pool, and whether it had nothing left to do when they were taken.
  struct Batch {
    std::vector<RunRow> rows;  ///< rows finished since the last take
    bool idle = false;         ///< nothing queued (or stopped) and nothing running
    std::exception_ptr error;  ///< the first exception a group threw (the pool then stopped)
  };

  /// Starts `threads` workers over `sweeps` (which must outlive the pool); `stop` (may be null)
  /// is read before each group is started. Throws std::system_error naming the thread count
  /// when the system cannot start them all (the ones started are joined first).
  GroupPool(const std::vector<ExpandedSweep>& sweeps, int threads, ControllerFactory factory,
            const std::atomic<bool>* stop);
  /// Drops the groups not started, lets running ones finish and joins the workers.
  ~GroupPool();
  GroupPool(const GroupPool&) = delete;
  GroupPool& operator=(const GroupPool&) = delete;

  /// Queues groups behind those already queued.
  void add(std::vector<TaskGroup> groups);
  /// Groups queued and not yet started.
  std::size_t queued() const;
  /// Waits until the pool is idle or `timeout` (s) has passed, then takes the finished rows.
  Batch take(double timeout);
  /// Starts no further group; running ones finish.
  void stop();

 private:
  bool stopped() const;
  bool idle() const;
  void work();

  const std::vector<ExpandedSweep>& sweeps_;
  ControllerFactory factory_;
  const std::atomic<bool>* external_stop_;
  mutable std::mutex mutex_;
  std::condition_variable work_ready_;
  std::condition_variable changed_;
  std::deque<TaskGroup> queue_;
  std::vector<RunRow> rows_;
  int running_ = 0;
  std::exception_ptr error_;
  bool stop_ = false;
  bool closed_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace plumetrace
