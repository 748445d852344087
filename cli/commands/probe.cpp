#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/io/results_io.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

namespace {

std::vector<Vec3> parse_points(const std::string& text) {
  std::vector<Vec3> points;
  std::stringstream all(text);
  std::string item;
  while (std::getline(all, item, ';')) {
    if (item.find_first_not_of(" \t") == std::string::npos) continue;
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
  sub->add_option("--seed", seed, "master seed (default 1)");
  sub->add_flag("--json", json, "print JSON");
  return sub;
}

int ProbeCommand::run() {
  const Scenario s = scenario.load();
  const auto at = parse_points(points);
  options.seed = parse_u64("--seed", seed);
  const auto results = probe_plume(s, at, options);
  if (json) {
    std::cout << probe_to_json(results) << std::endl;
  } else {
    std::cout << "       x        y        z   detect   mean C\n";
    for (const auto& r : results) {
      std::printf("%8.3f %8.3f %8.3f   %6.3f   %.4g\n", r.point.x, r.point.y, r.point.z,
                  r.detect_fraction, r.mean_concentration);
    }
  }
  return 0;
}

}  // namespace plumetrace::cli
