#include "plumetrace/probe.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "plumetrace/geometry.hpp"
#include "plumetrace/scenario.hpp"

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

// Cross-sections 1, 7 and 14.5 m downwind of the source: on the axis, well inside the corridor,
// and beyond its edge at about 0.55 m (SPEC section 2).
std::vector<Vec3> cross_sections() {
  std::vector<Vec3> points;
  for (const double x : {2.0, 8.0, 15.5}) {
    for (const double y : {0.0, 0.45, -0.45, 0.8, -0.8, 1.0, -1.0}) points.push_back({x, y, 0.0});
  }
  return points;
}

TEST(Probe, DefaultPlumeIsASteadyCorridorWithSharpEdges) {
  const Scenario scenario;
  const std::vector<Vec3> points = cross_sections();
  const auto results = probe_plume(scenario, points, corridor_options(1));
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
