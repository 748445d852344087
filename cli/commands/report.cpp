#include <cstdio>
#include <filesystem>

#include "campaign_run.hpp"
#include "commands.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/io/exports.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

CLI::App* ReportCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand(
      "report",
      "draw the report of any sweep from a results store: two panels per sweep (success rate, "
      "overhead), the summary tables, and the points that have runs missing");
  from.add_to(*sub,
              "output folder: report.html, report.md, report.csv, figures/ and the exports "
              "(default: the store's folder)",
              false);
  return sub;
}

int ReportCommand::run() {
  const std::vector<ExpandedSweep> sweeps = from.sweeps();
  const auto& [sweep_files, store, out, runs, sets] = from;
  check_campaign(sweeps, runs);
  const std::vector<RunRow> rows = read_campaign_rows(store, sweeps);
  const auto incomplete = incomplete_points(sweeps, rows, runs);
  const std::string options = extra_options(sets, runs);
  if (rows.empty()) {
    std::string commands;
    for (const auto& s : sweeps) {
      commands += "\n  plumetrace sweep " + shell_word(s.def.file) + " --store " +
                  shell_word(store) + options;
    }
    throw ConfigError("results store '" + store +
                      "' holds no run of these sweeps' points: nothing to report; compute them "
                      "with" +
                      commands);
  }
  const std::filesystem::path parent = std::filesystem::path(store).parent_path();
  const std::string folder = !out.empty() ? out : parent.empty() ? "." : parent.string();
  make_output_folder(folder, out.empty() ? "the folder of --store" : "--out");
  write_exports(folder, sweeps, rows, runs);
  warn_incomplete(sweeps, incomplete, store, options);

  // what the report shows as the commands that redraw it and that compute the missing runs
  std::string files;
  for (const auto& f : sweep_files) files += " " + shell_word(f);
  std::vector<std::string> args{"--regenerate=plumetrace report" + files + " --store " +
                                shell_word(store) + " --out " + shell_word(folder) + options};
  for (const auto& s : sweeps) {
    args.push_back("--complete=plumetrace sweep " + shell_word(s.def.file) + " --store " +
                   shell_word(store) + options);
  }
  if (const int rc = draw_report(folder, "plumetrace.report.sweep", args)) return rc;
  std::printf(
      "report: %s/report.html (and report.md, report.csv, figures/)%s\n", folder.c_str(),
      incomplete.empty() ? "" : "; points with runs missing are marked (see the warning above)");
  return 0;
}

}  // namespace plumetrace::cli
