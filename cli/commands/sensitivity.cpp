#include <cstdio>
#include <filesystem>

#include "campaign_run.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "lochmatter2008/reproduce.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

CLI::App* SensitivityCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand(
      "sensitivity",
      "rerun the nine sets under every noise mode, kernel and success radius; claims matrix");
  sub->add_option("--runs", runs, "runs per value (default 10)")
      ->check(whole_number(1, kMaxCampaignRuns));
  flags.add_to(*sub);
  return sub;
}

int SensitivityCommand::run() {
  const Study study = read_study(flags.study_file());
  const std::vector<ExpandedSweep> sweeps = sensitivity_campaign(study, runs);
  check_campaign(sweeps, runs);
  make_output_folder(flags.out, "--out");
  Store store(flags.out + "/sensitivity.sqlite", sweeps, version(), flags.fresh);
  CampaignResult result;
  if (!run_with_progress("sensitivity", sweeps, store, runs, flags, result)) return kInterrupted;
  const std::string md =
      write_sensitivity(flags.out, study, sweeps, store.rows(), runs, result.elapsed);
  std::fputs(md.c_str(), stdout);
  // a report already in the folder gains the matrix
  if (std::filesystem::exists(flags.out + "/summary.json")) return draw_report(flags.out);
  return 0;
}

}  // namespace plumetrace::cli
