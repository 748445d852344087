#include "plumetrace/sim/world.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plumetrace/env/environment.hpp"
#include "plumetrace/env/filament_plume.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/trace.hpp"
#include "support/stepped_wind.hpp"

namespace plumetrace {
namespace {

constexpr std::uint64_t kSeed = 20080101;

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

// a scenario with one algorithm and a time limit, checked like a config file would be
Scenario make_scenario(Algorithm algorithm, double timeout) {
  Scenario s;
  s.controller.algorithm = algorithm;
  s.supervisor.timeout = timeout;
  validate(s);
  return s;
}

RobotState robot_at(double x, double y) { return {Pose{x, y, kPi}, 0.0}; }

// path length of one full-speed step (m)
double step_travel(const Scenario& s) { return s.robot.wheel_speed * s.sim.dt; }

// supervise()

TEST(Supervise, SuccessWithinTheRadiusOfTheSourceInXYBoundaryIncluded) {
  Scenario s;
  s.supervisor.success_radius = 0.25;  // exact in binary, so the boundary is exact too
  const double cx = s.source.center.x, cy = s.source.center.y;
  EXPECT_EQ(supervise(s, robot_at(cx, cy), 0.0), Outcome::kSuccess);
  EXPECT_EQ(supervise(s, robot_at(cx + 0.25, cy), 0.0), Outcome::kSuccess);
  EXPECT_EQ(supervise(s, robot_at(cx - 0.25, cy), 0.0), Outcome::kSuccess);
  EXPECT_EQ(supervise(s, robot_at(cx, cy + 0.25), 0.0), Outcome::kSuccess);
  EXPECT_EQ(supervise(s, robot_at(cx, cy - 0.25), 0.0), Outcome::kSuccess);
  EXPECT_EQ(supervise(s, robot_at(cx + 0.15, cy + 0.15), 0.0), Outcome::kSuccess);
  EXPECT_EQ(supervise(s, robot_at(std::nextafter(cx + 0.25, 2.0), cy), 0.0), Outcome::kRunning);
  EXPECT_EQ(supervise(s, robot_at(cx + 0.18, cy + 0.18), 0.0), Outcome::kRunning);
  // only (x, y) counts: a raised source is reached all the same
  s.source.center.z = 0.4;
  EXPECT_EQ(supervise(s, robot_at(cx + 0.25, cy), 0.0), Outcome::kSuccess);

  // the default radius: the robot body touches the source disc
  Scenario d;
  EXPECT_DOUBLE_EQ(d.supervisor.success_radius, d.source.radius + d.robot.radius);
  EXPECT_EQ(supervise(d, robot_at(d.source.center.x, 0.185), 0.0), Outcome::kSuccess);
  EXPECT_EQ(supervise(d, robot_at(d.source.center.x, 0.186), 0.0), Outcome::kRunning);
}

TEST(Supervise, WallWhenTheCentreIsCloserThanTheRobotRadiusToAnyWall) {
  Scenario s;
  const ArenaParams& a = s.arena;
  const double r = s.robot.radius;
  const double mid_x = 8.0, mid_y = 0.0;
  EXPECT_EQ(supervise(s, robot_at(mid_x, mid_y), 0.0), Outcome::kRunning);
  for (double margin : {0.0, 0.5 * r, 0.99 * r}) {
    EXPECT_EQ(supervise(s, robot_at(a.x_min + margin, mid_y), 0.0), Outcome::kWall) << margin;
    EXPECT_EQ(supervise(s, robot_at(a.x_max - margin, mid_y), 0.0), Outcome::kWall) << margin;
    EXPECT_EQ(supervise(s, robot_at(mid_x, a.y_min + margin), 0.0), Outcome::kWall) << margin;
    EXPECT_EQ(supervise(s, robot_at(mid_x, a.y_max - margin), 0.0), Outcome::kWall) << margin;
  }
  // just clear of each wall; at exactly one radius the body only touches (x_min = 0: exact)
  EXPECT_EQ(supervise(s, robot_at(a.x_min + r, mid_y), 0.0), Outcome::kRunning);
  EXPECT_EQ(supervise(s, robot_at(a.x_max - 1.01 * r, mid_y), 0.0), Outcome::kRunning);
  EXPECT_EQ(supervise(s, robot_at(mid_x, a.y_min + 1.01 * r), 0.0), Outcome::kRunning);
  EXPECT_EQ(supervise(s, robot_at(mid_x, a.y_max - 1.01 * r), 0.0), Outcome::kRunning);
}

TEST(Supervise, TimeoutOnceTheTimeReachesTheLimit) {
  Scenario s;
  s.supervisor.timeout = 100.0;
  const RobotState free = robot_at(8.0, 0.0);
  EXPECT_EQ(supervise(s, free, 0.0), Outcome::kRunning);
  EXPECT_EQ(supervise(s, free, std::nextafter(100.0, 0.0)), Outcome::kRunning);
  EXPECT_EQ(supervise(s, free, 100.0), Outcome::kTimeout);
  EXPECT_EQ(supervise(s, free, 250.0), Outcome::kTimeout);
}

// whole runs

TEST(WorldRun, SucceedsWhenStartedJustDownwindOfTheSource) {
  // as on the command line: --set controller.algorithm=surge-spiral --set robot.start_x=1.5
  const Scenario s = build_scenario(
      {parse_override("controller.algorithm=surge-spiral"), parse_override("robot.start_x=1.5")});
  for (std::uint64_t trial = 0; trial < 3; ++trial) {
    World world(s, kSeed, trial);
    Pose before = world.robot().pose;
    while (!world.done()) {
      before = world.robot().pose;
      world.step();
    }
    const RunResult r = world.result();
    EXPECT_EQ(r.outcome, Outcome::kSuccess);
    const auto to_source = [&](const Pose& p) {
      return std::hypot(p.x - s.source.center.x, p.y - s.source.center.y);
    };
    // the run ends at the first step that brings the centre within reach
    EXPECT_LE(to_source(world.robot().pose), s.supervisor.success_radius);
    EXPECT_GT(to_source(before), s.supervisor.success_radius);
    EXPECT_GT(r.d_u, 0.0);
    EXPECT_LT(r.time, 60.0);
  }
}

TEST(WorldRun, SucceedsAtTheFirstStepWhenTheStartIsWithinTheSuccessRadius) {
  Scenario s = make_scenario(Algorithm::kCasting, 1200.0);
  s.supervisor.success_radius = 15.0;
  const RunResult r = run_once(s, kSeed, 0);
  EXPECT_EQ(r.outcome, Outcome::kSuccess);
  EXPECT_EQ(r.steps, 1);
}

TEST(WorldRun, EndsAtTheWallWhenCastingStartsNextToIt) {
  Scenario s = make_scenario(Algorithm::kCasting, 1200.0);
  // 0.1 m from the left-hand wall, far outside the plume: whichever side casting picks, an
  // upwind leg or the crosswind leg after the loss runs into that wall
  s.robot.start.y = s.arena.y_max - 0.1;
  validate(s);
  for (std::uint64_t trial = 0; trial < 4; ++trial) {
    World world(s, kSeed, trial);
    while (!world.done()) world.step();
    EXPECT_EQ(world.outcome(), Outcome::kWall) << "trial " << trial;
    EXPECT_LT(s.arena.y_max - world.robot().pose.y, s.robot.radius);
    EXPECT_LT(world.time(), 60.0);
  }
}

TEST(WorldRun, TimesOutAtTheFirstStepReachingTheTimeLimit) {
  for (double timeout : {1.0, 2.5}) {
    const Scenario s = make_scenario(Algorithm::kSurgeSpiral, timeout);
    const RunResult r = run_once(s, kSeed, 1);
    EXPECT_EQ(r.outcome, Outcome::kTimeout);
    std::int64_t expected = 0;
    while (static_cast<double>(expected) * s.sim.dt < timeout) ++expected;
    EXPECT_EQ(r.steps, expected) << timeout;
    EXPECT_GE(r.time, timeout);
    EXPECT_LT(r.time - s.sim.dt, timeout);
  }
}

TEST(WorldRun, SurgeCastGivesUpWhenNoOdorIsEverPerceived) {
  const Scenario s = build_scenario(
      {parse_override("controller.algorithm=surge-cast"), parse_override("odor.threshold=1e30")});
  const SurgeCastParams& p = s.controller.get<SurgeCastParams>();
  for (std::uint64_t trial = 0; trial < 3; ++trial) {
    const RunResult r = run_once(s, kSeed, trial);
    EXPECT_EQ(r.outcome, Outcome::kGaveUp);
    EXPECT_EQ(r.losses, 1);
    EXPECT_EQ(r.wind_samples, 2) << "one at release, one at the loss";
    EXPECT_EQ(r.odor_fraction, 0.0);
    // a surge of d_lost, a cast of d_cast and one of 2 d_cast, each to within one step
    const double path = p.d_lost + 3.0 * p.d_cast;
    EXPECT_GE(r.d_t, path);
    EXPECT_LE(r.d_t, path + 3.0 * step_travel(s));
  }
}

// metrics

// A controller that drives straight along its release heading (odometry heading 0).
class Straight final : public Controller {
 public:
  Command step(const Observation&, WindProbe&) override { return Command::go(0.0); }
  std::string_view state() const override { return "straight"; }
  int losses() const override { return 0; }
};

// a straight run from (x, y) facing upwind toward a solid source of radius 5 cm, success only
// by touching it
RunResult straight_at_solid_source(double x, double y, Pose* end) {
  const Scenario s = build_scenario({parse_override("source.solid_radius=0.05"),
                                     parse_override("supervisor.success_radius=0"),
                                     parse_override("robot.start_x=" + std::to_string(x)),
                                     parse_override("robot.start_y=" + std::to_string(y))});
  World world(s, kSeed, 0, std::make_unique<Straight>());
  while (!world.done()) world.step();
  *end = world.robot().pose;
  return world.result();
}

TEST(WorldRun, TouchingASolidSourceIsSuccessAtTheContactDistance) {
  const Scenario d;
  const double contact = 0.05 + d.robot.radius;
  for (const double y : {0.0, 0.05, -0.1}) {
    Pose end;
    const RunResult r = straight_at_solid_source(3.0, y, &end);
    EXPECT_EQ(r.outcome, Outcome::kSuccess) << y;
    EXPECT_NEAR(std::hypot(end.x - d.source.center.x, end.y - d.source.center.y), contact, 1e-9);
    EXPECT_NEAR(r.d_t, 3.0 - end.x, 1e-9);
  }
}

TEST(WorldRun, PassingASolidSourceWiderThanContactGoesOnToTheWall) {
  const Scenario d;
  const double contact = 0.05 + d.robot.radius;
  Pose end;
  const RunResult r = straight_at_solid_source(3.0, contact + 0.01, &end);
  EXPECT_EQ(r.outcome, Outcome::kWall);
  EXPECT_LT(end.x, d.arena.x_min + d.robot.radius);
  EXPECT_NEAR(end.y, contact + 0.01, 1e-9);
}

TEST(RunMetrics, AgreeWithTheRobotsPathAndTheStepCount) {
  for (Algorithm algorithm : all_algorithms()) {
    const Scenario s = make_scenario(algorithm, 150.0);
    World world(s, kSeed, 2);
    double chords = 0.0;
    std::int64_t odor_steps = 0, samples = 0;
    Pose last = world.robot().pose;
    while (!world.done()) {
      world.step();
      const Pose& p = world.robot().pose;
      chords += std::hypot(p.x - last.x, p.y - last.y);
      last = p;
      odor_steps += world.odor();
      samples += world.wind_sensor().samples();
    }
    const RunResult r = world.result();
    const Pose& end = world.robot().pose;
    EXPECT_EQ(bits(r.d_t), bits(world.robot().odometer));
    EXPECT_EQ(bits(r.d_u), bits(s.robot.start.x - end.x));
    // (a random walk may end downwind of its start: its overhead is then NaN)
    if (r.d_u > 0.0) {
      EXPECT_EQ(bits(r.overhead), bits(r.d_t / r.d_u)) << algorithm_name(algorithm);
    } else {
      EXPECT_TRUE(std::isnan(r.overhead)) << algorithm_name(algorithm);
    }
    EXPECT_EQ(bits(r.time), bits(static_cast<double>(r.steps) * s.sim.dt));
    EXPECT_EQ(r.odor_fraction, static_cast<double>(odor_steps) / static_cast<double>(r.steps));
    EXPECT_EQ(r.wind_samples, samples);
    EXPECT_EQ(r.losses, world.controller().losses());
    EXPECT_EQ(r.seed, kSeed);
    EXPECT_EQ(r.trial, 2u);
    // the odometer is the path length: straight steps add their chord, arcs (the spirals of
    // surge-spiral, hayes and the particle filter, which rides on surge-spiral) a little more
    if (algorithm == Algorithm::kSurgeSpiral || algorithm == Algorithm::kHayes ||
        algorithm == Algorithm::kParticleFilter) {
      EXPECT_GE(r.d_t, chords - 1e-9);
      EXPECT_LE(r.d_t, chords * 1.01);
    } else {
      EXPECT_NEAR(r.d_t, chords, 1e-9 * r.d_t);
    }
  }
}

TEST(RunMetrics, OverheadIsNaNWithoutUpwindProgress) {
  // casting first turns on the spot by beta (0.18 s); stop it before it has driven
  const Scenario s = make_scenario(Algorithm::kCasting, 0.1);
  const RunResult r = run_once(s, kSeed, 0);
  EXPECT_EQ(r.outcome, Outcome::kTimeout);
  EXPECT_EQ(r.d_t, 0.0);
  EXPECT_EQ(r.d_u, 0.0);
  EXPECT_TRUE(std::isnan(r.overhead));
}

// reproducibility (docs/model.md section 10)

Trace record(const Scenario& s, std::uint64_t seed, std::uint64_t trial) {
  Trace trace;
  TraceRecorder recorder(trace, 5.0, s.sim.dt);
  run_once(s, seed, trial, std::ref(recorder));
  return trace;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (bits(a[i]) != bits(b[i])) return false;
  }
  return true;
}

bool same_step(const TraceStep& a, const TraceStep& b) {
  return bits(a.time) == bits(b.time) && bits(a.pose.x) == bits(b.pose.x) &&
         bits(a.pose.y) == bits(b.pose.y) && bits(a.pose.heading) == bits(b.pose.heading) &&
         bits(a.odometer) == bits(b.odometer) && a.state == b.state && a.odor == b.odor &&
         bits(a.concentration) == bits(b.concentration) && a.wind_samples == b.wind_samples &&
         bits(a.wind_body.x) == bits(b.wind_body.x) && bits(a.wind_body.y) == bits(b.wind_body.y) &&
         bits(a.wind_body.z) == bits(b.wind_body.z);
}

bool same_snapshot(const FilamentSnapshot& a, const FilamentSnapshot& b) {
  return bits(a.time) == bits(b.time) && same_bits(a.x, b.x) && same_bits(a.y, b.y) &&
         same_bits(a.z, b.z) && same_bits(a.w, b.w);
}

bool same_trace(const Trace& a, const Trace& b) {
  const auto &as = a.agents.front().steps, &bs = b.agents.front().steps;
  if (as.size() != bs.size() || a.snapshots.size() != b.snapshots.size()) return false;
  for (std::size_t i = 0; i < as.size(); ++i) {
    if (!same_step(as[i], bs[i])) return false;
  }
  for (std::size_t i = 0; i < a.snapshots.size(); ++i) {
    if (!same_snapshot(a.snapshots[i], b.snapshots[i])) return false;
  }
  return true;
}

TEST(Reproducibility, SameSeedAndTrialGiveABitIdenticalTrace) {
  for (Algorithm algorithm : all_algorithms()) {
    const Scenario s = make_scenario(algorithm, 60.0);
    const Trace a = record(s, kSeed, 3);
    const Trace b = record(s, kSeed, 3);
    const auto &as = a.agents.front().steps, &bs = b.agents.front().steps;
    ASSERT_GT(as.size(), 100u);
    ASSERT_GE(a.snapshots.size(), 2u);
    ASSERT_EQ(as.size(), bs.size());
    ASSERT_EQ(a.snapshots.size(), b.snapshots.size());
    for (std::size_t i = 0; i < as.size(); ++i) {
      ASSERT_TRUE(same_step(as[i], bs[i])) << algorithm_name(algorithm) << " step " << i;
    }
    for (std::size_t i = 0; i < a.snapshots.size(); ++i) {
      ASSERT_TRUE(same_snapshot(a.snapshots[i], b.snapshots[i]))
          << algorithm_name(algorithm) << " snapshot " << i;
    }
  }
}

TEST(Reproducibility, DifferentTrialOrSeedGivesADifferentTrace) {
  const Scenario s = make_scenario(Algorithm::kCasting, 30.0);
  const Trace a = record(s, kSeed, 3);
  EXPECT_FALSE(same_trace(a, record(s, kSeed, 4)));
  EXPECT_FALSE(same_trace(a, record(s, kSeed + 1, 3)));
  // already the plume at release differs
  const Trace b = record(s, kSeed, 4);
  ASSERT_FALSE(a.snapshots.empty());
  ASSERT_FALSE(b.snapshots.empty());
  EXPECT_FALSE(same_snapshot(a.snapshots.front(), b.snapshots.front()));
}

// the filaments of a world's plume
FilamentSpans filaments(const World& world) {
  return world.environment().odor->snapshot().filaments;
}

void expect_same_plume(const FilamentSpans& a, const FilamentSpans& b, const char* when) {
  ASSERT_EQ(a.size(), b.size()) << when;
  const auto same = [](std::span<const double> u, std::span<const double> v) {
    return same_bits({u.begin(), u.end()}, {v.begin(), v.end()});
  };
  EXPECT_TRUE(same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z) && same(a.w, b.w)) << when;
}

TEST(Reproducibility, TrialMeetsTheSamePlumeWhateverTheController) {
  // the sweep point (algorithm, its parameters, the wind-sensor noise) never enters the plume
  Scenario casting = make_scenario(Algorithm::kCasting, 1200.0);
  Scenario spiral = make_scenario(Algorithm::kSurgeSpiral, 1200.0);
  spiral.controller.get<SurgeSpiralParams>().d_gap = 0.111;
  spiral.wind_sensor.sigma_a = 0.5;
  Scenario cast = make_scenario(Algorithm::kSurgeCast, 1200.0);
  cast.controller.get<SurgeCastParams>().d_lost = 0.3;
  for (std::uint64_t trial : {0u, 7u}) {
    World a(casting, kSeed, trial), b(spiral, kSeed, trial), c(cast, kSeed, trial);
    ASSERT_GT(filaments(a).size(), 1000u);
    expect_same_plume(filaments(a), filaments(b), "after warm-up");
    expect_same_plume(filaments(a), filaments(c), "after warm-up");
    for (int i = 0; i < 500; ++i) {
      a.step();
      b.step();
      c.step();
    }
    ASSERT_FALSE(a.done() || b.done() || c.done());
    // the robots went their own ways, the plume did not
    EXPECT_NE(bits(a.robot().pose.y), bits(b.robot().pose.y));
    expect_same_plume(filaments(a), filaments(b), "after 500 steps");
    expect_same_plume(filaments(a), filaments(c), "after 500 steps");
  }
  // a different trial meets a different plume
  World t0(casting, kSeed, 0), t1(casting, kSeed, 1);
  EXPECT_NE(bits(filaments(t0).x[0]), bits(filaments(t1).x[0]));
}

bool same_result(const RunResult& a, const RunResult& b) {
  return a.outcome == b.outcome && bits(a.time) == bits(b.time) && bits(a.d_t) == bits(b.d_t) &&
         bits(a.d_u) == bits(b.d_u) && bits(a.overhead) == bits(b.overhead) &&
         a.losses == b.losses && bits(a.odor_fraction) == bits(b.odor_fraction) &&
         a.steps == b.steps && a.wind_samples == b.wind_samples && a.seed == b.seed &&
         a.trial == b.trial;
}

using testing::SteppedWind;

// Stands still and takes one wind sample per step (body frame x).
class WindLogger final : public Controller {
 public:
  explicit WindLogger(std::vector<double>& log) : log_(log) {}
  Command step(const Observation&, WindProbe& wind) override {
    log_.push_back(wind.measure_wind_body().x);
    return Command::stop();
  }
  std::string_view state() const override { return "logging"; }
  int losses() const override { return 0; }

 private:
  std::vector<double>& log_;
};

TEST(World, TheWindSensorAndThePlumeReadTheSameWindObject) {
  Scenario s;
  s.sim.warmup = 1.0;
  s.plume.sigma_p = 0.0;  // filaments move by the wind alone
  s.plume.gamma = 0.0;
  s.wind_sensor.sigma_a = 0.0;  // the sensor reads the wind itself
  s.robot.start.heading = 0.0;  // body frame = world frame
  Environment env;
  auto wind = std::make_unique<SteppedWind>();
  const SteppedWind& field = *wind;
  env.wind = std::move(wind);
  env.odor = std::make_unique<FilamentPlume>(s.plume, s.source, s.arena.x_max, 7);
  std::vector<double> sensed;
  World world(s, kSeed, 0, std::make_unique<WindLogger>(sensed), std::move(env));
  const int warmup_steps = 31;  // llround(1.0 / 0.032)
  ASSERT_EQ(field.steps, warmup_steps);
  EXPECT_NEAR(world.environment().time, warmup_steps * s.sim.dt, 1e-12);
  for (int k = 1; k <= 20; ++k) {
    const FilamentSpans before = filaments(world);
    const std::vector<double> x(before.x.begin(), before.x.end());
    world.step();
    // the field took one step per World step, however many readers it has
    ASSERT_EQ(field.steps, warmup_steps + k);
    ASSERT_EQ(sensed.size(), static_cast<std::size_t>(k));
    // the sensor read the field as it is after this step's advance ...
    EXPECT_DOUBLE_EQ(sensed.back(), 0.5 + 0.1 * (warmup_steps + k));
    // ... and the filaments moved in that same wind (the neighbouring steps' winds differ by
    // 0.1 m/s, 3.2 mm a step)
    const FilamentSpans after = filaments(world);
    ASSERT_GE(after.size(), x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_NEAR(after.x[i] - x[i], sensed.back() * s.sim.dt, 1e-12) << "step " << k;
    }
  }
}

TEST(World, AnEnvironmentWithoutWindOrOdorIsRefused) {
  const Scenario s;
  Environment no_odor;
  no_odor.wind = std::make_unique<ConstantWind>(s.wind.velocity);
  EXPECT_THROW(World(s, kSeed, 0, make_run_controller(s, kSeed, 0), std::move(no_odor)),
               std::invalid_argument);
  EXPECT_THROW(World(std::vector<const Scenario*>{}, kSeed, 0), std::invalid_argument);
}

TEST(World, AgentsInOneEnvironmentEqualSeparateRunsBitForBit) {
  std::vector<Scenario> scenarios;
  for (Algorithm algorithm : all_algorithms()) scenarios.push_back(make_scenario(algorithm, 300.0));
  scenarios[1].wind_sensor.sigma_a = 0.4;
  scenarios[2].robot.start.x = 8.0;
  scenarios.push_back(make_scenario(Algorithm::kCasting, 20.0));  // ends long before the others
  std::vector<const Scenario*> group;
  for (const auto& s : scenarios) group.push_back(&s);
  for (std::uint64_t trial : {0u, 1u}) {
    World world(group, kSeed, trial);
    ASSERT_EQ(world.agent_count(), scenarios.size());
    while (!world.done()) world.step();
    const std::vector<RunResult> together = world.results();
    ASSERT_EQ(together.size(), scenarios.size());
    for (std::size_t i = 0; i < scenarios.size(); ++i) {
      EXPECT_TRUE(same_result(together[i], run_once(scenarios[i], kSeed, trial)))
          << "agent " << i << " trial " << trial;
      EXPECT_TRUE(same_result(world.agent(i).result(), together[i]));
    }
    EXPECT_TRUE(same_result(world.result(), together[0]));
  }
}

TEST(Reproducibility, RunOnceIsAPureFunctionOfScenarioSeedAndTrial) {
  for (Algorithm algorithm : all_algorithms()) {
    const Scenario s = make_scenario(algorithm, 300.0);
    const RunResult first = run_once(s, kSeed, 5);
    // another run in between must not leak into the replay
    const RunResult other = run_once(s, kSeed, 6);
    const RunResult again = run_once(s, kSeed, 5);
    EXPECT_TRUE(same_result(first, again)) << algorithm_name(algorithm);
    EXPECT_FALSE(same_result(first, other)) << algorithm_name(algorithm);
    EXPECT_GT(first.steps, 10);
  }
}

// Scenarios that stay coherent (docs/scenarios.md): the plume reaches the robot however the
// wind or the source is set

Scenario scenario_of(const std::vector<const char*>& overrides, double timeout) {
  std::vector<Setting> settings;
  for (const char* o : overrides) settings.push_back(parse_override(o));
  settings.push_back(parse_override("supervisor.timeout=" + std::to_string(timeout)));
  return build_scenario(settings);
}

// how many of the runs of the paper's algorithms sense odor within `seconds` of release
int runs_finding_odor(const std::vector<const char*>& overrides, double seconds, int trials) {
  int found = 0;
  for (const Algorithm algorithm : builtin_algorithms()) {
    Scenario s = scenario_of(overrides, seconds);
    s.controller.algorithm = algorithm;
    for (int trial = 0; trial < trials; ++trial) {
      World world(s, kSeed, static_cast<std::uint64_t>(trial));
      bool odor = world.odor();
      while (!world.done() && !odor) {
        world.step();
        odor = world.odor();
      }
      found += odor;
    }
  }
  return found;
}

TEST(CoherentScenarios, ASlowerWindOrAMovedSourceStillReachesTheRobot) {
  constexpr int kTrials = 10, kRuns = 3 * kTrials;
  // why 90%: a robot released at the plume's end senses it within 15 s in every run of the
  // paper's setup (30 of 30 measured, as here for each case); the wind sensor's noise at a slow
  // wind may steer a run off the plume's side first
  for (const auto& set : std::vector<std::vector<const char*>>{
           {}, {"wind.vx=0.5"}, {"wind.vx=0.3"}, {"source.y=1.0"}, {"source.y=-1.2"}}) {
    const std::string name = set.empty() ? "default" : set.front();
    EXPECT_GE(runs_finding_odor(set, 15.0, kTrials), 0.9 * kRuns) << name;
    EXPECT_TRUE(scenario_warnings(scenario_of(set, 15.0)).empty()) << name;
  }
  // as before derivation: the 1600-filament ring ends the plume 8 m downwind at 0.5 m/s, and
  // a start that stays put misses a moved source; no run can sense odor in 15 s
  EXPECT_EQ(
      runs_finding_odor({"wind.vx=0.5", "plume.capacity=1600", "sim.warmup=20"}, 15.0, kTrials), 0);
  EXPECT_EQ(runs_finding_odor({"source.y=1.0", "robot.start_y=0"}, 15.0, kTrials), 0);
}

}  // namespace
}  // namespace plumetrace
