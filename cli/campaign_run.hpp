#pragma once

#include <string>
#include <vector>

#include "options.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace::cli {

/// Runs the campaign (or a shard of it) into `store` with a progress bar, Ctrl-C stopping it
/// between runs; false when interrupted, after saying how far it got.
bool run_with_progress(const std::string& label, const std::vector<ExpandedSweep>& sweeps,
                       Store& store, int runs, const CampaignFlags& flags, CampaignResult& result,
                       const Shard& shard = {}, const TaskRunner& runner = {});

/// Draws report.html and report.md from the results in OUT (python -m MODULE OUT; the paper's
/// report by default); returns 0, or kIoFailure after saying that it failed.
int draw_report(const std::string& out, const std::string& module = "plumetrace.report");

}  // namespace plumetrace::cli
