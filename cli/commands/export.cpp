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
  sub->add_option("sweeps", sweep_files, "the sweep files the store was made from")
      ->required()
      ->check(not_empty());
  sub->add_option("--store", store, "results store")->required()->check(not_empty());
  sub->add_option("--out", out, "output folder")->required()->check(not_empty());
  sub->add_option("--runs", runs, "runs per point (default: the sweep files')")
      ->check(whole_number(1, kMaxCampaignRuns));
  sub->add_option("--set", sets, "the --set overrides the sweep ran with (repeatable)")
      ->allow_extra_args(false);
  return sub;
}

int ExportCommand::run() {
  std::vector<ExpandedSweep> sweeps;
  for (const auto& f : sweep_files) {
    sweeps.push_back(expand_sweep(read_sweep_file(f), parse_sets(sets)));
  }
  warn_incomplete(sweeps, export_store(store, sweeps, out, runs), store, extra_options(sets, runs));
  return 0;
}

}  // namespace plumetrace::cli
