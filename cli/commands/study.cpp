#include <cstdio>
#include <filesystem>

#include "campaign_run.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/io/exports.hpp"
#include "plumetrace/io/study_file.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

CLI::App* StudyCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand(
      "study", "run a study's sweep files as one campaign, export them and draw its report");
  sub->add_option("folder", folder, "the study's folder, holding study.toml (e.g. studies/meander)")
      ->required()
      ->check(not_empty());
  sub->add_option("--runs", runs, "runs per point (default: each sweep file's)")
      ->check(whole_number(1, kMaxCampaignRuns));
  sub->add_option("--threads", flags.threads, "worker threads (default: all cores)")
      ->check(whole_number(1, kMaxThreads));
  out_option = sub->add_option("--out", flags.out,
                               "output folder: store, exports and report (default: out/NAME)")
                   ->check(not_empty());
  sub->add_flag("--quiet", flags.quiet, "no progress bar");
  sub->add_flag("--fresh", flags.fresh,
                "discard every run the store holds (needed only when the base scenario, a --set or "
                "the seed changed; a sweep given more values keeps its stored runs)");
  sub->add_flag("--no-share-plumes", flags.no_share,
                "simulate the plume anew for every run (same results, slower)");
  return sub;
}

int StudyCommand::run() {
  const StudyFile study = read_study_file(folder);
  std::vector<ExpandedSweep> sweeps;
  for (const auto& file : study.sets) sweeps.push_back(expand_sweep(read_sweep_file(file), {}));
  check_campaign(sweeps, runs);
  // why: the name comes from a file; "../../escaped" must not lead out of out/ (issue 22, G3)
  if (out_option->count() == 0) flags.out = default_output_folder(study.name, study.file);
  make_output_folder(flags.out, out_option->count() ? "--out" : study.file + ": name");
  Store store(flags.out + "/results.sqlite", sweeps, version(), flags.fresh);
  CampaignResult result;
  if (!run_with_progress(study.name, sweeps, store, runs, flags, result)) return kInterrupted;
  write_exports(flags.out, sweeps, store.rows(), runs);
  std::printf("%s: %lld runs (%lld computed now in %.1f s)\nresults: %s/results.json\n",
              study.name.c_str(), static_cast<long long>(result.total),
              static_cast<long long>(result.computed), result.elapsed, flags.out.c_str());
  if (study.report.empty()) return 0;
  if (const int rc = draw_report(flags.out, study.report, {}, study.report_is_file)) return rc;
  std::printf("report: %s/report.html (and report.md)\n", flags.out.c_str());
  return 0;
}

}  // namespace plumetrace::cli
