#include "plumetrace/sim/probe.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

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

namespace {

// the cells [first, last] of ascending centres c whose centre may lie within r of v
std::pair<std::size_t, std::size_t> cells_near(const std::vector<double>& c, double v, double r) {
  const auto first = std::lower_bound(c.begin(), c.end(), v - r);
  const auto last = std::upper_bound(first, c.end(), v + r);
  return {static_cast<std::size_t>(first - c.begin()), static_cast<std::size_t>(last - c.begin())};
}

}  // namespace

std::vector<std::uint8_t> detection_mask(const Scenario& scenario, const FilamentSnapshot& snapshot,
                                         const MapGrid& grid) {
  const std::size_t nx = grid.x.size(), ny = grid.y.size();
  const double threshold = scenario.odor.threshold;
  const double eps = 1e-9 * threshold;
  std::vector<double> c(nx * ny, 0.0);
  // why: each filament adds its kernel to the cells it reaches, rather than each cell summing
  // every filament, since a filament reaches a few dozen cells of the thousands
  for (std::size_t k = 0; k < snapshot.x.size(); ++k) {
    const double w = snapshot.w[k], dz = grid.z - snapshot.z[k];
    // why: the reach's own rounding is covered by a relative margin far above it
    const double r = kernel_reach(scenario.plume, w, eps) * (1.0 + 1e-9);
    if (!(r > std::abs(dz))) continue;
    const double r_xy = std::sqrt(r * r - dz * dz);
    const auto [i0, i1] = cells_near(grid.x, snapshot.x[k], r_xy);
    const auto [j0, j1] = cells_near(grid.y, snapshot.y[k], r_xy);
    for (std::size_t j = j0; j < j1; ++j) {
      const double dy = grid.y[j] - snapshot.y[k];
      for (std::size_t i = i0; i < i1; ++i) {
        const double dx = grid.x[i] - snapshot.x[k];
        c[j * nx + i] += kernel_value(scenario.plume, w, dx * dx + dy * dy + dz * dz);
      }
    }
  }
  std::vector<std::uint8_t> mask(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) mask[i] = perceives_odor(scenario.odor, c[i]) ? 1 : 0;
  return mask;
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
