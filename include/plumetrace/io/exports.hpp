#pragma once

#include <string>
#include <vector>

#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace {

/// Writes a campaign's exports into the folder `out` (which must exist): runs.csv, teams.csv
/// (always, so that no teams.csv of an earlier export is left beside other runs; a robot alone
/// is a team of one), summary.csv and results.json (results_io.hpp). Throws IoError naming the
/// file.
void write_exports(const std::string& out, const std::vector<ExpandedSweep>& sweeps,
                   const std::vector<RunRow>& rows, int runs_override);

/// Writes the exports of the results store `store` for the campaign `sweeps` into the folder
/// `out` (created if needed): the runs of its points the store holds (read_campaign_rows, which
/// throws StoreError for a store not made from these sweeps); returns the points with runs
/// missing.
std::vector<IncompletePoint> export_store(const std::string& store,
                                          const std::vector<ExpandedSweep>& sweeps,
                                          const std::string& out, int runs_override);

/// The points' success rates and mean overheads with their 95% intervals, one line each under
/// a header, as `plumetrace sweep` prints them.
std::string summary_table(const std::vector<ExpandedSweep>& sweeps, const std::vector<RunRow>& rows,
                          int runs_override);

}  // namespace plumetrace
