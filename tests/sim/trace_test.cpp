// Tests of sim/trace.hpp: what the recorder keeps of every robot of a team, and the controllers'
// snapshots moved to the world frame.
#include "plumetrace/sim/trace.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/world.hpp"
#include "support/snapshot_controller.hpp"

namespace plumetrace {
namespace {

constexpr std::uint64_t kSeed = 20080101;

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

// the default scenario with a team of `count`, released at (x, y) facing `heading`
Scenario team_scenario(int count, double timeout, Pose start = {15.5, 0.0, kPi}) {
  Scenario s;
  s.team.count = count;
  s.supervisor.timeout = timeout;
  s.robot.start = start;
  s.robot.start_x_auto = s.robot.start_y_auto = false;
  validate(s);
  return s;
}

TEST(TraceRecorder, RecordsEveryRobotOfTheTeamUntilItsRunEnds) {
  const Scenario s = team_scenario(3, 60.0);
  Trace trace;
  TraceRecorder recorder(trace, 1.0, s.sim.dt);
  // robot k declares after 200 + 40 k steps: each run ends at its own step
  const std::vector<RunResult> results =
      run_team(s, kSeed, 2, std::ref(recorder), testing::snapshot_controllers(200, true));
  ASSERT_EQ(trace.agents.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const AgentTrace& a = trace.agents[k];
    const RunResult& r = results[k];
    EXPECT_EQ(a.index, static_cast<int>(k));
    EXPECT_EQ(a.result.agent, static_cast<int>(k));
    EXPECT_EQ(a.result.steps, 201 + 40 * static_cast<std::int64_t>(k));
    EXPECT_EQ(bits(a.result.d_t), bits(r.d_t));
    EXPECT_EQ(a.result.outcome, r.outcome);
    // a row at release, then one per step: none after its run ended
    ASSERT_EQ(a.steps.size(), static_cast<std::size_t>(r.steps) + 1) << k;
    EXPECT_EQ(a.steps.front().time, 0.0);
    EXPECT_EQ(bits(a.steps.back().time), bits(r.time));
    EXPECT_EQ(bits(a.steps.front().pose.x), bits(a.start.x));
    EXPECT_EQ(bits(a.steps.front().pose.y), bits(a.start.y));
    // the declaration, where the estimate (2, -1) of its odometry frame is in the world's
    EXPECT_NEAR(a.declared.x, a.start.x - 2.0, 1e-12);
    EXPECT_NEAR(a.declared.y, a.start.y + 1.0, 1e-12);
  }
  // at a point start, robots 1 and 2 beside robot 0, across its heading (team.spacing)
  EXPECT_NEAR(trace.agents[1].start.y - trace.agents[0].start.y, -s.team.spacing, 1e-12);
  EXPECT_NEAR(trace.agents[2].start.y - trace.agents[0].start.y, s.team.spacing, 1e-12);
  // the filaments go on while any robot runs, each snapshot at the world's time
  ASSERT_GE(trace.snapshots.size(), 2u);
  EXPECT_EQ(trace.snapshots.back().time, 279 * s.sim.dt);
}

TEST(TraceRecorder, ARobotAlonesTraceIsWhatItAlwaysWas) {
  const Scenario s = team_scenario(1, 40.0);
  Trace trace;
  TraceRecorder recorder(trace, 1.0, s.sim.dt);
  const RunResult r = run_once(s, kSeed, 1, std::ref(recorder));
  ASSERT_EQ(trace.agents.size(), 1u);
  EXPECT_EQ(trace.agents[0].steps.size(), static_cast<std::size_t>(r.steps) + 1);
  EXPECT_TRUE(std::isnan(trace.agents[0].declared.x));
  // a snapshot every 31 steps (0.992 s) from release; the paper's controllers show nothing
  EXPECT_EQ(trace.snapshots.size(), static_cast<std::size_t>(r.steps / 31 + 1));
  EXPECT_TRUE(trace.controller_snapshots.empty());
}

TEST(TraceRecorder, ASnapshotIsMovedToTheWorldFrameByTheStartPose) {
  // released at (10, 0.5) facing -x (heading pi): the odometry point (x, y) is the world's
  // (10 - x, 0.5 - y)
  const Scenario s = team_scenario(1, 60.0, {10.0, 0.5, kPi});
  Trace trace;
  TraceRecorder recorder(trace, 1.0, s.sim.dt);
  const RunResult r =
      run_once(s, kSeed, 0, std::ref(recorder), testing::snapshot_controllers(100, true));
  ASSERT_EQ(r.steps, 101);
  // at release, every 31 steps, and at the step that ended the run (101)
  ASSERT_EQ(trace.controller_snapshots.size(), 5u);
  EXPECT_EQ(trace.controller_snapshots[0].time, 0.0);
  EXPECT_EQ(trace.controller_snapshots[3].time, 93 * s.sim.dt);
  EXPECT_EQ(trace.controller_snapshots[4].time, r.time);

  const ControllerSnapshot& c = trace.controller_snapshots.front();
  EXPECT_EQ(c.agent, 0);
  EXPECT_EQ(c.start.x, 10.0);
  EXPECT_EQ(c.start.y, 0.5);
  EXPECT_EQ(c.start.heading, kPi);
  const Snapshot& w = c.snapshot;
  const std::vector<Vec2> points{{9.0, 0.5}, {10.0, -1.5}, {7.0, 1.5}};
  ASSERT_EQ(w.points.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR(w.points[i].x, points[i].x, 1e-12) << i;
    EXPECT_NEAR(w.points[i].y, points[i].y, 1e-12) << i;
  }
  EXPECT_EQ(w.weights, (std::vector<double>{1.0, 3.0, 2.0}));
  const std::vector<Vec2> path{{10.0, 0.5}, {9.0, -0.5}, {8.0, -0.5}};
  ASSERT_EQ(w.path.size(), path.size());
  for (std::size_t i = 0; i < path.size(); ++i) {
    EXPECT_NEAR(w.path[i].x, path[i].x, 1e-12) << i;
    EXPECT_NEAR(w.path[i].y, path[i].y, 1e-12) << i;
  }
  ASSERT_TRUE(w.has_estimate);
  EXPECT_NEAR(w.estimate.x, 8.0, 1e-12);
  EXPECT_NEAR(w.estimate.y, 1.5, 1e-12);
  // the grid keeps its odometry-frame geometry: a viewer draws it rotated by the start pose
  const Snapshot g = testing::every_layer();
  EXPECT_EQ(w.grid, g.grid);
  EXPECT_EQ(w.x0, g.x0);
  EXPECT_EQ(w.y0, g.y0);
  EXPECT_EQ(w.dx, g.dx);
  EXPECT_EQ(w.dy, g.dy);
  EXPECT_EQ(w.nx, g.nx);
  EXPECT_EQ(w.ny, g.ny);
  // the estimate and the declaration of the same point agree
  EXPECT_EQ(bits(trace.agents[0].declared.x), bits(w.estimate.x));
  EXPECT_EQ(bits(trace.agents[0].declared.y), bits(w.estimate.y));
}

TEST(TraceRecorder, NoSnapshotsWithoutAnInterval) {
  const Scenario s = team_scenario(2, 60.0);
  Trace trace;
  TraceRecorder recorder(trace, 0.0, s.sim.dt);
  run_team(s, kSeed, 0, std::ref(recorder), testing::snapshot_controllers(50, true));
  EXPECT_TRUE(trace.snapshots.empty());
  EXPECT_TRUE(trace.controller_snapshots.empty());
  EXPECT_EQ(trace.agents.size(), 2u);
}

// a controller whose snapshot is `shown`
class Showing final : public Controller {
 public:
  explicit Showing(Snapshot shown) : shown_(std::move(shown)) {}
  Command step(const Observation&, WindProbe&) override { return Command::go(0.0); }
  std::string_view state() const override { return "showing"; }
  int losses() const override { return 0; }
  Snapshot snapshot() const override { return shown_; }

 private:
  Snapshot shown_;
};

std::string refusal(const Snapshot& shown) {
  const Scenario s = team_scenario(1, 10.0);
  Trace trace;
  TraceRecorder recorder(trace, 1.0, s.sim.dt);
  try {
    run_once(s, kSeed, 0, std::ref(recorder),
             [&](const Scenario&, Rng) { return std::make_unique<Showing>(shown); });
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(TraceRecorder, ASnapshotTooLargeOrMalformedIsRefusedNamingTheController) {
  Snapshot big;
  big.nx = 1000, big.ny = 201;
  big.grid.assign(201000, 0.0);
  const std::string what = refusal(big);
  EXPECT_NE(what.find("controller 'casting' (robot 0)"), std::string::npos) << what;
  EXPECT_NE(what.find("201000 numbers"), std::string::npos) << what;
  EXPECT_NE(what.find("200000"), std::string::npos) << what;
  // the bound itself is fine: 100 000 points are 200 000 numbers
  Snapshot most;
  most.points.assign(kMaxSnapshotValues / 2, Vec2{1.0, 2.0});
  EXPECT_EQ(refusal(most), "no error");

  Snapshot weights;
  weights.points = {{1.0, 2.0}};
  weights.weights = {1.0, 2.0};
  EXPECT_NE(refusal(weights).find("2 weights for 1 points"), std::string::npos);
  Snapshot grid;
  grid.nx = 2, grid.ny = 2;
  grid.grid = {1.0};
  EXPECT_NE(refusal(grid).find("1 values for nx = 2, ny = 2"), std::string::npos);
  grid.grid = {1.0, 2.0, 3.0, 4.0};
  grid.dx = 0.0;
  EXPECT_NE(refusal(grid).find("cell size"), std::string::npos) << refusal(grid);
}

}  // namespace
}  // namespace plumetrace
