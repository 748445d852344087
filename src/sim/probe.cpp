#include "plumetrace/sim/probe.hpp"

#include <algorithm>
#include <cmath>

#include "plumetrace/agent/sensors.hpp"
#include "plumetrace/env/environment.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

namespace {

double warmup_of(const ProbeOptions& options, const Scenario& scenario) {
  return std::isnan(options.warmup) ? scenario.sim.warmup : options.warmup;
}

}  // namespace

void check_probe_options(const ProbeOptions& options, const Scenario& scenario) {
  const double dt = scenario.sim.dt;
  static_assert(kMaxSteps == 1e7, "the message below names the limit");
  if (!((warmup_of(options, scenario) + options.duration) / dt <= kMaxSteps)) {
    throw ConfigError("--warmup, --duration: must be at most 1e7 steps of sim.dt together");
  }
  // why: compared before rounding, so that a huge interval never reaches lround
  if (!(options.interval <= options.duration) ||
      std::lround(options.duration / dt) < std::max(1L, std::lround(options.interval / dt))) {
    throw ConfigError("--duration: must be at least --interval, or no sample is taken");
  }
}

ProbeReport probe_report(const Scenario& scenario, const std::vector<Vec3>& points,
                         const ProbeOptions& options) {
  const double dt = scenario.sim.dt;
  check_probe_options(options, scenario);
  if (!(options.centreline_slab > 0.0) || !std::isfinite(options.centreline_slab)) {
    throw ConfigError("--slab: must be a positive number of metres");
  }
  Environment env = make_environment(scenario, options.seed, 0);
  const long warmup_steps = std::lround(warmup_of(options, scenario) / dt);
  const long steps = std::lround(options.duration / dt);
  const long every = std::max(1L, std::lround(options.interval / dt));

  ProbeReport report;
  report.points.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) report.points[i].point = points[i];
  // the centreline's y at each instant, summed and squared (per x)
  std::vector<double> sum(options.centreline_x.size()), sum2(options.centreline_x.size());
  report.centrelines.resize(options.centreline_x.size());
  for (std::size_t i = 0; i < options.centreline_x.size(); ++i) {
    report.centrelines[i].x = options.centreline_x[i];
  }
  const double half = options.centreline_slab / 2.0;
  for (long k = 0; k < warmup_steps + steps; ++k) {
    step(env, dt);
    const long since = k + 1 - warmup_steps;
    if (since <= 0 || since % every != 0) continue;
    for (auto& r : report.points) {
      const double c = env.odor->concentration(r.point);
      r.mean_concentration += c;
      if (perceives_odor(scenario.odor, c)) r.detect_fraction += 1.0;
      ++r.samples;
    }
    if (report.centrelines.empty()) continue;
    const OdorSnapshot snap = env.odor->snapshot();
    for (std::size_t i = 0; i < report.centrelines.size(); ++i) {
      auto& cl = report.centrelines[i];
      double y_sum = 0.0;
      long n = 0;
      if (snap.kind == OdorSnapshotKind::kFilaments) {
        for (std::size_t f = 0; f < snap.filaments.size(); ++f) {
          if (std::abs(snap.filaments.x[f] - cl.x) <= half) {
            y_sum += snap.filaments.y[f];
            ++n;
          }
        }
      }
      if (n == 0) {
        ++cl.empty;
        continue;
      }
      const double y = y_sum / static_cast<double>(n);
      sum[i] += y;
      sum2[i] += y * y;
      ++cl.samples;
    }
  }
  for (auto& r : report.points) {
    if (r.samples == 0) continue;
    r.mean_concentration /= static_cast<double>(r.samples);
    r.detect_fraction /= static_cast<double>(r.samples);
  }
  for (std::size_t i = 0; i < report.centrelines.size(); ++i) {
    auto& cl = report.centrelines[i];
    const auto n = static_cast<double>(cl.samples);
    if (cl.samples > 0) cl.mean_y = sum[i] / n;
    if (cl.samples > 1) {
      cl.std_y = std::sqrt(std::max(0.0, (sum2[i] - n * cl.mean_y * cl.mean_y) / (n - 1.0)));
    }
  }
  return report;
}

std::vector<ProbeResult> probe_plume(const Scenario& scenario, const std::vector<Vec3>& points,
                                     const ProbeOptions& options) {
  ProbeOptions only_points = options;
  only_points.centreline_x.clear();
  return probe_report(scenario, points, only_points).points;
}

MapGrid arena_grid(const Scenario& scenario, double dx, double dy) {
  const auto& a = scenario.arena;
  MapGrid grid;
  for (double x = a.x_min + dx / 2; x < a.x_max; x += dx) grid.x.push_back(x);
  for (double y = a.y_min + dy / 2; y < a.y_max; y += dy) grid.y.push_back(y);
  grid.z = scenario.odor.height;
  return grid;
}

std::vector<std::vector<double>> detection_map(const Scenario& scenario, const MapGrid& grid,
                                               const ProbeOptions& options) {
  std::vector<Vec3> points;
  for (const double y : grid.y) {
    for (const double x : grid.x) points.push_back({x, y, grid.z});
  }
  const auto results = probe_plume(scenario, points, options);
  std::vector<std::vector<double>> fraction(grid.y.size());
  for (std::size_t j = 0; j < grid.y.size(); ++j) {
    for (std::size_t i = 0; i < grid.x.size(); ++i) {
      fraction[j].push_back(results[j * grid.x.size() + i].detect_fraction);
    }
  }
  return fraction;
}

}  // namespace plumetrace
