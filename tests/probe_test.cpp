#include "plumetrace/sim/probe.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/env/environment.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/trace.hpp"

namespace plumetrace {
namespace {

// The probe options used below: 20 s warm-up, then 32 s sampled every 0.32 s (100 samples).
ProbeOptions corridor_options(std::uint64_t seed) {
  ProbeOptions options;
  options.warmup = 20.0;
  options.duration = 32.0;
  options.interval = 0.32;
  options.seed = seed;
  return options;
}

// Cross-sections 1, 7 and 14.5 m downwind of the source: on the axis, at 0.45 m (inside the
// printed-amount corridor, outside the default plume) and beyond both (docs/fidelity.md).
std::vector<Vec3> cross_sections() {
  std::vector<Vec3> points;
  for (const double x : {2.0, 8.0, 15.5}) {
    for (const double y : {0.0, 0.45, -0.45, 0.8, -0.8, 1.0, -1.0}) points.push_back({x, y, 0.0});
  }
  return points;
}

// The plume of the plugin-published reading: the printed amount 8.3e9 on the Gaussian kernel.
Scenario printed_amount_scenario() {
  Scenario s;
  s.plume.amount = 8.3e9;
  s.plume.sigma_p = 0.1;
  s.plume.kernel = Kernel::kGaussian;
  s.wind.velocity = {1.0, 0.0, 0.0};
  s.odor.height = 0.0;
  return s;
}

TEST(Probe, PrintedAmountPlumeIsASteadyCorridorWithSharpEdges) {
  const std::vector<Vec3> points = cross_sections();
  const auto results = probe_plume(printed_amount_scenario(), points, corridor_options(1));
  ASSERT_EQ(results.size(), points.size());
  for (const ProbeResult& r : results) {
    EXPECT_EQ(r.samples, 100);
    const bool inside = std::fabs(r.point.y) < 0.5;
    if (inside) {
      EXPECT_GE(r.detect_fraction, 0.9)
          << "x " << r.point.x << " y " << r.point.y << " mean " << r.mean_concentration;
    } else {
      EXPECT_LE(r.detect_fraction, 0.05)
          << "x " << r.point.x << " y " << r.point.y << " mean " << r.mean_concentration;
    }
  }
}

// The default plume as 0.3.0 had it (wind 0.9 m/s, sensor 0.02 m): the ring ends it short of the
// robot's start
TEST(Probe, DefaultPlumeIsANarrowIntermittentBandEndingNearTheRobotStart) {
  Scenario scenario;
  scenario.wind.velocity.x = 0.9;
  scenario.odor.height = 0.02;
  const std::vector<Vec3> points = cross_sections();
  const auto results = probe_plume(scenario, points, corridor_options(1));
  ASSERT_EQ(results.size(), points.size());
  for (const ProbeResult& r : results) {
    EXPECT_EQ(r.samples, 100);
    const std::string where = "x " + std::to_string(r.point.x) + " y " + std::to_string(r.point.y) +
                              " mean " + std::to_string(r.mean_concentration);
    if (r.point.y != 0.0) {
      // a single filament of amount 1 is below threshold: nothing 0.45 m off the axis
      EXPECT_LE(r.detect_fraction, 0.05) << where;
    } else if (r.point.x < 10.0) {
      // on the axis odor comes and goes: neither a steady corridor nor empty
      EXPECT_GE(r.detect_fraction, 0.1) << where;
      EXPECT_LE(r.detect_fraction, 0.8) << where;
    } else {
      // the ring's 16 s at 0.9 m/s end the plume about 15.4 m from the arena's upwind wall
      EXPECT_LE(r.detect_fraction, 0.3) << where;
    }
  }
}

TEST(Probe, SameSeedSameResult) {
  const Scenario scenario;
  const std::vector<Vec3> points{{2.0, 0.0, 0.0}, {5.0, 0.3, 0.0}, {8.0, -0.45, 0.0}};
  ProbeOptions options = corridor_options(7);
  options.duration = 10.0;
  const auto a = probe_plume(scenario, points, options);
  const auto b = probe_plume(scenario, points, options);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].samples, b[i].samples);
    EXPECT_EQ(a[i].detect_fraction, b[i].detect_fraction);
    EXPECT_EQ(a[i].mean_concentration, b[i].mean_concentration);
  }
  // another seed meets another plume
  options.seed = 8;
  const auto c = probe_plume(scenario, points, options);
  EXPECT_NE(a[0].mean_concentration, c[0].mean_concentration);
}

}  // namespace
}  // namespace plumetrace

namespace plumetrace {
namespace {

ProbeOptions short_options() {
  ProbeOptions options;
  options.warmup = 20.0;
  options.duration = 16.0;
  options.interval = 0.32;
  options.seed = 3;
  return options;
}

TEST(ProbeStatistics, TheDetectionMapIsTheProbeAtEveryCellCentre) {
  Scenario s;
  const MapGrid grid = arena_grid(s, 2.0, 0.5);
  ASSERT_EQ(grid.x.size(), 8u);  // arena 0..16 m by -2..2 m (docs/model.md section 1)
  ASSERT_EQ(grid.y.size(), 8u);
  EXPECT_DOUBLE_EQ(grid.z, s.odor.height);
  const auto map = detection_map(s, grid, short_options());
  std::vector<Vec3> points;
  for (const double y : grid.y) {
    for (const double x : grid.x) points.push_back({x, y, grid.z});
  }
  const auto direct = probe_plume(s, points, short_options());
  ASSERT_EQ(map.size(), grid.y.size());
  for (std::size_t j = 0; j < grid.y.size(); ++j) {
    ASSERT_EQ(map[j].size(), grid.x.size());
    for (std::size_t i = 0; i < grid.x.size(); ++i) {
      EXPECT_EQ(map[j][i], direct[j * grid.x.size() + i].detect_fraction);
    }
  }
}

TEST(ProbeStatistics, CentrelinesLeaveThePointsUnchangedAndFollowTheSource) {
  Scenario s;
  ProbeOptions options = short_options();
  const std::vector<Vec3> points{{2.0, 0.0, s.odor.height}, {6.0, 0.1, s.odor.height}};
  const auto alone = probe_plume(s, points, options);
  options.centreline_x = {3.0, 1000.0};
  const ProbeReport report = probe_report(s, points, options);
  ASSERT_EQ(report.points.size(), alone.size());
  for (std::size_t i = 0; i < alone.size(); ++i) {
    EXPECT_EQ(report.points[i].detect_fraction, alone[i].detect_fraction);
    EXPECT_EQ(report.points[i].mean_concentration, alone[i].mean_concentration);
  }
  // laminar wind along x: the centreline 2 m downwind stays on the source's y; the random walk
  // (sigma_p 0.02 m/s) spreads a slab's mean by far less than the source radius
  const CentrelineResult& near = report.centrelines[0];
  EXPECT_EQ(near.samples, 50);
  EXPECT_EQ(near.empty, 0);
  EXPECT_NEAR(near.mean_y, s.source.center.y, 0.02);
  EXPECT_GT(near.std_y, 0.0);
  EXPECT_LT(near.std_y, 0.05);
  // no filament ever reaches x = 1000 m
  EXPECT_EQ(report.centrelines[1].samples, 0);
  EXPECT_EQ(report.centrelines[1].empty, 50);
  EXPECT_TRUE(std::isnan(report.centrelines[1].mean_y));

  Scenario moved = s;
  moved.source.center.y = 0.7;
  moved.robot.start.y = 0.7;
  const auto shifted = probe_report(moved, points, options).centrelines[0];
  EXPECT_NEAR(shifted.mean_y, 0.7, 0.02);
}

TEST(ProbeStatistics, ABadSlabIsRefusedNamingTheOption) {
  Scenario s;
  ProbeOptions options = short_options();
  options.centreline_x = {3.0};
  options.centreline_slab = 0.0;
  try {
    probe_report(s, {}, options);
    FAIL() << "a slab of 0 m was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--slab"), std::string::npos) << e.what();
  }
}

// The filaments of a plume stepped `steps` times, as a trace snapshot holds them.
FilamentSnapshot snapshot_after(const Environment& env) {
  const FilamentSpans f = env.odor->snapshot().filaments;
  FilamentSnapshot snap;
  snap.x.assign(f.x.begin(), f.x.end());
  snap.y.assign(f.y.begin(), f.y.end());
  snap.z.assign(f.z.begin(), f.z.end());
  snap.w.assign(f.w.begin(), f.w.end());
  return snap;
}

// cells on, and cells where the mask and the model's own concentration() disagree (away from the
// threshold by more than the mask's stated 1e-9)
std::pair<long, long> compare_mask(const Scenario& s, const Environment& env, const MapGrid& grid,
                                   const std::vector<std::uint8_t>& mask) {
  long on = 0, wrong = 0;
  for (std::size_t j = 0; j < grid.y.size(); ++j) {
    for (std::size_t i = 0; i < grid.x.size(); ++i) {
      const double c = env.odor->concentration({grid.x[i], grid.y[j], grid.z});
      const bool perceived = mask[j * grid.x.size() + i] == 1;
      on += perceived;
      if (std::abs(c / s.odor.threshold - 1.0) > 1e-6 && perceived != (c >= s.odor.threshold)) {
        ++wrong;
      }
    }
  }
  return {on, wrong};
}

TEST(DetectionMask, IsWhereTheModelsConcentrationReachesTheThreshold) {
  // the default plume, and the printed-amount plume on the Gaussian kernel (wide and dense)
  for (const Scenario& s : {Scenario{}, printed_amount_scenario()}) {
    Environment env = make_environment(s, 3, 0);
    for (int k = 0; k < 1000; ++k) step(env, s.sim.dt);
    const MapGrid grid = arena_grid(s, 0.05, 0.05);
    const auto mask = detection_mask(s, snapshot_after(env), grid);
    ASSERT_EQ(mask.size(), grid.x.size() * grid.y.size());
    const auto [on, wrong] = compare_mask(s, env, grid, mask);
    EXPECT_EQ(wrong, 0);
    EXPECT_GT(on, 20) << "the region is not empty";
    EXPECT_LT(on, static_cast<long>(mask.size()) / 2) << "nor the whole arena";
  }
}

TEST(DetectionMask, OneFilamentPerceivedOutToItsAnalyticRadius) {
  // one filament of width w at height dz under the sensor: the printed kernel s/w^3 exp(-d/w^2)
  // reaches the threshold out to d = w^2 ln(s / (w^3 threshold)), so in the plane out to
  // sqrt(d^2 - dz^2)
  Scenario s;
  s.odor.threshold = 10.0;
  const double w = 0.2, dz = 0.05;
  FilamentSnapshot snap;
  snap.x = {3.0};
  snap.y = {0.4};
  snap.z = {s.odor.height - dz};
  snap.w = {w};
  const double d = w * w * std::log(s.plume.amount / (w * w * w * s.odor.threshold));
  const double r = std::sqrt(d * d - dz * dz);
  const MapGrid grid = arena_grid(s, 0.01, 0.01);
  const auto mask = detection_mask(s, snap, grid);
  long on = 0;
  for (std::size_t j = 0; j < grid.y.size(); ++j) {
    for (std::size_t i = 0; i < grid.x.size(); ++i) {
      const double rho = std::hypot(grid.x[i] - 3.0, grid.y[j] - 0.4);
      if (std::abs(rho - r) < 1e-9) continue;
      ASSERT_EQ(mask[j * grid.x.size() + i], rho < r ? 1 : 0) << grid.x[i] << ", " << grid.y[j];
      on += rho < r;
    }
  }
  // the disc's area in 1 cm cells, to within its rim
  EXPECT_NEAR(static_cast<double>(on), kPi * r * r / 1e-4, 2.0 * kPi * r / 1e-2);
}

}  // namespace
}  // namespace plumetrace
