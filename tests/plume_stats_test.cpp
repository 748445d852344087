#include "plumetrace/sim/plume_stats.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/core/rng.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace plumetrace {
namespace {

// path lengths 0, step, 2 step, ... for n samples
std::vector<double> evenly(std::size_t n, double step) {
  std::vector<double> arc;
  for (std::size_t k = 0; k < n; ++k) arc.push_back(static_cast<double>(k) * step);
  return arc;
}

TEST(GapAnalysis, HandMadeSequencesGiveTheirGapsBandAndEnds) {
  // detections at 0, 1, 4, 6, 7: a gap of two samples and one of one
  const GapAnalysis g = analyse_gaps({1, 1, 0, 0, 1, 0, 1, 1, 0}, evenly(9, 0.1));
  ASSERT_EQ(g.gaps.size(), 2u);
  EXPECT_NEAR(g.gaps[0], 0.2, 1e-12);  // from the detection at 0.1 to the last miss at 0.3
  EXPECT_NEAR(g.gaps[1], 0.1, 1e-12);
  EXPECT_EQ(g.leading, 0.0);
  EXPECT_EQ(g.first, 0.0);
  EXPECT_NEAR(g.last, 0.7, 1e-12);
  EXPECT_NEAR(g.trailing, 0.1, 1e-12);
  EXPECT_EQ(g.samples, 9);
  EXPECT_EQ(g.detections, 5);

  // odor first at the fourth sample, on uneven steps (a spiral's): the misses cover 0.5 m
  const GapAnalysis late = analyse_gaps({0, 0, 0, 1, 1}, {0.0, 0.2, 0.5, 0.6, 1.0});
  EXPECT_TRUE(late.gaps.empty());
  EXPECT_NEAR(late.leading, 0.5, 1e-12);
  EXPECT_NEAR(late.first, 0.6, 1e-12);
  EXPECT_NEAR(late.trailing, 0.0, 1e-12);

  const GapAnalysis none = analyse_gaps({0, 0, 0}, evenly(3, 0.1));
  EXPECT_TRUE(none.gaps.empty());
  EXPECT_NEAR(none.leading, 0.2, 1e-12);
  EXPECT_TRUE(std::isnan(none.first));
  EXPECT_TRUE(std::isnan(none.trailing));
  EXPECT_EQ(none.detections, 0);

  EXPECT_TRUE(analyse_gaps({1, 1, 1, 1}, evenly(4, 0.1)).gaps.empty());
  EXPECT_EQ(analyse_gaps({}, {}).samples, 0);
}

// A gap is what the controllers' loss test measures: a sensor that had odor loses the plume
// inside a gap (LossTracker, agent/controller.hpp) exactly when the gap is at least d_lost.
TEST(GapAnalysis, AGapReachesDLostExactlyWhenTheLossTestFiresInsideIt) {
  Rng rng(7);
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<std::uint8_t> odor(60);
    const double p = 0.1 + 0.8 * rng.uniform();
    for (auto& o : odor) o = rng.uniform() < p ? 1 : 0;
    const std::vector<double> arc = evenly(odor.size(), 0.01);
    const double d_lost = 0.01 * static_cast<double>(1 + trial % 12);
    const GapAnalysis g = analyse_gaps(odor, arc);
    if (g.detections < 2) continue;
    bool fired = false;  // between the first and the last detection
    LossTracker tracker;
    for (std::size_t k = 0; k < odor.size(); ++k) {
      if (arc[k] < g.first || arc[k] > g.last) continue;
      Observation obs;
      obs.odor = odor[k] != 0;
      obs.odometer = arc[k];
      tracker.observe(obs);
      fired = fired || tracker.lost(obs, d_lost);
    }
    bool long_gap = false;
    for (const double gap : g.gaps) long_gap = long_gap || gap >= d_lost;
    EXPECT_EQ(fired, long_gap) << "trial " << trial;
  }
}

TEST(SortedQuantile, IsTheType7Quantile) {
  EXPECT_DOUBLE_EQ(sorted_quantile({1.0, 2.0, 3.0, 4.0}, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(sorted_quantile({1.0, 2.0, 3.0, 4.0}, 0.9), 3.7);
  EXPECT_DOUBLE_EQ(sorted_quantile({1.0, 2.0, 3.0, 4.0}, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(sorted_quantile({5.0}, 0.9), 5.0);
  EXPECT_TRUE(std::isnan(sorted_quantile({}, 0.5)));
}

TEST(SensorPaths, AStraightPathAdvancesOneStepOfTheSpeedPerSample) {
  const SensorPath p = straight_path({2.0, 1.0}, kPi, 1.0, 0.02, 0.1, 0.5);
  ASSERT_EQ(p.points.size(), 21u);  // 0, 0.05, ..., 1.0 m
  for (std::size_t k = 0; k < p.points.size(); ++k) {
    EXPECT_NEAR(p.arc[k], 0.05 * static_cast<double>(k), 1e-12);
    EXPECT_NEAR(p.points[k].x, 2.0 - p.arc[k], 1e-12);
    EXPECT_NEAR(p.points[k].y, 1.0, 1e-12);
    EXPECT_EQ(p.points[k].z, 0.02);
  }
  EXPECT_EQ(straight_path({0.0, 0.0}, 0.0, 0.0, 0.0, 0.1, 0.5).points.size(), 1u);
}

// Entered at its centre, heading +x, the controller's spiral is r = b theta about its start:
// the polar radius of the point reached after a path length s is b theta(s); the centre moves
// at the wheel-speed limit slowed by the curvature (docs/model.md section 6).
TEST(SensorPaths, TheSpiralIsTheControllersArchimedesSpiral) {
  SurgeSpiralParams params;
  params.start_radius = 0.0;
  const RobotParams robot;
  const double dt = 0.032, b = params.d_gap / (2.0 * kPi);
  const SensorPath p = spiral_path({0.0, 0.0, 0.0}, 1, params, robot, 0.02, dt, 3.0);
  ASSERT_GT(p.points.size(), 100u);
  EXPECT_NEAR(spiral_turns(params, p.arc.back()), 3.0, 0.01);
  double theta = 0.0;
  for (std::size_t k = 1; k < p.points.size(); ++k) {
    theta = spiral_angle_at(b, p.arc[k], theta);
    EXPECT_NEAR(std::hypot(p.points[k].x, p.points[k].y), b * theta, 0.004) << "point " << k;
    const double v =
        robot.wheel_speed /
        (1.0 + spiral_curvature(b, spiral_angle_at(b, p.arc[k - 1], theta)) * robot.axle / 2.0);
    EXPECT_NEAR(p.arc[k] - p.arc[k - 1], v * dt, 1e-12) << "step " << k;
  }
  // clockwise is the mirror image
  const SensorPath m = spiral_path({0.0, 0.0, 0.0}, -1, params, robot, 0.02, dt, 3.0);
  ASSERT_EQ(m.points.size(), p.points.size());
  for (std::size_t k = 0; k < p.points.size(); ++k) {
    EXPECT_NEAR(m.points[k].x, p.points[k].x, 1e-12);
    EXPECT_NEAR(m.points[k].y, -p.points[k].y, 1e-12);
  }
}

TEST(VirtualSensors, SensorsReadThePlumeWithoutChangingIt) {
  Scenario s;
  s.robot.start_offset.x = 3.0;
  derive_scenario(s);
  const SensorPath along = straight_path({4.0, 0.0}, kPi, 3.0, 0.02, 0.106, s.sim.dt);
  const SensorPath across = straight_path({2.0, -0.5}, kPi / 2.0, 1.0, 0.02, 0.106, s.sim.dt);
  const auto alone = sense_paths(s, 1, 0, {along}, 5.0);
  const auto both = sense_paths(s, 1, 0, {across, along}, 5.0);
  ASSERT_EQ(alone[0].size(), along.points.size());
  EXPECT_EQ(alone[0], both[1]);
  // another trial is another plume
  EXPECT_NE(sense_paths(s, 1, 1, {along}, 5.0)[0], alone[0]);
}

// A plume one can reason about: a source of radius 1 mm, no random walk, no growth, 300
// filaments a second on the Gaussian kernel. The filaments lie on the axis 3 mm apart, far
// closer than their width, so the concentration is the line integral
//   C(y, z) = s rate sqrt(pi) / (u sqrt(8 pi^3) w^2) exp(-(y^2 + z^2) / w^2),
// steady, with odor exactly where |y| <= sqrt(w^2 ln(K / threshold) - z^2).
Scenario line_plume() {
  Scenario s;
  s.sim.warmup = 8.0;
  s.sim.warmup_auto = false;
  s.source.radius = 1e-3;
  s.source.solid_radius = 0.0;
  s.plume.kernel = Kernel::kGaussian;
  s.plume.sigma_p = 0.0;
  s.plume.gamma = 0.0;
  s.plume.release_rate = 300.0;
  s.plume.capacity = 2700;  // 9 s: past the start at 0.9 m/s
  s.plume.capacity_auto = false;
  s.plume.amount = 5e4;
  s.robot.start_offset.x = 4.0;
  s.wind_sensor.sigma_a = 0.0;
  derive_scenario(s);
  return s;
}

double line_plume_half_width(const Scenario& s) {
  const double w = s.plume.initial_width, u = s.wind.velocity.x, z = s.odor.height;
  const double k = s.plume.amount * s.plume.release_rate * std::sqrt(kPi) /
                   (u * std::sqrt(8.0 * kPi * kPi * kPi) * w * w);
  return std::sqrt(w * w * std::log(k / s.odor.threshold) - z * z);
}

TEST(PlumeStats, ASteadyLinePlumeHasNoGapsAndItsAnalyticBandWidth) {
  const Scenario s = line_plume();
  const double half = line_plume_half_width(s);
  ASSERT_GT(half, 0.2);
  ASSERT_LT(half, 0.4);
  PlumeStatsOptions o;
  o.trials = 2;
  o.surges = 0;
  o.offsets = {0.0, 0.1, half + 0.02};
  o.across = {1.0, 3.0};
  const PlumeStats st = plume_stats(s, o);
  const double step = s.robot.wheel_speed * s.sim.dt;
  ASSERT_EQ(st.along.size(), 3u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_TRUE(st.along[i].gaps.gaps.empty()) << "offset " << st.along[i].offset;
    EXPECT_EQ(st.along[i].gaps.detections, st.along[i].gaps.samples);
  }
  EXPECT_EQ(st.along[2].gaps.detections, 0);
  ASSERT_EQ(st.across.size(), 2u);
  for (const auto& c : st.across) {
    EXPECT_TRUE(c.gaps.gaps.empty()) << "distance " << c.distance;
    ASSERT_EQ(c.band_widths.size(), 2u);
    for (const double b : c.band_widths) EXPECT_NEAR(b, 2.0 * half, 2.0 * step + 1e-3);
  }
  EXPECT_EQ(st.release.in_odor, 2);
  EXPECT_EQ(st.release.within_d_lost, 2);
}

// Surges that start beside the line plume lose it after d_lost; their spirals cannot meet the
// band before covering the distance to it, and meet it within the turns that distance needs.
TEST(PlumeStats, SpiralsReachTheBandNoSoonerThanItsDistanceAndWithinTheTurnsItNeeds) {
  Scenario s = line_plume();
  const double half = line_plume_half_width(s);
  s.robot.start_offset.y = half + 0.3;
  derive_scenario(s);
  PlumeStatsOptions o;
  o.trials = 2;
  o.surges = 3;
  o.offsets = {};
  o.across = {};
  o.turns = 4.0;
  const PlumeStats st = plume_stats(s, o);
  const auto& sp = st.spirals;
  EXPECT_EQ(sp.surges, 6);
  EXPECT_EQ(sp.lost, 6);  // straight upwind at y = start, never in odor
  for (const double x : sp.loss_x) {
    EXPECT_NEAR(x, s.robot.start.x - st.d_lost, s.robot.wheel_speed * s.sim.dt + 1e-9);
  }
  // 0.3 m from the band: two turns of 0.222 m widen the spiral past it on either side
  EXPECT_EQ(sp.reacquired, 6);
  EXPECT_EQ(sp.walls + sp.out_of_turns, 0);
  for (const double d : sp.distances) EXPECT_GE(d, 0.3 - 0.01);
  for (const double t : sp.turns_to_odor) EXPECT_LE(t, 2.5);
  EXPECT_EQ(st.release.within_d_lost, 0);
}

// Where no odor is, every spiral ends where a run would: at a wall, or after its turns.
TEST(PlumeStats, SpiralsThatFindNoOdorEndAtAWallOrAfterTheirTurns) {
  Scenario s;
  s.arena.y_min = -0.6;
  s.arena.y_max = 0.6;
  s.odor.threshold = 1e30;
  s.robot.start_offset.x = 3.0;
  s.sim.warmup = 2.0;
  s.sim.warmup_auto = false;
  derive_scenario(s);
  PlumeStatsOptions o;
  o.trials = 1;
  o.surges = 2;
  o.offsets = {};
  o.across = {};
  PlumeStats st = plume_stats(s, o);
  EXPECT_EQ(st.spirals.lost, 2);
  EXPECT_EQ(st.spirals.walls, 2);
  EXPECT_EQ(st.spirals.reacquired + st.spirals.out_of_turns, 0);
  o.turns = 0.5;
  st = plume_stats(s, o);
  EXPECT_EQ(st.spirals.out_of_turns, 2);
  EXPECT_EQ(st.spirals.walls, 0);
}

TEST(PlumeStats, ResultsDoNotDependOnTheThreadCount) {
  Scenario s;
  s.robot.start_offset.x = 4.0;
  s.sim.warmup = 6.0;
  s.sim.warmup_auto = false;
  derive_scenario(s);
  PlumeStatsOptions o;
  o.trials = 4;
  o.surges = 3;
  o.offsets = {0.0, 0.1};
  o.across = {2.0};
  o.turns = 2.0;
  o.threads = 1;
  const PlumeStats one = plume_stats(s, o);
  o.threads = 3;
  const PlumeStats three = plume_stats(s, o);
  ASSERT_EQ(one.along.size(), three.along.size());
  for (std::size_t i = 0; i < one.along.size(); ++i) {
    EXPECT_EQ(one.along[i].gaps.gaps, three.along[i].gaps.gaps);
    EXPECT_EQ(one.along[i].gaps.detections, three.along[i].gaps.detections);
  }
  EXPECT_EQ(one.across[0].band_widths, three.across[0].band_widths);
  EXPECT_EQ(one.spirals.loss_x, three.spirals.loss_x);
  EXPECT_EQ(one.spirals.distances, three.spirals.distances);
  EXPECT_EQ(one.release.in_odor, three.release.in_odor);
  EXPECT_GT(one.spirals.lost, 0);  // the statistic was exercised
  // a seed of its own: another master seed gives other plumes
  o.seed = 2;
  EXPECT_NE(plume_stats(s, o).along[0].gaps.gaps, one.along[0].gaps.gaps);
}

TEST(PlumeStats, BadOptionsAreRefusedNamingTheOption) {
  const Scenario s;
  const auto refused = [&](PlumeStatsOptions o, const std::string& name) {
    try {
      plume_stats(s, o);
      ADD_FAILURE() << name << " was accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  PlumeStatsOptions o;
  o.trials = 0;
  refused(o, "--trials");
  o = {};
  o.turns = 0.0;
  refused(o, "--turns");
  o = {};
  o.offsets = {NAN};
  refused(o, "--offsets");
  o = {};
  o.warmup = -1.0;
  refused(o, "--warmup");
}

}  // namespace
}  // namespace plumetrace
