#include "campaign_run.hpp"
#include "commands.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/exports.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

CLI::App* ExportCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand(
      "export", "write runs.csv, summary.csv and results.json from a results store");
  from.add_to(*sub, "output folder", true);
  return sub;
}

int ExportCommand::run() {
  const std::vector<ExpandedSweep> sweeps = from.sweeps();
  warn_incomplete(sweeps, export_store(from.store, sweeps, from.out, from.runs), from.store,
                  extra_options(from.sets, from.runs));
  return 0;
}

}  // namespace plumetrace::cli
