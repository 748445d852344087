#pragma once

#include <string>
#include <vector>

#include "plumetrace/experiment/store.hpp"
#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace {

/// Runs per point of a sweep: its own count, or `runs_override` when positive.
int runs_per_point(const ExpandedSweep& sweep, int runs_override);

/// One of `count` fixed, disjoint parts of a campaign (`index` from 1), for job arrays: trial t
/// of a point whose plume is the campaign's g-th distinct plume (plume_indices) belongs to part
/// (g + t) mod count + 1, so runs that share a plume stay together, every part gets its share
/// of every plume, and a part grows with the runs per point without changing what it held.
struct Shard {
  int index = 1;  ///< which part, 1..count
  int count = 1;  ///< how many parts
};

/// Parses "i/n" with 1 <= i <= n; throws ConfigError naming --shard.
Shard parse_shard(const std::string& text);

/// Where a campaign's store goes in its output folder OUT when no store is named:
/// OUT/results.sqlite, or for a shard OUT/part-I-of-N.sqlite (merged with plumetrace merge).
std::string default_store_path(const std::string& out, const Shard& shard);

/// "i/n", or "" for the whole campaign (1/1).
std::string shard_text(const Shard& shard);

/// For each sweep and point, the index of its plume (plume_key and master seed) among the
/// campaign's distinct plumes, numbered in campaign order.
std::vector<std::vector<int>> plume_indices(const std::vector<ExpandedSweep>& sweeps);

/// Checks a campaign before a store is opened (nothing is written then) and returns the number of
/// runs it defines (points times runs per point, over its sweeps). Throws ConfigError naming
/// both files when two of its sweeps share a name (a store keys runs by sweep name), and naming
/// the sweep file (or the sweeps) and the count when it is above kMaxCampaignRuns.
std::int64_t check_campaign(const std::vector<ExpandedSweep>& sweeps, int runs_override);

/// The (sweep, point, trial) runs of a campaign (of one shard of it) that `done` does not hold
/// with every robot of the point's team (agents 0 to team.count - 1), in campaign order; checks
/// the campaign first (check_campaign).
std::vector<RunTask> missing_runs(const std::vector<ExpandedSweep>& sweeps,
                                  const std::set<RunKey>& done, int runs_override,
                                  const Shard& shard = {});

/// Runs every missing run of the campaign (of `shard` of it) and stores it, in transactional
/// batches; a stopped call keeps everything already finished, and calling again computes only
/// what is missing. `runner` computes the runs (empty: run_tasks, the threads of this process).
/// The points and the runs asked for are recorded with the first runs, so that a call that
/// fails before any run (say, a runner that cannot start) leaves the store unchanged.
CampaignResult run_campaign(const std::vector<ExpandedSweep>& sweeps, Store& store,
                            int runs_override, const CampaignOptions& options,
                            const Shard& shard = {}, const TaskRunner& runner = {});

/// The stored results of one sweep point, trials 0..runs-1, every robot of each trial's team, in
/// the order of `rows` (runs beyond the current runs per point are left out, so a store run with
/// more trials can be reused).
std::vector<RunResult> point_runs(const std::vector<RunRow>& rows, const std::string& sweep,
                                  int point, int runs);

/// A point of a campaign with fewer stored runs than its sweep asks for.
struct IncompletePoint {
  std::string sweep;        ///< sweep name
  int point = 0;            ///< point index in the sweep
  std::string values;       ///< its axis values, "key = value, ..."
  std::int64_t stored = 0;  ///< runs stored (trials 0..runs-1 with every robot of the team)
  int runs = 0;             ///< runs per point asked
};

/// The points of a campaign with fewer runs in `rows` (numbered by the campaign's points) than
/// their sweep's runs per point, in campaign order; a run counts when `rows` hold every robot of
/// its team.
std::vector<IncompletePoint> incomplete_points(const std::vector<ExpandedSweep>& sweeps,
                                               const std::vector<RunRow>& rows, int runs_override);

}  // namespace plumetrace
