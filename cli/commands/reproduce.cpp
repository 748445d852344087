#include "lochmatter2008/reproduce.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <optional>
#include <thread>
#include <vector>

#include "campaign_run.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

namespace {

// a comma-separated list of names given to `option`: none when not given (every one), an empty
// list for "none"; an empty name is refused (G13: "a,,b" is a typo, not fewer names)
std::optional<std::vector<std::string>> name_list(const std::string& text,
                                                  const std::string& option) {
  if (text.empty()) return std::nullopt;
  std::vector<std::string> names;
  for (std::size_t start = 0; text != "none" && start <= text.size();) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string name = text.substr(start, comma - start);
    if (name.empty()) throw ConfigError(option + ": empty name (in '" + text + "')");
    names.push_back(name);
    start = comma + 1;
  }
  return names;
}

}  // namespace

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
  sub->add_option("--axes", axes,
                  "the axis readings whose sets are run too under the main reading, for the "
                  "axes' claims columns, comma-separated, or none (default: every file "
                  "studies/lochmatter2008/axes/NAME.toml; docs/fidelity.md, \"The axes\")")
      ->check(not_empty());
  sub->add_option("--runs", runs, "runs per value (default 50, as the paper)")
      ->check(whole_number(1, kMaxCampaignRuns));
  flags.add_to(*sub);
  return sub;
}

int ReproduceCommand::run() {
  const Study study = read_study(flags.study_file());
  // --presets and --axes: none, NAME,NAME,..., or every file when not given
  const Reproduction plan = plan_reproduction(study, preset, name_list(presets, "--presets"),
                                              name_list(axes, "--axes"));
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
