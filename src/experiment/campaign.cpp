#include "plumetrace/experiment/campaign.hpp"

#include <map>
#include <set>

namespace plumetrace {

int runs_per_point(const ExpandedSweep& sweep, int runs_override) {
  return runs_override > 0 ? runs_override : sweep.def.runs;
}

std::string default_store_path(const std::string& out, const Shard& shard) {
  if (shard.count <= 1) return out + "/results.sqlite";
  return out + "/part-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count) +
         ".sqlite";
}

Shard parse_shard(const std::string& text) {
  Shard shard;
  const auto slash = text.find('/');
  const auto whole = [](const std::string& part, int& value) {
    if (part.empty() || part.size() > 9 || part.find_first_not_of("0123456789") != part.npos) {
      return false;
    }
    value = std::stoi(part);
    return true;
  };
  if (slash == std::string::npos || !whole(text.substr(0, slash), shard.index) ||
      !whole(text.substr(slash + 1), shard.count) || shard.count < 1 || shard.index < 1 ||
      shard.index > shard.count) {
    throw ConfigError("--shard: expected i/n with 1 <= i <= n, e.g. 2/8 (got '" + text + "')");
  }
  return shard;
}

std::string shard_text(const Shard& shard) {
  if (shard.count <= 1) return "";
  return std::to_string(shard.index) + "/" + std::to_string(shard.count);
}

std::vector<std::vector<int>> plume_indices(const std::vector<ExpandedSweep>& sweeps) {
  std::map<std::string, int> index_of;
  std::vector<std::vector<int>> out;
  for (const auto& sweep : sweeps) {
    auto& indices = out.emplace_back();
    for (const auto& p : sweep.points) {
      const std::string key = plume_key(p.scenario) + "/" + std::to_string(sweep.def.seed);
      const auto [it, added] = index_of.try_emplace(key, static_cast<int>(index_of.size()));
      indices.push_back(it->second);
    }
  }
  return out;
}

std::int64_t check_campaign(const std::vector<ExpandedSweep>& sweeps, int runs_override) {
  // why: a store keys its runs by sweep name; one name twice exported every run twice, and two
  // files of one name failed inside the store (issue 22, G10)
  std::map<std::string, const SweepDef*> by_name;
  for (const auto& s : sweeps) {
    const auto [it, added] = by_name.try_emplace(s.def.name, &s.def);
    if (added) continue;
    const std::string first = it->second->file.empty() ? "(given)" : it->second->file;
    const std::string second = s.def.file.empty() ? "(given)" : s.def.file;
    throw ConfigError(first == second
                          ? "sweep file '" + first + "' is given twice in one campaign"
                          : "sweep files '" + first + "' and '" + second +
                                "' both name their sweep '" + s.def.name +
                                "': the sweeps of one campaign (and store) need distinct names");
  }
  std::int64_t total = 0;
  for (const auto& s : sweeps) {
    // why: at most kMaxGridPoints points times at most 2^31 runs: no overflow
    total += static_cast<std::int64_t>(s.points.size()) * runs_per_point(s, runs_override);
  }
  if (total <= kMaxCampaignRuns) return total;
  std::string what = std::to_string(total) + " runs";
  if (sweeps.size() == 1) {
    const SweepDef& def = sweeps.front().def;
    what = (def.file.empty() ? "sweep " + def.name : def.file) + ": " +
           std::to_string(sweeps.front().points.size()) + " points x " +
           std::to_string(runs_per_point(sweeps.front(), runs_override)) + " runs = " + what;
  } else {
    what = "the " + std::to_string(sweeps.size()) + " sweeps define " + what;
  }
  throw ConfigError(what + ", more than the " + std::to_string(kMaxCampaignRuns) +
                    " one command may run (split the sweep, or use fewer runs per point)");
}

namespace {

// whether `done` holds trial t of point p with every robot of its team (a team's rows are stored
// together, but a merge may bring them from parts that each hold some)
bool stored(const std::set<RunKey>& done, const std::string& sweep, const SweepPoint& p,
            std::uint64_t t) {
  for (int agent = 0; agent < p.scenario.team.count; ++agent) {
    if (!done.count({sweep, p.index, t, agent})) return false;
  }
  return true;
}

}  // namespace

std::vector<RunTask> missing_runs(const std::vector<ExpandedSweep>& sweeps,
                                  const std::set<RunKey>& done, int runs_override,
                                  const Shard& shard) {
  check_campaign(sweeps, runs_override);
  const auto plumes = shard.count > 1 ? plume_indices(sweeps) : std::vector<std::vector<int>>{};
  std::vector<RunTask> tasks;
  for (std::size_t s = 0; s < sweeps.size(); ++s) {
    const int runs = runs_per_point(sweeps[s], runs_override);
    for (const auto& p : sweeps[s].points) {
      for (int trial = 0; trial < runs; ++trial) {
        const auto t = static_cast<std::uint64_t>(trial);
        if (shard.count > 1) {
          const auto g = static_cast<std::uint64_t>(plumes[s][static_cast<std::size_t>(p.index)]);
          if ((g + t) % static_cast<std::uint64_t>(shard.count) !=
              static_cast<std::uint64_t>(shard.index - 1)) {
            continue;
          }
        }
        if (stored(done, sweeps[s].def.name, p, t)) continue;
        tasks.push_back({static_cast<int>(s), p.index, t});
      }
    }
  }
  return tasks;
}

CampaignResult run_campaign(const std::vector<ExpandedSweep>& sweeps, Store& store,
                            int runs_override, const CampaignOptions& options, const Shard& shard,
                            const TaskRunner& runner) {
  const auto tasks = missing_runs(sweeps, store.keys(), runs_override, shard);
  // the points and the runs asked for are recorded with the first runs (or once the runner is
  // done), so that a campaign refused before its first run leaves the store as it was
  bool planned = false;
  const auto plan = [&] {
    if (planned) return;
    std::vector<std::pair<std::string, int>> runs;
    for (const auto& s : sweeps) runs.emplace_back(s.def.name, runs_per_point(s, runs_override));
    store.put_points(sweeps);
    store.put_plan(runs, shard_text(shard));
    planned = true;
  };
  const RowSink sink = [&](const std::vector<RunRow>& batch) {
    plan();
    store.insert(batch);
  };
  CampaignResult result =
      runner ? runner(sweeps, tasks, options, sink) : run_tasks(sweeps, tasks, options, sink);
  plan();
  const auto defined =
      static_cast<std::int64_t>(missing_runs(sweeps, {}, runs_override, shard).size());
  result.skipped = defined - static_cast<std::int64_t>(tasks.size());
  result.total = defined;
  result.interrupted = result.skipped + result.computed < defined;
  return result;
}

std::vector<RunResult> point_runs(const std::vector<RunRow>& rows, const std::string& sweep,
                                  int point, int runs) {
  std::vector<RunResult> out;
  for (const auto& r : rows) {
    if (r.sweep == sweep && r.point == point && r.trial < static_cast<std::uint64_t>(runs)) {
      out.push_back(r.result);
    }
  }
  return out;
}

std::vector<IncompletePoint> incomplete_points(const std::vector<ExpandedSweep>& sweeps,
                                               const std::vector<RunRow>& rows, int runs_override) {
  std::set<RunKey> done;
  for (const auto& r : rows) done.insert(run_key(r));
  std::vector<IncompletePoint> out;
  for (const auto& s : sweeps) {
    const int runs = runs_per_point(s, runs_override);
    for (const auto& p : s.points) {
      std::int64_t have = 0;
      for (int trial = 0; trial < runs; ++trial) {
        have += stored(done, s.def.name, p, static_cast<std::uint64_t>(trial)) ? 1 : 0;
      }
      if (have < runs) out.push_back({s.def.name, p.index, axis_values_text(s.def, p), have, runs});
    }
  }
  return out;
}

}  // namespace plumetrace
