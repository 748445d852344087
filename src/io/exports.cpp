#include "plumetrace/io/exports.hpp"

#include <filesystem>

#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/sweep_file.hpp"

namespace plumetrace {

void write_exports(const std::string& out, const std::vector<ExpandedSweep>& sweeps,
                   const std::vector<RunRow>& rows, int runs_override) {
  write_runs_csv(out + "/runs.csv", sweeps, rows);
  write_summary_csv(out + "/summary.csv", sweeps, rows, runs_override);
  write_results_json(out + "/results.json", sweeps, rows, runs_override);
}

void export_store(const std::string& store, const std::vector<ExpandedSweep>& sweeps,
                  const std::string& out, int runs_override) {
  std::string definition;
  const auto rows = read_store_rows(store, &definition);
  if (definition != campaign_definition(sweeps)) {
    throw StoreError("results store '" + store +
                     "' was not made from these sweep files (or with other --set overrides)");
  }
  std::filesystem::create_directories(out);
  write_exports(out, sweeps, rows, runs_override);
}

}  // namespace plumetrace
