// The plumetrace command: parses arguments and calls the library; no model logic here.
#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "campaigns.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/distributed/distributed.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/sim/probe.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/trace.hpp"
#include "plumetrace/sim/world.hpp"
#include "plumetrace/view/viewer.hpp"
#include "validators.hpp"

namespace pt = plumetrace;
namespace cli = plumetrace::cli;

namespace {

using plumetrace::cli::kBadInput;

// the registered algorithms: "casting, surge-spiral or surge-cast"
std::string algorithm_names() {
  const auto all = pt::all_algorithms();
  std::string out;
  for (std::size_t i = 0; i < all.size(); ++i) {
    out += (i == 0 ? "" : i + 1 == all.size() ? " or " : ", ");
    out += pt::algorithm_name(all[i]);
  }
  return out;
}

// options every scenario-reading command shares
struct ScenarioOptions {
  std::string path;
  std::vector<std::string> sets;
  std::string algorithm;

  void add_to(CLI::App& cmd, bool with_algorithm) {
    cmd.add_option("scenario", path, "scenario TOML file (default: the paper's setup)")
        ->check(cli::not_empty());
    cmd.add_option("--set", sets, "override a config key: key.path=value (repeatable)")
        ->allow_extra_args(false);
    if (with_algorithm) {
      cmd.add_option("--algorithm", algorithm, algorithm_names())->check(cli::not_empty());
    }
  }

  pt::Scenario load() const {
    std::vector<pt::Setting> overrides;
    if (!algorithm.empty()) {
      overrides.push_back(
          {"controller.algorithm", algorithm, true, "--algorithm", pt::Layer::kCommandLine});
    }
    for (const auto& s : sets) overrides.push_back(pt::parse_override(s));
    return pt::load_scenario(path, overrides);
  }
};

// a whole number in [0, 2^64); CLI11 would wrap "-1" silently
std::uint64_t parse_u64(const std::string& option, const std::string& text) {
  std::uint64_t v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size()) {
    throw pt::ConfigError(
        option + ": must be a whole number from 0 to 18446744073709551615 (got '" + text + "')");
  }
  return v;
}

std::vector<pt::Vec3> parse_points(const std::string& text) {
  std::vector<pt::Vec3> points;
  std::stringstream all(text);
  std::string item;
  while (std::getline(all, item, ';')) {
    if (item.find_first_not_of(" \t") == std::string::npos) continue;
    double v[3];
    char extra;
    if (std::sscanf(item.c_str(), " %lf , %lf , %lf %c", &v[0], &v[1], &v[2], &extra) != 3 ||
        !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      throw pt::ConfigError("--points: '" + item + "' is not x,y,z");
    }
    points.push_back({v[0], v[1], v[2]});
  }
  if (points.empty()) throw pt::ConfigError("--points: no point given (expected \"x,y,z;...\")");
  return points;
}

std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

void print_human(const pt::RunResult& r, const pt::RunInfo& info) {
  std::cout << "plumetrace " << pt::version() << ": " << info.algorithm << ", seed " << info.seed
            << ", trial " << info.trial << "\n"
            << "  outcome   " << pt::outcome_name(r.outcome) << "\n"
            << "  time      " << fixed(r.time, 2) << " s\n"
            << "  d_t       " << fixed(r.d_t, 3) << " m (path length)\n"
            << "  d_u       " << fixed(r.d_u, 3) << " m (upwind displacement)\n"
            << "  overhead  " << fixed(r.overhead, 3) << " (d_t / d_u)\n"
            << "  losses    " << r.losses << "\n"
            << "  in odor   " << fixed(100.0 * r.odor_fraction, 1) << " % of steps\n";
}

}  // namespace

namespace plumetrace::cli {

int main(int argc, char** argv) {
  // why: past a file size limit (ulimit -f) a write then fails with EFBIG, which is reported
  // naming the file (exit 3), where SIGXFSZ would kill the process mid-write
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"plumetrace: odor plume tracking simulator and benchmark"};
  app.set_version_flag("--version", std::string(pt::version()));
  app.require_subcommand(1);

  // run
  auto* run = app.add_subcommand("run", "simulate one run and print its metrics");
  ScenarioOptions run_scn;
  run_scn.add_to(*run, true);
  std::string seed_text = "1", trial_text = "0";
  std::string trace_path;
  double snapshot_interval = 1.0;
  bool json_out = false;
  run->add_option("--seed", seed_text, "master seed (default 1)");
  run->add_option("--trial", trial_text, "trial index (default 0)");
  run->add_option("--trace", trace_path, "write the run's trace (.csv or .json)")
      ->check(cli::not_empty());
  run->add_option("--snapshot-interval", snapshot_interval,
                  "seconds between filament snapshots in the trace (0: none)")
      ->check(cli::finite_number(0.0));
  run->add_flag("--json", json_out, "print one JSON object");
  std::string run_view_path;
  run->add_option("--view", run_view_path,
                  "write the run's viewer (.html, animated) or figure (.svg); filaments every "
                  "0.25 s unless --snapshot-interval says otherwise")
      ->check(cli::not_empty());

  // view
  auto* view = app.add_subcommand("view", "draw a run from its .json trace: viewer or figure");
  std::string view_trace, view_out;
  pt::ViewerOptions view_opts;
  view->add_option("trace", view_trace, "trace written by: plumetrace run --trace FILE.json")
      ->required()
      ->check(cli::not_empty());
  view->add_option("-o,--output", view_out,
                   "FILE.html (animated viewer) or FILE.svg (static figure); default: the "
                   "trace's name with .html")
      ->check(cli::not_empty());
  view->add_option("--max-frames", view_opts.max_frames,
                   "most robot frames kept for the animation (default 12000)")
      ->check(cli::whole_number(1, std::numeric_limits<int>::max()));
  view->add_option("--max-snapshots", view_opts.max_snapshots,
                   "most filament snapshots kept (default 600)")
      ->check(cli::whole_number(1, std::numeric_limits<int>::max()));
  view->add_option("--at", view_opts.figure_time,
                   "time of the filaments drawn in an .svg figure (s; default: the end)")
      ->check(cli::finite_number(0.0));

  // probe
  auto* probe = app.add_subcommand("probe", "run the plume alone and sample it at points");
  ScenarioOptions probe_scn;
  probe_scn.add_to(*probe, false);
  std::string points_text;
  pt::ProbeOptions probe_opts;
  bool probe_json = false;
  probe->add_option("--points", points_text, "points \"x,y,z;x,y,z;...\" (m)")->required();
  probe
      ->add_option("--warmup", probe_opts.warmup,
                   "plume-only time before sampling (s; default sim.warmup)")
      ->check(cli::finite_number(0.0));
  probe->add_option("--duration", probe_opts.duration, "sampling time (s)")
      ->check(cli::finite_number(0.0, true));
  probe->add_option("--interval", probe_opts.interval, "time between samples (s)")
      ->check(cli::finite_number(0.0, true));
  std::string probe_seed_text = "1";
  probe->add_option("--seed", probe_seed_text, "master seed (default 1)");
  probe->add_flag("--json", probe_json, "print JSON");

  // config
  auto* config = app.add_subcommand("config", "print the fully resolved configuration");
  ScenarioOptions config_scn;
  config_scn.add_to(*config, true);
  bool config_json = false;
  config->add_flag("--json", config_json, "print JSON instead of TOML");

  pt::cli::SweepCommand sweep_cmd;
  auto* sweep = pt::cli::add_sweep_command(app, sweep_cmd);
  pt::cli::ExportCommand export_cmd;
  auto* export_sub = pt::cli::add_export_command(app, export_cmd);
  pt::cli::MergeCommand merge_cmd;
  auto* merge = pt::cli::add_merge_command(app, merge_cmd);
  pt::cli::ReproduceCommand reproduce_cmd;
  auto* reproduce = pt::cli::add_reproduce_command(app, reproduce_cmd);
  pt::cli::SensitivityCommand sensitivity_cmd;
  auto* sensitivity = pt::cli::add_sensitivity_command(app, sensitivity_cmd);
  for (int i = 0; i < argc; ++i) {
    reproduce_cmd.command_line += (i ? " " : "") + std::string(i ? argv[i] : "plumetrace");
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kBadInput;
  } catch (...) {
    return pt::cli::report_error(std::current_exception());
  }

  // the MPI job this process belongs to, if any: left (MPI_Finalize) when main returns, after any
  // error has been reported
  std::optional<pt::Ranks> ranks;
  try {
    if (!*sweep && pt::launched_ranks() > 1) {
      throw pt::ConfigError(
          "only plumetrace sweep runs across the processes of an MPI job; run this command "
          "without mpirun");
    }
    if (*run) {
      const pt::Scenario scenario = run_scn.load();
      const std::uint64_t seed = parse_u64("--seed", seed_text);
      const std::uint64_t trial = parse_u64("--trial", trial_text);
      // fail on an unwritable trace before spending the run
      if (!trace_path.empty()) pt::check_trace_path(trace_path);
      if (!run_view_path.empty()) pt::check_view_path(run_view_path, "--view");
      const pt::RunInfo info{std::string(pt::algorithm_name(scenario.controller.algorithm)), seed,
                             trial};
      pt::Trace trace;
      pt::StepObserver observer;
      if (!trace_path.empty() || !run_view_path.empty()) {
        const bool interval_given = run->get_option("--snapshot-interval")->count() > 0;
        // why: the viewer animates the plume, so it wants snapshots more often than a trace
        const double interval = run_view_path.empty() || interval_given ? snapshot_interval : 0.25;
        observer = pt::TraceRecorder(trace, interval, scenario.sim.dt);
      }
      const pt::RunResult result = pt::run_once(scenario, seed, trial, observer);
      // print the result before writing the trace, so a failing write loses nothing computed
      if (json_out) {
        std::cout << pt::result_to_json(result, info) << std::endl;
      } else {
        print_human(result, info);
      }
      if (!trace_path.empty()) {
        pt::write_trace(trace_path, trace, scenario, result, info);
        if (!json_out) std::cout << "  trace     " << trace_path << "\n";
      }
      if (!run_view_path.empty()) {
        const pt::RecordedRun recorded{scenario, result, info, std::string(pt::version()),
                                       std::move(trace)};
        pt::write_view(run_view_path, recorded, pt::ViewerOptions{});
        if (!json_out) std::cout << "  view      " << run_view_path << "\n";
      }
    } else if (*probe) {
      const pt::Scenario scenario = probe_scn.load();
      const auto points = parse_points(points_text);
      probe_opts.seed = parse_u64("--seed", probe_seed_text);
      const auto results = pt::probe_plume(scenario, points, probe_opts);
      if (probe_json) {
        std::cout << pt::probe_to_json(results) << std::endl;
      } else {
        std::cout << "       x        y        z   detect   mean C\n";
        for (const auto& r : results) {
          std::printf("%8.3f %8.3f %8.3f   %6.3f   %.4g\n", r.point.x, r.point.y, r.point.z,
                      r.detect_fraction, r.mean_concentration);
        }
      }
    } else if (*view) {
      if (view_out.empty()) {
        const std::filesystem::path p(view_trace);
        view_out = (p.parent_path() / p.stem()).string() + ".html";
      }
      const pt::RecordedRun recorded = pt::read_trace(view_trace);
      pt::check_view_path(view_out, "--output");
      pt::write_view(view_out, recorded, view_opts);
      std::cout << view_out << "\n";
    } else if (*config) {
      const pt::Scenario scenario = config_scn.load();
      std::cout << (config_json ? pt::scenario_to_json(scenario) + "\n"
                                : pt::scenario_to_toml(scenario));
    }
    if (*sweep) {
      ranks.emplace();
      return pt::cli::run_sweep_command(sweep_cmd, *ranks);
    }
    if (*export_sub) return pt::cli::run_export_command(export_cmd);
    if (*merge) return pt::cli::run_merge_command(merge_cmd);
    if (*reproduce) return pt::cli::run_reproduce_command(reproduce_cmd);
    if (*sensitivity) return pt::cli::run_sensitivity_command(sensitivity_cmd);
  } catch (...) {
    return pt::cli::report_error(std::current_exception());
  }
  return 0;
}

}  // namespace plumetrace::cli
