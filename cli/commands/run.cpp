#include <cmath>
#include <cstdio>
#include <iostream>
#include <vector>

#include "commands.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/sim/trace.hpp"
#include "plumetrace/sim/world.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

namespace {

std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

void print_human(const RunResult& r, const RunInfo& info, int team) {
  std::cout << "plumetrace " << version() << ": " << info.algorithm << ", seed " << info.seed
            << ", trial " << info.trial;
  if (team > 1) std::cout << ", robot " << r.agent << " of " << team;
  std::cout << "\n"
            << "  outcome   " << outcome_name(r.outcome) << "\n"
            << "  time      " << fixed(r.time, 2) << " s\n"
            << "  d_t       " << fixed(r.d_t, 3) << " m (path length)\n"
            << "  d_u       " << fixed(r.d_u, 3) << " m (upwind displacement)\n"
            << "  overhead  " << fixed(r.overhead, 3) << " (d_t / d_u)\n"
            << "  losses    " << r.losses << "\n"
            << "  in odor   " << fixed(100.0 * r.odor_fraction, 1) << " % of steps\n";
  if (!std::isnan(r.declaration_error)) {
    std::cout << "  declared  " << fixed(r.declaration_error, 3) << " m from the source\n";
  }
}

}  // namespace

CLI::App* RunCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand("run", "simulate one run and print its metrics");
  scenario.add_to(*sub, true);
  sub->add_option("--seed", seed, "master seed, 0 to 2^64-1 (default 1)")
      ->type_name("UINT");  // why: kept as text and parsed by parse_u64, which names the option
  sub->add_option("--trial", trial, "trial index, 0 to 2^64-1 (default 0)")->type_name("UINT");
  sub->add_option("--trace", trace_path, "write the run's trace (.csv or .json)")
      ->check(not_empty());
  snapshot_option = sub->add_option("--snapshot-interval", snapshot_interval,
                                    "seconds between filament snapshots in the trace (0: none)")
                        ->check(finite_number(0.0));
  sub->add_flag("--json", json, "print one JSON object");
  sub->add_option("--view", view_path,
                  "write the run's viewer (.html, animated) or figure (.svg); filaments every "
                  "0.25 s unless --snapshot-interval says otherwise")
      ->check(not_empty());
  return sub;
}

int RunCommand::run() {
  const Scenario s = scenario.load();
  const std::uint64_t seed_value = parse_u64("--seed", seed);
  const std::uint64_t trial_value = parse_u64("--trial", trial);
  // fail on an unwritable trace before spending the run
  if (!trace_path.empty()) check_trace_path(trace_path);
  if (!view_path.empty()) check_view_path(view_path, "--view");
  const RunInfo info{std::string(algorithm_name(s.controller.algorithm)), seed_value, trial_value};
  Trace trace;
  StepObserver observer;
  if (!trace_path.empty() || !view_path.empty()) {
    // why: the viewer animates the plume, so it wants snapshots more often than a trace
    const double interval =
        view_path.empty() || snapshot_option->count() > 0 ? snapshot_interval : 0.25;
    observer = TraceRecorder(trace, interval, s.sim.dt);
  }
  const std::vector<RunResult> results = run_team(s, seed_value, trial_value, observer);
  const RunResult& result = results.front();
  // print the results before writing the trace, so a failing write loses nothing computed; a
  // robot alone prints what it always did, a team one line (JSON) or block per robot
  for (const RunResult& r : results) {
    RunInfo robot = info;
    robot.agent = r.agent;
    // a robot of a mixed team names its own algorithm
    if (std::string own = own_algorithm(s, r.agent); !own.empty()) robot.algorithm = own;
    if (json) {
      std::cout << result_to_json(r, robot) << std::endl;
    } else {
      print_human(r, robot, s.team.count);
    }
  }
  if (!trace_path.empty()) {
    write_trace(trace_path, trace, s, result, info);
    if (!json) std::cout << "  trace     " << trace_path << "\n";
  }
  if (!view_path.empty()) {
    // why: the page is the one `plumetrace view` draws from the trace file
    round_as_stored(trace);
    const RecordedRun recorded{s, result, info, std::string(version()), std::move(trace)};
    write_view(view_path, recorded, ViewerOptions{});
    if (!json) std::cout << "  view      " << view_path << "\n";
  }
  return 0;
}

}  // namespace plumetrace::cli
