#pragma once

#include <string>
#include <vector>

#include "plumetrace/experiment/store.hpp"
#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace {

/// Writes a campaign's exports into the folder `out` (which must exist): runs.csv,
/// summary.csv and results.json (results_io.hpp). Throws IoError naming the file.
void write_exports(const std::string& out, const std::vector<ExpandedSweep>& sweeps,
                   const std::vector<RunRow>& rows, int runs_override);

/// Writes the exports of the results store `store` into the folder `out` (created if needed),
/// after checking that the store was made from `sweeps`: throws StoreError when it was not.
void export_store(const std::string& store, const std::vector<ExpandedSweep>& sweeps,
                  const std::string& out, int runs_override);

/// The points' success rates and mean overheads with their 95% intervals, one line each under
/// a header, as `plumetrace sweep` prints them.
std::string summary_table(const std::vector<ExpandedSweep>& sweeps, const std::vector<RunRow>& rows,
                          int runs_override);

}  // namespace plumetrace
