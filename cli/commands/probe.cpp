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

// "x;x;..." as numbers; empty: none
std::vector<double> parse_positions(const std::string& text) {
  std::vector<double> xs;
  for (const auto& item : items(text)) {
    double v;
    char extra;
    if (std::sscanf(item.c_str(), " %lf %c", &v, &extra) != 1 || !std::isfinite(v)) {
      throw ConfigError("--centreline: '" + item + "' is not a number x (m)");
    }
    xs.push_back(v);
  }
  return xs;
}

}  // namespace

CLI::App* ProbeCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand("probe", "run the plume alone and sample it at points");
  scenario.add_to(*sub, false);
  sub->add_option("--points", points, "points \"x,y,z;x,y,z;...\" (m)")->required();
  sub->add_option("--warmup", options.warmup,
                  "plume-only time before sampling (s; default sim.warmup)")
      ->check(finite_number(0.0));
  sub->add_option("--duration", options.duration, "sampling time (s)")
      ->check(finite_number(0.0, true));
  sub->add_option("--interval", options.interval, "time between samples (s)")
      ->check(finite_number(0.0, true));
  sub->add_option("--seed", seed, "master seed, 0 to 2^64-1 (default 1)")
      ->type_name("UINT");  // why: kept as text and parsed by parse_u64, which names the option
  sub->add_option("--centreline", centreline,
                  "downwind positions \"x;x;...\" (m) where the plume's centreline is measured: "
                  "mean and spread of its lateral position");
  sub->add_option("--slab", options.centreline_slab,
                  "width along x of the filaments averaged for the centreline (m, default 0.2)")
      ->check(finite_number(0.0, true));
  sub->add_option("--map", map,
                  "also write the detection map over the arena (0.2 x 0.05 m cells at the "
                  "sensor height) to this JSON file")
      ->check(not_empty());
  sub->add_flag("--json", json, "print JSON");
  return sub;
}

int ProbeCommand::run() {
  // why: the warnings are about the robot's start, which a probe has no use for
  const Scenario s = scenario.load(false);
  const auto at = parse_points(points);
  options.seed = parse_u64("--seed", seed);
  options.centreline_x = parse_positions(centreline);
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
