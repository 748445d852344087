#include "lochmatter2008/reproduce.hpp"

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <thread>

#include "campaign_run.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

CLI::App* ReproduceCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand(
      "reproduce", "run the paper's nine experiment sets and write the report (report.html)");
  std::string names = kDefaultReading;
  try {
    for (const auto& n : preset_names(read_study(default_study_file()).presets_dir)) {
      names += ", " + n;
    }
  } catch (const ConfigError&) {
    // why: the help names what it can; running says what is wrong with the study file
  }
  sub->add_option("--preset", preset,
                  "the main reading of what the paper leaves unsaid: " + names +
                      " (files studies/lochmatter2008/presets/NAME.toml; default: default, "
                      "the built-in defaults)")
      ->check(not_empty());
  sub->add_option("--presets", presets,
                  "the other readings whose nine sets are run too, for the claims columns, "
                  "comma-separated, or none (default: every preset file)")
      ->check(not_empty());
  sub->add_option("--runs", runs, "runs per value (default 50, as the paper)")
      ->check(whole_number(1, kMaxCampaignRuns));
  flags.add_to(*sub);
  return sub;
}

int ReproduceCommand::run() {
  const Study study = read_study(flags.study_file());
  // --presets: none, NAME,NAME,..., or every preset file when not given
  std::optional<std::vector<std::string>> others;
  if (!presets.empty()) {
    others.emplace();
    // why: "a,,b" or a trailing comma is a typo, not a request for fewer readings (G13)
    for (std::size_t start = 0; presets != "none" && start <= presets.size();) {
      const std::size_t comma = std::min(presets.find(',', start), presets.size());
      const std::string name = presets.substr(start, comma - start);
      if (name.empty()) throw ConfigError("--presets: empty name (in '" + presets + "')");
      others->push_back(name);
      start = comma + 1;
    }
  }
  const Reproduction plan = plan_reproduction(study, preset, others);
  check_campaign(plan.sweeps, runs);
  make_output_folder(flags.out, "--out");
  Store store(flags.out + "/results.sqlite", plan.sweeps, version(), flags.fresh);
  CampaignResult result;
  if (!run_with_progress("reproduce", plan.sweeps, store, runs, flags, result)) {
    return kInterrupted;
  }
  ReproduceInfo info;
  info.command = command_line;
  info.runs_override = runs;
  info.threads =
      flags.threads > 0 ? flags.threads : static_cast<int>(std::thread::hardware_concurrency());
  info.elapsed = result.elapsed;
  info.computed = result.computed;
  write_reproduction(flags.out, study, plan, store.rows(), info);
  if (const int rc = draw_report(flags.out)) return rc;
  std::printf(
      "%lld runs (%lld computed now in %.1f s, %lld from the store)\nreport: %s/report.html "
      "(and report.md)\n",
      static_cast<long long>(result.total), static_cast<long long>(result.computed), result.elapsed,
      static_cast<long long>(result.skipped), flags.out.c_str());
  return 0;
}

}  // namespace plumetrace::cli
