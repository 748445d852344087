// Tests of agent/controllers/hayes.hpp: Hayes' spiral-surge for teams, its rules on hand-made
// observations, its keys, and a team of three in the laminar tunnel (docs/algorithms.md).
#include "plumetrace/agent/controllers/hayes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {
namespace {

constexpr double kDt = 0.032;

// A wind sensor that always reads the wind (1, 0) m/s of the odometry frame from the robot's
// heading: upwind is pi. Counts its samples.
class SteadyWind final : public WindProbe {
 public:
  Vec2 measure_wind_body() override {
    ++calls;
    return rotate({1.0, 0.0}, -heading);
  }
  double heading = 0.0;  // the robot's heading (rad)
  int calls = 0;
};

// Drives a Hayes controller with hand-made observations; the robot is wherever a step says.
class Bench {
 public:
  explicit Bench(const HayesParams& params = {}, std::uint64_t seed = 1)
      : hayes(params, Rng(seed)) {}

  // one decision at `at` (odometry frame, heading `heading`), with odor or not and messages
  Command step(Vec2 at, bool odor, std::vector<Message> messages = {}, double heading = 0.0) {
    inbox_ = std::move(messages);
    Observation obs;
    obs.time = ++steps_ * kDt;
    obs.odor = odor;
    odometer_ += std::hypot(at.x - last_.x, at.y - last_.y);
    last_ = at;
    obs.odometry = {at.x, at.y, heading};
    obs.odometer = odometer_;
    obs.messages = inbox_;
    wind.heading = heading;
    return hayes.step(obs, wind);
  }
  double odometer() const { return odometer_; }

  Hayes hayes;
  SteadyWind wind;

 private:
  std::vector<Message> inbox_;
  int steps_ = 0;
  double odometer_ = 0.0;
  Vec2 last_;
};

// a teammate's hit at (x, y) of the team's frame, sent at `sent`
Message hit_from(int from, double x, double y, double sent = 0.0) {
  return {from, sent, {x, y, Hayes::kHitTag, 0.0}};
}

TEST(Hayes, SpiralsFromTheReleasePointWithTheFindingGap) {
  HayesParams p;
  Bench b(p);
  const Command c = b.step({0.0, 0.0}, false);
  EXPECT_EQ(b.hayes.state(), "find");
  EXPECT_EQ(c.motion, Motion::kCurve);
  EXPECT_FALSE(c.send);
  // the first curvature is the spiral's at r0 = start_radius, b = d_gap_find / (2 pi)
  const double bb = p.d_gap_find / (2.0 * kPi);
  EXPECT_DOUBLE_EQ(std::fabs(c.curvature), spiral_curvature(bb, p.start_radius / bb));
  EXPECT_EQ(c.curvature > 0.0 ? 1 : -1, b.hayes.curl());
  EXPECT_EQ(b.wind.calls, 0) << "no wind sample before a hit";
}

TEST(Hayes, AHitSurgesUpwindAndBroadcastsItsPositionInTheTeamsFrame) {
  HayesParams p;
  p.origin_x = 1.0;
  p.origin_y = 2.0;
  p.origin_heading = kPi / 2.0;
  Bench b(p);
  b.step({0.0, 0.0}, false);
  const Command c = b.step({0.5, 0.0}, true);
  EXPECT_EQ(b.hayes.state(), "surge");
  EXPECT_EQ(c.motion, Motion::kGo);
  EXPECT_NEAR(std::fabs(wrap_angle(c.heading - kPi)), 0.0, 1e-12);  // measured upwind
  EXPECT_EQ(b.wind.calls, 1);
  // (0.5, 0) of the odometry frame, turned by 90 deg and moved to (1, 2): (1, 2.5)
  ASSERT_TRUE(c.send);
  EXPECT_NEAR(c.message[0], 1.0, 1e-12);
  EXPECT_NEAR(c.message[1], 2.5, 1e-12);
  EXPECT_EQ(c.message[2], Hayes::kHitTag);
  EXPECT_EQ(c.message[3], 0.0);
  // and back: the team's frame to the odometry frame
  const Vec2 back = b.hayes.from_team({1.0, 2.5});
  EXPECT_NEAR(back.x, 0.5, 1e-12);
  EXPECT_NEAR(back.y, 0.0, 1e-12);
}

TEST(Hayes, TheSurgeEndsDSurgePastTheLastHitAndASpiralFollows) {
  HayesParams p;
  p.d_surge = 0.3;
  Bench b(p);
  b.step({0.0, 0.0}, true);
  // hits at x = 0 .. 0.2 (the surge restarts at each), then none
  double x = 0.0;
  for (; x < 0.2 - 1e-9; x += 0.01) b.step({-x, 0.0}, true, {}, kPi);
  b.step({-x, 0.0}, true, {}, kPi);
  const double last_hit = b.odometer();
  while (b.hayes.state() == "surge") {
    x += 0.01;
    b.step({-x, 0.0}, false, {}, kPi);
    ASSERT_LT(x, 2.0);
  }
  // lost on the first step at least d_surge past the last hit
  EXPECT_GE(b.odometer() - last_hit, p.d_surge - 1e-12);
  EXPECT_LT(b.odometer() - last_hit, p.d_surge + 0.01);
  EXPECT_EQ(b.hayes.state(), "spiral");
  EXPECT_EQ(b.hayes.losses(), 1);
  EXPECT_EQ(b.wind.calls, 1) << "one sample, at the switch into the surge";
}

TEST(Hayes, ATeammatesHitWhileSearchingSendsTheRobotThereThenItSpirals) {
  HayesParams p;
  p.origin_x = 1.0;  // this robot was released at (1, 1) of the team's frame
  p.origin_y = 1.0;
  Bench b(p);
  b.step({0.0, 0.0}, false);
  const Command c = b.step({0.0, 0.0}, false, {hit_from(2, 4.0, 5.0)});
  EXPECT_EQ(b.hayes.state(), "goto");
  EXPECT_EQ(c.motion, Motion::kGo);
  // the hit at (4, 5) of the team's frame is (3, 4) of the robot's odometry frame
  EXPECT_NEAR(b.hayes.target().x, 3.0, 1e-12);
  EXPECT_NEAR(b.hayes.target().y, 4.0, 1e-12);
  EXPECT_NEAR(c.heading, std::atan2(4.0, 3.0), 1e-12);
  EXPECT_FALSE(c.send) << "a teammate's hit is not sent on";
  // on the way: still going there
  b.step({1.5, 2.0}, false);
  EXPECT_EQ(b.hayes.state(), "goto");
  // within d_arrive: a spiral with the traversal gap, around the teammate's hit
  const Command there = b.step({3.0 - 0.6 * p.d_arrive, 4.0 - 0.6 * p.d_arrive}, false);
  EXPECT_EQ(b.hayes.state(), "spiral");
  EXPECT_EQ(there.motion, Motion::kCurve);
  const double bb = p.d_gap / (2.0 * kPi);
  EXPECT_DOUBLE_EQ(std::fabs(there.curvature), spiral_curvature(bb, p.start_radius / bb));
}

TEST(Hayes, TheNewestTeammateHitIsTheTarget) {
  Bench b;
  b.step({0.0, 0.0}, false);
  b.step({0.0, 0.0}, false, {hit_from(1, 2.0, 0.0, 0.01), hit_from(2, 0.0, 3.0, 0.02)});
  EXPECT_NEAR(b.hayes.target().y, 3.0, 1e-12);
  b.step({0.0, 0.1}, false, {hit_from(1, -2.0, 0.5, 0.05)});
  EXPECT_NEAR(b.hayes.target().x, -2.0, 1e-12);
}

TEST(Hayes, ASurgingRobotKeepsItsOwnSurge) {
  Bench b;
  b.step({0.0, 0.0}, true);
  const Command c = b.step({-0.01, 0.0}, false, {hit_from(1, 5.0, 5.0)}, kPi);
  EXPECT_EQ(b.hayes.state(), "surge");
  EXPECT_EQ(c.motion, Motion::kGo);
  EXPECT_NEAR(std::fabs(wrap_angle(c.heading - kPi)), 0.0, 1e-12);
}

TEST(Hayes, ARobotThatMetThePlumeFollowsOnlyHitsNotDownwindOfItsOwn) {
  HayesParams p;
  p.d_surge = 0.05;
  Bench b(p);
  b.step({0.0, 0.0}, true);  // own hit at (0, 0); upwind is -x
  double x = 0.0;
  while (b.hayes.state() == "surge") {
    x += 0.01;
    b.step({-x, 0.0}, false, {}, kPi);
  }
  ASSERT_EQ(b.hayes.state(), "spiral");
  b.step({-x, 0.01}, false, {hit_from(1, 1.0, 0.0)});  // downwind of its own hit
  EXPECT_EQ(b.hayes.state(), "spiral");
  b.step({-x, 0.02}, false, {hit_from(1, -1.0, 0.4)});  // upwind of it
  EXPECT_EQ(b.hayes.state(), "goto");
  EXPECT_NEAR(b.hayes.target().x, -1.0, 1e-12);
}

TEST(Hayes, DeclaresAtTheMeanOfEnoughRecentHitsNearIt) {
  HayesParams p;
  p.declare_hits = 3;
  p.declare_radius = 0.3;
  p.declare_window = 1.0;
  Bench b(p);
  // an old hit nearby (it will be outside the window) and a recent one too far away
  b.step({0.0, 0.0}, false, {hit_from(1, 0.05, 0.05, 0.0)});
  for (int k = 0; k < 40; ++k) b.step({0.0, 0.0}, false);  // 1.28 s later
  Command c = b.step({0.0, 0.0}, false, {hit_from(1, 0.5, 0.0, 1.3)});
  EXPECT_FALSE(c.declare);
  c = b.step({0.0, 0.0}, true);  // own hit at (0, 0): 1 near and recent
  EXPECT_FALSE(c.declare);
  c = b.step({0.0, 0.0}, false, {hit_from(2, 0.1, 0.0, 1.35)});  // 2
  EXPECT_FALSE(c.declare);
  c = b.step({0.0, 0.0}, false, {hit_from(1, 0.0, 0.2, 1.38)});  // 3: declares
  ASSERT_TRUE(c.declare);
  EXPECT_NEAR(c.source.x, (0.0 + 0.1 + 0.0) / 3.0, 1e-12);
  EXPECT_NEAR(c.source.y, (0.0 + 0.0 + 0.2) / 3.0, 1e-12);
}

TEST(Hayes, NeverDeclaresWithDeclareHitsZero) {
  Bench b;  // declare_hits = 0
  for (int k = 0; k < 200; ++k) {
    const Command c = b.step({0.0, 0.0}, true, {hit_from(1, 0.0, 0.0, k * kDt)});
    ASSERT_FALSE(c.declare);
  }
}

TEST(Hayes, IgnoresMessagesThatAreNotHits) {
  Bench b;
  b.step({0.0, 0.0}, false);
  b.step({0.0, 0.0}, false, {{1, 0.0, {3.0, 4.0, 7.0, 0.0}}});
  EXPECT_EQ(b.hayes.state(), "find");
  EXPECT_EQ(b.hayes.hits(), 0u);
}

TEST(Hayes, TheSnapshotShowsPooledHitsAndTheTarget) {
  Bench b;
  b.step({0.0, 0.0}, false, {hit_from(1, 2.0, 1.0), hit_from(2, 3.0, 1.0)});
  const Snapshot s = b.hayes.snapshot();
  ASSERT_EQ(s.points.size(), 2u);
  EXPECT_EQ(s.points[1].x, 3.0);
  ASSERT_EQ(s.path.size(), 2u);
  EXPECT_EQ(s.path[1].x, 3.0);  // heading to the newest
  EXPECT_EQ(s.path[1].y, 1.0);
}

TEST(Hayes, RemembersAtMostItsMemoryForgettingTheOldest) {
  HayesParams p;
  p.declare_window = 1e9;
  Bench b(p);
  std::vector<Message> many;
  for (std::size_t i = 0; i < Hayes::kHitMemory + 10; ++i) {
    many.push_back(hit_from(1, static_cast<double>(i), 0.0));
  }
  b.step({0.0, 0.0}, false, many);
  EXPECT_EQ(b.hayes.hits(), Hayes::kHitMemory);
  EXPECT_EQ(b.hayes.snapshot().points.front().x, 10.0);
}

// the settings are refused before any run, with a message naming `key`
void refused(const std::string& key, ConfigValue value) {
  try {
    build_scenario({Setting{key, std::move(value), false, "test", Layer::kCommandLine}});
    ADD_FAILURE() << key << " accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

TEST(Hayes, BadKeysAreRefusedNamingTheKey) {
  refused("hayes.d_surge", 0.0);
  refused("hayes.d_gap", -0.1);
  refused("hayes.d_gap_find", 0.0);
  refused("hayes.start_radius", -0.01);
  refused("hayes.d_arrive", 0.0);
  refused("hayes.origin_heading_deg", 400.0);
  refused("hayes.origin_x", static_cast<double>(INFINITY));
  refused("hayes.declare_hits", std::int64_t{-1});
  refused("hayes.declare_radius", 0.0);
  refused("hayes.declare_window", -1.0);
}

// The team of three, released together outside the plume (robot 0 1 m to its side, 8 m
// downwind of the source, the others 0.4 m either side), in `runs` trials: how many robots of
// all the teams perceived odor.
struct TeamCount {
  int found = 0;    // robots that perceived odor
  int arrived = 0;  // robots that reached the source
  int robots = 0;
};

TeamCount team_outside(double range, int runs, double timeout) {
  const auto set = [](const char* key, ConfigValue v) {
    return Setting{key, std::move(v), false, "test", Layer::kCommandLine};
  };
  // robot k starts ceil(k/2) spacings to the left (odd k) or right of robot 0, facing the same
  // way: its release point is (0, +-0.4) of robot 0's odometry frame, the team's frame
  const Scenario s = build_scenario(
      {set("controller.algorithm", std::string("hayes")), set("robot.start_offset_x", 8.0),
       set("robot.start_offset_y", 1.0), set("team.count", std::int64_t{3}),
       set("team.spacing", 0.4), set("team.range", range), set("supervisor.timeout", timeout),
       set("member.1.hayes.origin_y", 0.4), set("member.2.hayes.origin_y", -0.4)});
  TeamCount count;
  for (int t = 0; t < runs; ++t) {
    for (const RunResult& r : run_team(s, 20080101, static_cast<std::uint64_t>(t))) {
      ++count.robots;
      count.found += !std::isnan(r.t_first_odor);
      count.arrived += r.outcome == Outcome::kSuccess;
    }
  }
  return count;
}

TEST(Hayes, ATeamSharingHitsFindsThePlumeWithMoreRobotsThanATeamOutOfRange) {
  const int runs = 30;
  const TeamCount shared = team_outside(INFINITY, runs, 100.0);
  const TeamCount silent = team_outside(0.0, runs, 100.0);
  ASSERT_EQ(shared.robots, 3 * runs);
  // why: two independent binomial proportions; the difference exceeds 4 of its standard errors
  // (pooled), so a team that shared nothing would pass by chance with odds under 1 in 10^4
  const double n = shared.robots;
  const double p1 = shared.found / n, p0 = silent.found / n, pool = (p1 + p0) / 2.0;
  const double se = std::sqrt(pool * (1.0 - pool) * 2.0 / n);
  EXPECT_GT(p1 - p0, 4.0 * se) << "shared " << shared.found << ", silent " << silent.found << " of "
                               << n;
}

}  // namespace
}  // namespace plumetrace
