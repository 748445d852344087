#include "lochmatter2008/calibration.hpp"

#include <algorithm>
#include <tuple>

#include "lochmatter2008/study.hpp"
#include "lochmatter2008/summary.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"

namespace plumetrace {

std::vector<std::string> experiment_set_names() {
  return set_names(read_sets(read_study(default_study_file())));
}

std::vector<ExpandedSweep> calibration_sweeps(const CalibrationOptions& options) {
  const std::vector<std::string> names =
      options.sets.empty() ? experiment_set_names() : options.sets;
  std::vector<ExpandedSweep> sweeps;
  for (const std::string& name : names) {
    SweepDef def = read_sweep_file(options.sets_dir + "/" + name + ".toml");
    if (options.seed != 0) def.seed = options.seed;
    if (options.runs > 0) def.runs = options.runs;
    sweeps.push_back(expand_sweep(def, options.overrides));
  }
  return sweeps;
}

CalibrationResult evaluate_sets(const CalibrationOptions& options) {
  const std::vector<ExpandedSweep> sweeps = calibration_sweeps(options);
  const std::vector<RunTask> tasks = missing_runs(sweeps, {}, 0);

  // every run, in memory
  CampaignOptions run_options;
  run_options.threads = options.threads;
  run_options.stop = options.stop;
  run_options.on_progress = options.on_progress;
  run_options.share_plumes = true;
  std::vector<RunRow> rows;
  rows.reserve(tasks.size());
  const CampaignResult ran = run_tasks(sweeps, tasks, run_options, [&rows](const auto& batch) {
    rows.insert(rows.end(), batch.begin(), batch.end());
  });

  CalibrationResult result;
  result.runs = ran.computed;
  result.elapsed = ran.elapsed;
  result.interrupted = static_cast<std::size_t>(ran.computed) < tasks.size();
  if (result.interrupted) return result;

  // why: a store hands its rows ordered by their run key; the same order makes the overhead
  // sums, hence the statistics, bit-identical to a store-based sweep's
  std::sort(rows.begin(), rows.end(),
            [](const RunRow& a, const RunRow& b) { return RunRow::key_of(a) < RunRow::key_of(b); });
  for (const ExpandedSweep& sweep : sweeps) {
    result.sets[sweep.def.name] = set_stats(sweep, rows, sweep.def.runs);
  }
  result.claims = evaluate_claims(result.sets);
  return result;
}

}  // namespace plumetrace
