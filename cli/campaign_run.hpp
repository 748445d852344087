#pragma once

#include <string>
#include <vector>

#include "options.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "shell.hpp"

namespace plumetrace::cli {

/// Runs the campaign (or a shard of it) into `store` with a progress bar, Ctrl-C stopping it
/// between runs; false when interrupted, after saying how far it got.
bool run_with_progress(const std::string& label, const std::vector<ExpandedSweep>& sweeps,
                       Store& store, int runs, const CampaignFlags& flags, CampaignResult& result,
                       const Shard& shard = {}, const TaskRunner& runner = {});

/// The options that give a command these --set values and --runs (0: none), for a command a
/// user may paste: " --set 'a=1' --runs 20".
std::string extra_options(const std::vector<std::string>& sets, int runs);

/// Says on stderr which points of the campaign have runs missing in the store at `store`, and
/// the command that computes them (`sweep FILE --store STORE`, with `extra` options such as
/// --set); says nothing when every point is complete. At most 10 points are named per sweep.
void warn_incomplete(const std::vector<ExpandedSweep>& sweeps,
                     const std::vector<IncompletePoint>& incomplete, const std::string& store,
                     const std::string& extra);

/// The PYTHONPATH under which the command runs Python: the source's package, then this build's
/// copy with the compiled module.
std::string python_path();

/// Runs `python -P -m MODULE ARGS...` with python_path(); returns its exit status (as
/// run_program).
int run_python_module(const std::string& module, const std::vector<std::string>& args);

/// Draws report.html and report.md from the results in OUT (python -P -m MODULE OUT ARGS...;
/// the paper's report by default; with `is_file`, MODULE is a script: python -P FILE OUT ARGS);
/// returns 0, or kIoFailure after saying that it failed. why: -P keeps the current folder off
/// the module path, so that a file there named like a module is never run (issue 22, G4).
int draw_report(const std::string& out, const std::string& module = "plumetrace.report",
                const std::vector<std::string>& args = {}, bool is_file = false);

}  // namespace plumetrace::cli
