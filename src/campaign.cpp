#include "plumetrace/campaign.hpp"

namespace plumetrace {

int runs_per_point(const ExpandedSweep& sweep, int runs_override) {
  return runs_override > 0 ? runs_override : sweep.def.runs;
}

std::vector<RunTask> missing_runs(const std::vector<ExpandedSweep>& sweeps,
                                  const std::set<RunKey>& done, int runs_override) {
  std::vector<RunTask> tasks;
  for (std::size_t s = 0; s < sweeps.size(); ++s) {
    const int runs = runs_per_point(sweeps[s], runs_override);
    for (const auto& p : sweeps[s].points) {
      for (int trial = 0; trial < runs; ++trial) {
        const auto t = static_cast<std::uint64_t>(trial);
        if (done.count({sweeps[s].def.name, p.index, t})) continue;
        tasks.push_back({static_cast<int>(s), p.index, t});
      }
    }
  }
  return tasks;
}

CampaignResult run_campaign(const std::vector<ExpandedSweep>& sweeps, Store& store,
                            int runs_override, const CampaignOptions& options) {
  store.put_points(sweeps);
  const auto done = store.keys();
  const auto tasks = missing_runs(sweeps, done, runs_override);
  CampaignResult result = run_tasks(sweeps, tasks, options,
                                    [&](const std::vector<RunRow>& batch) { store.insert(batch); });
  std::int64_t defined = 0;
  for (const auto& s : sweeps) {
    defined += static_cast<std::int64_t>(s.points.size()) * runs_per_point(s, runs_override);
  }
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

}  // namespace plumetrace
