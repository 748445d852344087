#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/results_io.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

namespace {

// the non-blank items of "a;b;..."
std::vector<std::string> items(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream all(text);
  std::string item;
  while (std::getline(all, item, ';')) {
    if (item.find_first_not_of(" \t") != std::string::npos) out.push_back(item);
  }
  return out;
}

std::vector<Vec3> parse_points(const std::string& text) {
  std::vector<Vec3> points;
  for (const auto& item : items(text)) {
    double v[3];
    char extra;
    if (std::sscanf(item.c_str(), " %lf , %lf , %lf %c", &v[0], &v[1], &v[2], &extra) != 3 ||
        !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      throw ConfigError("--points: '" + item + "' is not x,y,z");
    }
    points.push_back({v[0], v[1], v[2]});
  }
  if (points.empty()) throw ConfigError("--points: no point given (expected \"x,y,z;...\")");
  return points;
}

// "v;v;..." as numbers (m); empty: none. `option` and `what` name them in a message.
std::vector<double> parse_numbers(const std::string& text, const std::string& option,
                                  const std::string& what) {
  std::vector<double> xs;
  for (const auto& item : items(text)) {
    double v;
    char extra;
    if (std::sscanf(item.c_str(), " %lf %c", &v, &extra) != 1 || !std::isfinite(v)) {
      throw ConfigError(option + ": '" + item + "' is not a number " + what + " (m)");
    }
    xs.push_back(v);
  }
  return xs;
}

// numbers as "a;b;..." for a help text
std::string joined(const std::vector<double>& v) {
  std::string out;
  for (const double x : v) out += (out.empty() ? "" : ";") + format_number(x);
  return out;
}

int print_plume_stats(const PlumeStats& st, bool json) {
  if (json) {
    std::cout << plume_stats_to_json(st) << std::endl;
    return 0;
  }
  // the fraction of a line's samples with odor; NaN without samples
  const auto odor_fraction = [](const auto& g) {
    return g.samples ? static_cast<double>(g.detections) / static_cast<double>(g.samples) : NAN;
  };
  std::printf("plume statistics: %d trials (seed %llu), d_lost %.3f m, sensor speed %.3f m/s\n",
              st.trials, static_cast<unsigned long long>(st.seed), st.d_lost, st.speed);
  std::cout << "along (upwind, start to source)\n"
               "  offset  odor   gaps  median    p90 longest  >=d_lost  first odor\n";
  for (const auto& a : st.along) {
    const auto& g = a.gaps;
    std::printf(
        "%8.3f %5.3f %6zu %7.3f %6.3f %7.3f  %8.3f  %10.3f\n", a.offset, odor_fraction(g),
        g.gaps.size(), g.median, g.p90, g.longest, g.fraction_longer, a.leading_median);
  }
  std::cout << "across (crosswind, wall to wall)\n"
               "    dist  odor   gaps  median longest  >=d_lost  band median  band max\n";
  for (const auto& c : st.across) {
    const auto& g = c.gaps;
    std::printf(
        "%8.3f %5.3f %6zu %7.3f %7.3f  %8.3f  %11.3f  %8.3f\n", c.distance, odor_fraction(g),
        g.gaps.size(), g.median, g.longest, g.fraction_longer, c.band_median, c.band_max);
  }
  const auto& r = st.release;
  std::printf("released in odor: %d of %d trials; odor within d_lost upwind: %d of %d\n", r.in_odor,
              r.trials, r.within_d_lost, r.trials);
  const auto& s = st.spirals;
  std::printf(
      "spirals: %d of %d surges lost the plume; odor within one turn: %d, at all: %d (no odor "
      "before a wall: %d, in %g turns: %d); median path to odor %.3f m\n",
      s.lost, s.surges, s.within_one_turn, s.reacquired, s.walls, st.turns, s.out_of_turns,
      s.distance_median);
  return 0;
}

}  // namespace

CLI::App* ProbeCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand("probe", "run the plume alone and sample it at points");
  scenario.add_to(*sub, false);
  auto* at = sub->add_option("--points", points, "points \"x,y,z;x,y,z;...\" (m)");
  sub->add_option("--warmup", options.warmup,
                  "plume-only time before sampling (s; default sim.warmup)")
      ->check(finite_number(0.0));
  auto* duration = sub->add_option("--duration", options.duration, "sampling time (s)")
                       ->check(finite_number(0.0, true));
  auto* interval = sub->add_option("--interval", options.interval, "time between samples (s)")
                       ->check(finite_number(0.0, true));
  sub->add_option("--seed", seed, "master seed, 0 to 2^64-1 (default 1)")
      ->type_name("UINT");  // why: kept as text and parsed by parse_u64, which names the option
  auto* line = sub->add_option(
      "--centreline", centreline,
      "downwind positions \"x;x;...\" (m) where the plume's centreline is measured: "
      "mean and spread of its lateral position");
  auto* slab =
      sub->add_option("--slab", options.centreline_slab,
                      "width along x of the filaments averaged for the centreline (m, default 0.2)")
          ->check(finite_number(0.0, true));
  auto* map_file =
      sub->add_option("--map", map,
                      "also write the detection map over the arena (0.2 x 0.05 m cells at the "
                      "sensor height) to this JSON file")
          ->check(not_empty());
  sub->add_flag("--json", json, "print JSON");
  // the plume's own statistics (docs/plume-statistics.md): virtual sensors on paths
  const PlumeStatsOptions d;
  auto* stats_flag = sub->add_flag(
      "--plume-stats", plume_stats,
      "instead of points: the plume's statistics seen by virtual sensors moving at the robot's "
      "speed (gaps between detections along and across the plume, release in odor, spiral "
      "reacquisition; docs/plume-statistics.md)");
  stats_flag->excludes(at)
      ->excludes(duration)
      ->excludes(interval)
      ->excludes(line)
      ->excludes(slab)
      ->excludes(map_file);
  std::vector<CLI::Option*> stats_only{
      sub->add_option("--trials", stats.trials,
                      "--plume-stats: plumes measured, trial k the plume of a run's trial k "
                      "(default " +
                          std::to_string(d.trials) + ")")
          ->check(whole_number(1, 1000)),
      sub->add_option("--threads", stats.threads, "--plume-stats: worker threads (default 1)")
          ->check(whole_number(1, 1024)),
      sub->add_option("--offsets", offsets,
                      "--plume-stats: lateral offsets from the source of the upwind lines "
                      "\"y;y;...\" (m, default " +
                          joined(d.offsets) + ")"),
      sub->add_option("--across", across,
                      "--plume-stats: distances downwind of the source of the crosswind lines "
                      "\"d;d;...\" (m, default " +
                          joined(d.across) + ")"),
      sub->add_option("--surges", stats.surges,
                      "--plume-stats: virtual surges per trial, each followed by a spiral where "
                      "it loses the plume (default " +
                          std::to_string(d.surges) + ")")
          ->check(whole_number(0, 1000)),
      sub->add_option("--turns", stats.turns,
                      "--plume-stats: turns of each spiral followed at most (default " +
                          format_number(d.turns) + ")")
          ->check(finite_number(0.0, true))};
  for (auto* o : stats_only) o->needs(stats_flag);
  return sub;
}

int ProbeCommand::run() {
  // why: the warnings are about the robot's start, which a probe has no use for
  const Scenario s = scenario.load(false);
  options.seed = parse_u64("--seed", seed);
  if (plume_stats) {
    stats.seed = options.seed;
    stats.warmup = options.warmup;
    if (!offsets.empty()) stats.offsets = parse_numbers(offsets, "--offsets", "y");
    if (!across.empty()) stats.across = parse_numbers(across, "--across", "d");
    return print_plume_stats(plumetrace::plume_stats(s, stats), json);
  }
  if (points.empty()) throw ConfigError("--points: required (\"x,y,z;...\"), or --plume-stats");
  const auto at = parse_points(points);
  options.centreline_x = parse_numbers(centreline, "--centreline", "x");
  if (!map.empty()) check_writable(map);
  const ProbeReport report = probe_report(s, at, options);
  if (json) {
    std::cout << probe_to_json(report) << std::endl;
  } else {
    // why: "detect" is the intermittency, the fraction of instants with odor
    std::cout << "       x        y        z   detect   mean C\n";
    for (const auto& r : report.points) {
      std::printf("%8.3f %8.3f %8.3f   %6.3f   %.4g\n", r.point.x, r.point.y, r.point.z,
                  r.detect_fraction, r.mean_concentration);
    }
    if (!report.centrelines.empty()) std::cout << "centreline x   mean y    std y  instants\n";
    for (const auto& c : report.centrelines) {
      std::printf("%11.3f %8.3f %8.3f  %ld of %ld\n", c.x, c.mean_y, c.std_y, c.samples,
                  c.samples + c.empty);
    }
  }
  if (!map.empty()) {
    const MapGrid grid = arena_grid(s);
    write_text_file(map, detection_map_to_json(grid, detection_map(s, grid, options)));
  }
  return 0;
}

}  // namespace plumetrace::cli
