#pragma once

#include <string>
#include <vector>

#include "plumetrace/store.hpp"
#include "plumetrace/sweep.hpp"

namespace plumetrace {

/// Runs per point of a sweep: its own count, or `runs_override` when positive.
int runs_per_point(const ExpandedSweep& sweep, int runs_override);

/// The (sweep, point, trial) runs of a campaign that are not yet in `done`, in campaign order.
std::vector<RunTask> missing_runs(const std::vector<ExpandedSweep>& sweeps,
                                  const std::set<RunKey>& done, int runs_override);

/// Runs every missing run of the campaign and stores it, in transactional batches; a stopped
/// call keeps everything already finished, and calling again computes only what is missing.
CampaignResult run_campaign(const std::vector<ExpandedSweep>& sweeps, Store& store,
                            int runs_override, const CampaignOptions& options);

/// The stored runs of one sweep point, trials 0..runs-1, in trial order (runs beyond the
/// current runs per point are left out, so a store run with more trials can be reused).
std::vector<RunResult> point_runs(const std::vector<RunRow>& rows, const std::string& sweep,
                                  int point, int runs);

}  // namespace plumetrace
