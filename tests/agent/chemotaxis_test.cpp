// Tests of agent/controllers/chemotaxis.hpp: the bacterial biased random walk
// (docs/algorithms.md, "chemotaxis").
#include "plumetrace/agent/controllers/chemotaxis.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "plumetrace/agent/robot.hpp"
#include "support/fixed_wind.hpp"

namespace plumetrace {
namespace {

using testing::FixedWind;
using testing::InstantRobot;

// a step advances 1/8 m: a base run of 0.5 m is 4 steps, a lengthened one (bias 2) 12
constexpr double kAdvance = 0.125;

// Runs `steps` steps in which the reading is `reading(k)` (k counts from 0 over the whole drive),
// the robot obeying at once; returns the last command.
Command drive(Chemotaxis& c, InstantRobot& robot, int steps,
              const std::function<double(int)>& reading, int& k) {
  FixedWind wind;
  Command command;
  for (int i = 0; i < steps; ++i, ++k) {
    robot.obs.concentration = reading(k);
    robot.obs.odor = reading(k) >= 1.0;
    command = c.step(robot.obs, wind);
    robot.obey(command, kAdvance);
  }
  EXPECT_EQ(wind.calls, 0);  // chemotaxis reads no wind
  return command;
}

TEST(Chemotaxis, RunsOnLongerAfterARiseAndTumblesAfterAFall) {
  Chemotaxis c(ChemotaxisParams{}, Rng(3));
  InstantRobot robot;
  int k = 0;
  // run 1 (steps 0-3) reads 10, run 2 (steps 4-7) 20, then 5
  const auto reading = [](int k) { return k < 4 ? 10.0 : k < 8 ? 20.0 : 5.0; };
  drive(c, robot, 4, reading, k);
  EXPECT_EQ(c.runs(), 1);
  EXPECT_TRUE(std::isnan(c.last_mean()));
  // the first run ends in a tumble: there is nothing to compare with
  const Command second = drive(c, robot, 1, reading, k);
  EXPECT_EQ(c.runs(), 2);
  EXPECT_EQ(c.last_mean(), 10.0);
  EXPECT_EQ(c.state(), "run");
  EXPECT_EQ(c.run().length(), 0.5);
  // run 2 rose from 10 to 20: the same heading, (1 + 2) times as long
  drive(c, robot, 3, reading, k);
  const Command third = drive(c, robot, 1, reading, k);
  EXPECT_EQ(c.runs(), 3);
  EXPECT_EQ(c.last_mean(), 20.0);
  EXPECT_EQ(c.state(), "extended");
  EXPECT_EQ(third.heading, second.heading);
  EXPECT_EQ(c.run().length(), 1.5);
  // run 3 fell to 5 after 12 steps: a tumble to a new heading, a base run
  drive(c, robot, 11, reading, k);
  EXPECT_EQ(c.runs(), 3);
  const Command fourth = drive(c, robot, 1, reading, k);
  EXPECT_EQ(c.runs(), 4);
  EXPECT_EQ(c.last_mean(), 5.0);
  EXPECT_EQ(c.state(), "run");
  EXPECT_EQ(c.run().length(), 0.5);
  EXPECT_NE(fourth.heading, third.heading);
}

TEST(Chemotaxis, AnEqualMeanIsNoRise) {
  Chemotaxis c(ChemotaxisParams{}, Rng(3));
  InstantRobot robot;
  int k = 0;
  drive(
      c, robot, 9, [](int) { return 0.0; }, k);  // two runs of zeros, the third begun
  EXPECT_EQ(c.runs(), 3);
  EXPECT_EQ(c.state(), "run");
}

TEST(Chemotaxis, TheBinarySignalAveragesHitsAndAsksForNoConcentration) {
  ChemotaxisParams p;
  EXPECT_EQ(Chemotaxis(p, Rng(1)).reads(), static_cast<unsigned>(kReadsConcentration));
  p.signal = ChemotaxisSignal::kBinary;
  Chemotaxis c(p, Rng(1));
  EXPECT_EQ(c.reads(), static_cast<unsigned>(kReadsBinary));
  InstantRobot robot;
  int k = 0;
  // one hit in the first run's four steps: a mean of 1/4
  drive(
      c, robot, 5, [](int k) { return k == 2 ? 500.0 : 0.0; }, k);
  EXPECT_EQ(c.last_mean(), 0.25);
}

TEST(Chemotaxis, ABlockedRunEndsInATumbleEvenAfterARise) {
  Chemotaxis c(ChemotaxisParams{}, Rng(3));
  InstantRobot robot;
  int k = 0;
  // run 1 reads 0; run 2 begins
  const Command second = drive(
      c, robot, 5, [](int) { return 0.0; }, k);
  EXPECT_EQ(c.runs(), 2);
  FixedWind wind;
  robot.obs.concentration = 50.0;  // run 2 rises above run 1's mean...
  c.step(robot.obs, wind);
  robot.obey(second, 0.0);  // ... then is blocked: no move, no turn
  const Command after = c.step(robot.obs, wind);
  EXPECT_EQ(c.runs(), 3);
  EXPECT_EQ(c.last_mean(), 25.0);
  EXPECT_EQ(c.state(), "run");
  EXPECT_EQ(c.run().length(), 0.5);
  EXPECT_NE(after.heading, second.heading);
}

TEST(Chemotaxis, SnapshotShowsThePlannedRunAndRecentRunsWeightedByTheirMeans) {
  Chemotaxis c(ChemotaxisParams{}, Rng(3));
  EXPECT_TRUE(c.snapshot().empty());
  InstantRobot robot;
  int k = 0;
  drive(
      c, robot, 9, [](int k) { return k < 4 ? 7.0 : 0.0; }, k);
  const Snapshot s = c.snapshot();
  ASSERT_EQ(s.path.size(), 2u);
  EXPECT_NEAR(std::hypot(s.path[1].x - s.path[0].x, s.path[1].y - s.path[0].y), 0.5, 1e-12);
  ASSERT_EQ(s.points.size(), 2u);
  ASSERT_EQ(s.weights.size(), 2u);
  EXPECT_EQ(s.weights[0], 7.0);
  EXPECT_EQ(s.weights[1], 0.0);
  EXPECT_EQ(s.points[0].x, 0.0);
}

// Runs chemotaxis from the origin in a smooth field C(r) = 1000 exp(-|r - source| / 2 m) without
// walls, the robot moved by step_robot, for at most `seconds`; true when it comes within 0.3 m
// of the source, 4 m away in a direction drawn from the seed.
bool reaches_smooth_source(const ChemotaxisParams& p, std::uint64_t seed, double seconds) {
  const double dt = 0.032;
  Rng where(seed + 1000);
  const double a = 2.0 * kPi * where.uniform();
  const Vec2 source{4.0 * std::cos(a), 4.0 * std::sin(a)};
  Chemotaxis c(p, Rng(seed));
  FixedWind wind;
  RobotParams robot_params;
  RobotState robot{{0.0, 0.0, 0.0}, 0.0};
  for (double t = dt; t <= seconds; t += dt) {
    const double r = std::hypot(robot.pose.x - source.x, robot.pose.y - source.y);
    if (r <= 0.3) return true;
    Observation obs;
    obs.time = t;
    obs.odometry = robot.pose;
    obs.odometer = robot.odometer;
    obs.concentration = 1000.0 * std::exp(-r / 2.0);
    obs.odor = obs.concentration >= 100.0;  // the paper's threshold: within 4.6 m, always
    step_robot(robot_params, c.step(obs, wind), dt, robot);
  }
  return false;
}

// Wilson score interval of k successes in n at z standard deviations
struct Interval {
  double low, high;
};
Interval wilson(int k, int n, double z) {
  const double p = static_cast<double>(k) / n, z2 = z * z;
  const double centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
  const double half = z * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n)) / (1.0 + z2 / n);
  return {centre - half, centre + half};
}

TEST(Chemotaxis, ConcentrationClimbsASmoothGradientThatTheBinaryOdorCannotSee) {
  // in a smooth field the binary odor is 1 all along the way, so the binary walk never sees a
  // rise: it is the unbiased random walk, while the concentration biases the walk up the gradient
  const int n = 200;
  ChemotaxisParams concentration;
  ChemotaxisParams binary;
  binary.signal = ChemotaxisSignal::kBinary;
  int k_concentration = 0, k_binary = 0;
  for (int i = 0; i < n; ++i) {
    k_concentration += reaches_smooth_source(concentration, i, 1200.0);
    k_binary += reaches_smooth_source(binary, i, 1200.0);
  }
  // the two success fractions' 99.99% (3.9 sigma) Wilson intervals do not overlap
  EXPECT_GT(wilson(k_concentration, n, 3.9).low, wilson(k_binary, n, 3.9).high)
      << k_concentration << " vs " << k_binary << " of " << n;
}

}  // namespace
}  // namespace plumetrace
