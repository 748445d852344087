#include "plumetrace/agent/robot.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "plumetrace/agent/measurement.hpp"
#include "plumetrace/core/geometry.hpp"

namespace plumetrace {
namespace {

constexpr double kDt = 0.032;
constexpr double kSpeed = 0.106;
constexpr double kAxle = 0.0885;

TEST(Robot, DefaultsAreKheperaThree) {
  const RobotParams p;
  EXPECT_EQ(p.radius, 0.065);
  EXPECT_EQ(p.axle, kAxle);
  EXPECT_EQ(p.wheel_speed, kSpeed);
  EXPECT_EQ(p.start.x, 15.5);
  EXPECT_EQ(p.start.y, 0.0);
  EXPECT_EQ(p.start.heading, kPi);
  // both wheels at +-0.106 m/s on an axle of 0.0885 m: about 2.4 rad/s
  EXPECT_DOUBLE_EQ(turn_rate(p), 2.0 * kSpeed / kAxle);
  EXPECT_NEAR(turn_rate(p), 2.4, 0.01);
}

TEST(Robot, StraightLineAtWheelSpeed) {
  const RobotParams params;
  for (const double h : {0.0, 0.3, kPi / 2, -2.0, -kPi}) {
    RobotState state{{2.0, -1.0, h}, 0.0};
    const int n = 250;
    for (int k = 1; k <= n; ++k) {
      step_robot(params, Command::go(h), kDt, state);
      const double d = kSpeed * kDt * k;
      ASSERT_NEAR(state.pose.x, 2.0 + d * std::cos(h), 1e-12);
      ASSERT_NEAR(state.pose.y, -1.0 + d * std::sin(h), 1e-12);
      ASSERT_NEAR(state.odometer, d, 1e-12);
      ASSERT_NEAR(wrap_angle(state.pose.heading - h), 0.0, 1e-15);
    }
  }
}

TEST(Robot, StopChangesNothing) {
  const RobotParams params;
  RobotState state{{2.0, -1.0, 0.4}, 1.5};
  for (int k = 0; k < 10; ++k) step_robot(params, Command::stop(), kDt, state);
  EXPECT_EQ(state.pose.x, 2.0);
  EXPECT_EQ(state.pose.y, -1.0);
  EXPECT_EQ(state.pose.heading, 0.4);
  EXPECT_EQ(state.odometer, 1.5);
}

TEST(Robot, TurnToRotatesOnTheSpotAtTurnRate) {
  const RobotParams params;
  const double omega = 2.0 * kSpeed / kAxle;
  const double target = kPi / 2;
  const double turn_time = target / omega;  // about 0.656 s: 20 whole steps and a part
  RobotState state{{3.0, 1.0, 0.0}, 0.0};
  for (int k = 1; k <= 40; ++k) {
    step_robot(params, Command::turn_to(target), kDt, state);
    EXPECT_EQ(state.pose.x, 3.0);
    EXPECT_EQ(state.pose.y, 1.0);
    EXPECT_EQ(state.odometer, 0.0);
    if (k * kDt < turn_time) {
      EXPECT_NEAR(state.pose.heading, omega * kDt * k, 1e-12) << k;
    } else {
      EXPECT_NEAR(state.pose.heading, target, 1e-15) << k;
    }
  }
}

TEST(Robot, TurnTakesTheShorterWay) {
  const RobotParams params;
  const double omega = 2.0 * kSpeed / kAxle;
  // from -3 rad to +3 rad the short way is clockwise through pi (0.283 rad)
  RobotState state{{0.0, 0.0, -3.0}, 0.0};
  step_robot(params, Command::turn_to(3.0), kDt, state);
  EXPECT_NEAR(state.pose.heading, -3.0 - omega * kDt, 1e-12);
  for (int k = 0; k < 10; ++k) step_robot(params, Command::turn_to(3.0), kDt, state);
  EXPECT_NEAR(state.pose.heading, 3.0, 1e-15);
  // a negative target turns clockwise
  state = {{0.0, 0.0, 0.0}, 0.0};
  step_robot(params, Command::turn_to(-1.0), kDt, state);
  EXPECT_NEAR(state.pose.heading, -omega * kDt, 1e-12);
}

TEST(Robot, GoTurnsOnTheSpotThenDrivesTheRestOfTheStep) {
  const RobotParams params;
  const double omega = 2.0 * kSpeed / kAxle;
  const double target = kPi / 2;
  const double turn_time = target / omega;
  const int turning_steps = static_cast<int>(std::floor(turn_time / kDt));  // 20
  ASSERT_EQ(turning_steps, 20);
  RobotState state{{3.0, 1.0, 0.0}, 0.0};
  for (int k = 1; k <= turning_steps; ++k) {
    step_robot(params, Command::go(target), kDt, state);
    EXPECT_EQ(state.pose.x, 3.0);
    EXPECT_EQ(state.pose.y, 1.0);
    EXPECT_EQ(state.odometer, 0.0);
    EXPECT_NEAR(state.pose.heading, omega * kDt * k, 1e-12);
  }
  // the step that completes the turn drives forward for the time left
  const int n = 100;
  for (int k = turning_steps + 1; k <= n; ++k) {
    step_robot(params, Command::go(target), kDt, state);
    const double d = kSpeed * (k * kDt - turn_time);
    EXPECT_NEAR(state.pose.heading, target, 1e-15);
    EXPECT_NEAR(state.pose.x, 3.0, 1e-12);
    EXPECT_NEAR(state.pose.y, 1.0 + d, 1e-12);
    EXPECT_NEAR(state.odometer, d, 1e-12);
  }
}

TEST(Robot, CurveKeepsOuterWheelAtLimitAndStaysOnCircle) {
  const RobotParams params;
  for (const double k : {2.0, -2.0, 0.5, -8.0}) {
    const double v = kSpeed / (1.0 + std::fabs(k) * kAxle / 2.0);
    // outer wheel: v + |omega| axle / 2 with omega = k v, the wheel-speed limit
    EXPECT_NEAR(v + std::fabs(k * v) * kAxle / 2.0, kSpeed, 1e-15);
    const Pose start{4.0, -0.5, 0.3};
    RobotState state{start, 0.0};
    // centre of the circle: a distance 1/k to the left of the heading (right when k < 0)
    const double cx = start.x - std::sin(start.heading) / k;
    const double cy = start.y + std::cos(start.heading) / k;
    for (int n = 1; n <= 400; ++n) {
      step_robot(params, Command::curve(k), kDt, state);
      const double s = v * kDt * n;
      ASSERT_NEAR(state.odometer, s, 1e-12);
      ASSERT_NEAR(std::hypot(state.pose.x - cx, state.pose.y - cy), 1.0 / std::fabs(k), 1e-12);
      const double h = start.heading + k * s;
      ASSERT_NEAR(wrap_angle(state.pose.heading - h), 0.0, 1e-11);
      ASSERT_NEAR(state.pose.x, cx + std::sin(h) / k, 1e-11);
      ASSERT_NEAR(state.pose.y, cy - std::cos(h) / k, 1e-11);
    }
  }
}

TEST(Robot, PositiveCurvatureTurnsCounterClockwise) {
  const RobotParams params;
  RobotState left{{0.0, 0.0, 0.0}, 0.0}, right{{0.0, 0.0, 0.0}, 0.0};
  for (int n = 0; n < 10; ++n) {
    step_robot(params, Command::curve(1.0), kDt, left);
    step_robot(params, Command::curve(-1.0), kDt, right);
  }
  EXPECT_GT(left.pose.heading, 0.0);
  EXPECT_GT(left.pose.y, 0.0);
  EXPECT_LT(right.pose.heading, 0.0);
  EXPECT_LT(right.pose.y, 0.0);
  EXPECT_NEAR(left.pose.y, -right.pose.y, 1e-15);
}

TEST(Robot, ZeroCurvatureDrivesStraightAtFullSpeed) {
  const RobotParams params;
  RobotState state{{1.0, 1.0, 0.25}, 0.0};
  for (int n = 0; n < 50; ++n) step_robot(params, Command::curve(0.0), kDt, state);
  const double d = kSpeed * kDt * 50;
  EXPECT_NEAR(state.pose.x, 1.0 + d * std::cos(0.25), 1e-12);
  EXPECT_NEAR(state.pose.y, 1.0 + d * std::sin(0.25), 1e-12);
  EXPECT_NEAR(state.odometer, d, 1e-12);
  EXPECT_EQ(state.pose.heading, 0.25);
}

// solid obstacles

// the source cylinder of the DISAL wind-tunnel world: 5 cm radius at (1, 0)
const Obstacle kSolid{{1.0, 0.0}, 0.05};

double to_obstacle(const RobotState& state) {
  return std::hypot(state.pose.x - kSolid.center.x, state.pose.y - kSolid.center.y);
}

// Steps `command` until the robot touches kSolid or `steps` run out; returns the steps taken.
int drive_into(const RobotParams& params, const Command& command, RobotState& state, int steps) {
  for (int k = 1; k <= steps; ++k) {
    step_robot(params, command, kDt, state, kSolid);
    if (state.touching) return k;
  }
  return steps;
}

TEST(Robot, StopsAtContactDrivingStraightAtASolidObstacle) {
  const RobotParams params;
  const double contact = kSolid.radius + params.radius;
  for (const double y : {0.0, 0.03, -0.1, 0.114}) {
    RobotState state{{2.0, y, kPi}, 0.0};
    const int k = drive_into(params, Command::go(kPi), state, 1000);
    ASSERT_TRUE(state.touching) << y;
    EXPECT_NEAR(to_obstacle(state), contact, 1e-9) << y;
    // on the straight line, at the nearer root of the contact circle
    const double x = kSolid.center.x + std::sqrt(contact * contact - y * y);
    EXPECT_NEAR(state.pose.x, x, 1e-9) << y;
    EXPECT_NEAR(state.pose.y, y, 1e-12);
    EXPECT_NEAR(state.odometer, 2.0 - x, 1e-12) << y;
    // the step before, the robot had driven at full speed
    EXPECT_GT(state.odometer, (k - 1) * kSpeed * kDt - 1e-12);
    // pushing on moves it no further; backing away is free
    const RobotState held = state;
    for (int n = 0; n < 10; ++n) step_robot(params, Command::go(kPi), kDt, state, kSolid);
    EXPECT_NEAR(state.pose.x, held.pose.x, 1e-12);
    EXPECT_TRUE(state.touching);
    step_robot(params, Command::curve(0.0), kDt, state, kSolid);  // facing the obstacle still
    EXPECT_NEAR(state.pose.x, held.pose.x, 1e-12);
    state.pose.heading = 0.0;
    step_robot(params, Command::curve(0.0), kDt, state, kSolid);
    EXPECT_FALSE(state.touching);
    EXPECT_NEAR(state.pose.x, held.pose.x + kSpeed * kDt, 1e-12);
  }
}

TEST(Robot, StopsAtContactOnAnArcThroughASolidObstacle) {
  const RobotParams params;
  const double contact = kSolid.radius + params.radius;
  // arcs of radius 0.5 m whose circle runs through the obstacle's centre, either way round
  for (const double k : {2.0, -2.0}) {
    const Pose start = k > 0.0 ? Pose{2.0, 0.0, kPi / 2.0} : Pose{0.0, 0.0, kPi / 2.0};
    const Vec2 arc_centre{k > 0.0 ? 1.5 : 0.5, 0.0};
    RobotState state{start, 0.0};
    drive_into(params, Command::curve(k), state, 1000);
    ASSERT_TRUE(state.touching) << k;
    EXPECT_NEAR(to_obstacle(state), contact, 1e-9) << k;
    // still on the arc, short of the obstacle's centre: the arc angle is the path over 0.5 m
    EXPECT_NEAR(std::hypot(state.pose.x - arc_centre.x, state.pose.y - arc_centre.y), 0.5, 1e-12);
    const double angle_to_centre = kPi - 2.0 * std::asin(contact / 2.0 / 0.5);
    EXPECT_NEAR(state.odometer, 0.5 * angle_to_centre, 1e-9) << k;
  }
}

TEST(Robot, PassesASolidObstacleAtALargerOffset) {
  const RobotParams params;
  const double contact = kSolid.radius + params.radius;
  // straight, just outside the contact distance
  RobotState state{{2.0, contact + 1e-3, kPi}, 0.0};
  for (int n = 0; n < 700; ++n) {
    step_robot(params, Command::go(kPi), kDt, state, kSolid);
    ASSERT_FALSE(state.touching);
  }
  EXPECT_NEAR(state.pose.x, 2.0 - 700 * kSpeed * kDt, 1e-9);
  // a full circle that keeps 5 mm clear of the contact distance
  const double rho = 0.5 - contact - 0.005;
  RobotState loop{{1.5 + rho, 0.0, kPi / 2.0}, 0.0};
  double nearest = INFINITY;
  for (int n = 0; n < 1500; ++n) {
    step_robot(params, Command::curve(1.0 / rho), kDt, loop, kSolid);
    ASSERT_FALSE(loop.touching);
    nearest = std::min(nearest, to_obstacle(loop));
  }
  EXPECT_GT(loop.odometer, 2.0 * kPi * rho);
  EXPECT_NEAR(nearest, contact + 0.005, 1e-3);
}

TEST(Robot, NoObstacleByDefault) {
  const RobotParams params;
  RobotState with{{1.1, 0.0, kPi}, 0.0}, without{{1.1, 0.0, kPi}, 0.0};
  for (int n = 0; n < 200; ++n) {
    step_robot(params, Command::go(kPi), kDt, with, Obstacle{{1.0, 0.0}, 0.0});
    step_robot(params, Command::go(kPi), kDt, without);
  }
  EXPECT_EQ(with.pose.x, without.pose.x);
  EXPECT_FALSE(with.touching);
  EXPECT_LT(with.pose.x, 0.9);  // straight through where a solid obstacle would be
}

}  // namespace
}  // namespace plumetrace
