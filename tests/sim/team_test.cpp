// Tests of sim/world.hpp for teams: identity, contacts, messages, declarations, walls and
// start distributions (docs/agents.md).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "plumetrace/agent/controllers.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {
namespace {

constexpr std::uint64_t kSeed = 20080101;

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

// the results agree bit for bit
void expect_same(const RunResult& a, const RunResult& b) {
  EXPECT_EQ(a.outcome, b.outcome);
  EXPECT_EQ(bits(a.time), bits(b.time));
  EXPECT_EQ(bits(a.d_t), bits(b.d_t));
  EXPECT_EQ(bits(a.d_u), bits(b.d_u));
  EXPECT_EQ(a.losses, b.losses);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.wind_samples, b.wind_samples);
  EXPECT_EQ(bits(a.t_first_odor), bits(b.t_first_odor));
}

Scenario scenario(Algorithm algorithm, double timeout) {
  Scenario s;
  s.controller.algorithm = algorithm;
  s.supervisor.timeout = timeout;
  validate(s);
  return s;
}

// A controller that drives toward one heading (odometry frame) and may send, read, declare.
class Scripted final : public Controller {
 public:
  using Step = std::function<Command(const Observation&)>;
  Scripted(Step step, unsigned reads) : step_(std::move(step)), reads_(reads) {}
  Command step(const Observation& obs, WindProbe&) override { return step_(obs); }
  std::string_view state() const override { return "scripted"; }
  int losses() const override { return 0; }
  unsigned reads() const override { return reads_; }

 private:
  Step step_;
  unsigned reads_;
};

// the k-th controller a factory builds gets steps[k] (agents are built in index order)
ControllerFactory scripted(std::vector<Scripted::Step> steps, unsigned reads = kReadsBinary) {
  auto made = std::make_shared<std::size_t>(0);
  return [steps, reads, made](const Scenario&, Rng) -> std::unique_ptr<Controller> {
    const std::size_t k = (*made)++ % steps.size();
    return std::make_unique<Scripted>(steps[k], reads);
  };
}

TEST(Team, DerivedSeedsOfAgentZeroAreTheRobotAlonesAndOthersDiffer) {
  for (const Stream s : {Stream::kPlume, Stream::kWindSensor, Stream::kController}) {
    EXPECT_EQ(derive_seed(kSeed, 3, s, 0), derive_seed(kSeed, 3, s));
    EXPECT_NE(derive_seed(kSeed, 3, s, 1), derive_seed(kSeed, 3, s));
    EXPECT_NE(derive_seed(kSeed, 3, s, 1), derive_seed(kSeed, 3, s, 2));
  }
}

TEST(Team, ATeamOfOneIsTheRobotAlone) {
  for (const Algorithm a : library_algorithms()) {
    const Scenario s = scenario(a, 300.0);
    const std::vector<RunResult> team = run_team(s, kSeed, 1);
    ASSERT_EQ(team.size(), 1u);
    World alone(s, kSeed, 1);
    while (!alone.done()) alone.step();
    expect_same(team[0], alone.result());
    EXPECT_EQ(team[0].agent, 0);
  }
}

TEST(Team, WithoutContactRobotZeroOfATeamTakesTheStepsItTakesAlone) {
  for (const Algorithm a : library_algorithms()) {
    Scenario s = scenario(a, 300.0);
    const RunResult alone = run_once(s, kSeed, 2);
    s.team.count = 4;
    s.team.contact = TeamParams::Contact::kOff;
    validate(s);
    const std::vector<RunResult> team = run_team(s, kSeed, 2);
    ASSERT_EQ(team.size(), 4u);
    expect_same(team[0], alone);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(team[static_cast<std::size_t>(k)].agent, k);
    // the others have streams and starts of their own
    EXPECT_NE(bits(team[1].d_t), bits(team[2].d_t));
  }
}

TEST(Team, TeamsInOneWorldDoNotSeeEachOther) {
  Scenario a = scenario(Algorithm::kSurgeSpiral, 200.0);
  a.team.count = 3;
  Scenario b = a;
  b.controller.algorithm = Algorithm::kCasting;
  const std::vector<RunResult> ab = [&] {
    World w({&a, &b}, kSeed, 4);
    while (!w.done()) w.step();
    return w.results();
  }();
  const std::vector<RunResult> ta = run_team(a, kSeed, 4), tb = run_team(b, kSeed, 4);
  ASSERT_EQ(ab.size(), 6u);
  for (std::size_t k = 0; k < 3; ++k) {
    expect_same(ab[k], ta[k]);
    expect_same(ab[3 + k], tb[k]);
  }
}

// Two robots side by side (robot 1 is 0.3 m to robot 0's left, at y = -0.3 facing -x) drive
// toward each other.
std::vector<RunResult> head_on(TeamParams::Contact contact, std::vector<double>* gaps) {
  Scenario s = scenario(Algorithm::kCasting, 10.0);
  s.team.count = 2;
  s.team.contact = contact;
  validate(s);
  // world heading = odometry heading + pi: robot 0 faces -y (odometry pi/2), robot 1 +y
  const auto go = [](double h) { return [h](const Observation&) { return Command::go(h); }; };
  World w({&s}, kSeed, 0, scripted({go(kPi / 2), go(-kPi / 2)}));
  while (!w.done()) {
    w.step();
    const auto& p0 = w.agent(0).robot().pose;
    const auto& p1 = w.agent(1).robot().pose;
    if (gaps) gaps->push_back(std::hypot(p0.x - p1.x, p0.y - p1.y));
  }
  return w.results();
}

TEST(Team, BodiesInContactStopAndNeverOverlap) {
  std::vector<double> gaps;
  const auto results = head_on(TeamParams::Contact::kOn, &gaps);
  const double r = RobotParams{}.radius;
  const double travel = RobotParams{}.wheel_speed * SimParams{}.dt;
  ASSERT_FALSE(gaps.empty());
  for (const double g : gaps) EXPECT_GE(g, 2.0 * r - 1e-9);
  // head on, there is nothing to slide along: they stopped within one step's travel each of
  // touching, and moved no more after
  EXPECT_LT(gaps.back(), 2.0 * r + 2.0 * travel);
  EXPECT_EQ(results[0].outcome, Outcome::kTimeout);
  // each drove (0.3 - 2 r) / 2 toward the other, to within a step: the rest was blocked
  EXPECT_NEAR(results[0].d_t, (0.3 - 2.0 * r) / 2.0, travel + 1e-12);
  EXPECT_NEAR(results[0].d_t, results[1].d_t, 1e-12);
}

// Robots that meet at an angle slide along each other: neither stands still, neither overlaps
// (the contact rule of docs/agents.md). Robot 0 drives toward -y and robot 1 toward +y, each
// also toward -x at the angle `tilt` from the line between them.
TEST(Team, BodiesMeetingAtAnAngleSlideAlongEachOther) {
  constexpr double tilt = 0.4;
  constexpr double seconds = 10.0;
  Scenario s = scenario(Algorithm::kCasting, seconds);
  s.team.count = 2;
  validate(s);
  const auto go = [](double h) { return [h](const Observation&) { return Command::go(h); }; };
  World w({&s}, kSeed, 0, scripted({go(kPi / 2 - tilt), go(-kPi / 2 + tilt)}));
  const double r = RobotParams{}.radius;
  const double v = RobotParams{}.wheel_speed;
  const double travel = v * SimParams{}.dt;
  double closest = 1e9;
  while (!w.done()) {
    w.step();
    const auto& p0 = w.agent(0).robot().pose;
    const auto& p1 = w.agent(1).robot().pose;
    closest = std::min(closest, std::hypot(p0.x - p1.x, p0.y - p1.y));
  }
  const auto results = w.results();
  // they touched, within a nanometre, and never overlapped by more
  EXPECT_GE(closest, 2.0 * r - 1e-9);
  EXPECT_LT(closest, 2.0 * r + travel);
  for (const RunResult& res : results) {
    EXPECT_EQ(res.outcome, Outcome::kTimeout);
    // the move along -x is across the contact, so it is never lost: after the turn toward the
    // heading (under a second), the robot moves toward -x at v sin(tilt) the whole run
    EXPECT_NEAR(res.d_u, v * std::sin(tilt) * seconds, v * 1.0);
    // it drove on after touching: more than the (0.3 - 2 r) / 2 / cos(tilt) it took to meet
    EXPECT_GT(res.d_t, 2.0 * (0.3 - 2.0 * r) / 2.0 / std::cos(tilt));
  }
  EXPECT_NEAR(results[0].d_t, results[1].d_t, 1e-9);
}

TEST(Team, WithoutContactBodiesPassThroughEachOther) {
  std::vector<double> gaps;
  head_on(TeamParams::Contact::kOff, &gaps);
  double smallest = 1e9;
  for (const double g : gaps) smallest = std::min(smallest, g);
  EXPECT_LT(smallest, 2.0 * RobotParams{}.radius);
}

// messages: each robot sends its odometer and records what it gets
struct Inbox {
  std::vector<std::vector<Message>> got;  // per step, what robot 1 received
};

std::shared_ptr<Inbox> exchange(double range, double delay, int steps) {
  Scenario s = scenario(Algorithm::kCasting, static_cast<double>(steps) * SimParams{}.dt);
  s.team.count = 2;
  s.team.range = range;
  s.team.delay = delay;
  validate(s);
  auto inbox = std::make_shared<Inbox>();
  const auto sender = [](const Observation& o) {
    return Command::stop().with_message({o.time, 1.0, 2.0, 3.0});
  };
  const auto receiver = [inbox](const Observation& o) {
    inbox->got.emplace_back(o.messages.begin(), o.messages.end());
    return Command::stop();
  };
  World w({&s}, kSeed, 0, scripted({sender, receiver}, kReadsMessages));
  while (!w.done()) w.step();
  return inbox;
}

TEST(Team, AMessageArrivesTheNextStepOrAfterItsDelay) {
  const double dt = SimParams{}.dt;
  const auto now = exchange(INFINITY, 0.0, 10);
  ASSERT_EQ(now->got.size(), 10u);
  EXPECT_TRUE(now->got[0].empty());  // nothing is sent before the first step
  for (std::size_t k = 1; k < 10; ++k) {
    ASSERT_EQ(now->got[k].size(), 1u) << "step " << k + 1;
    EXPECT_EQ(now->got[k][0].from, 0);
    EXPECT_DOUBLE_EQ(now->got[k][0].sent, static_cast<double>(k) * dt);
    EXPECT_DOUBLE_EQ(now->got[k][0].data[0], static_cast<double>(k) * dt);
    EXPECT_DOUBLE_EQ(now->got[k][0].data[3], 3.0);
  }
  // 0.1 s at 0.032 s a step: the fourth step after sending
  const auto later = exchange(INFINITY, 0.1, 10);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_TRUE(later->got[k].empty()) << "step " << k + 1;
  for (std::size_t k = 4; k < 10; ++k) {
    ASSERT_EQ(later->got[k].size(), 1u);
    EXPECT_DOUBLE_EQ(later->got[k][0].sent, static_cast<double>(k - 3) * dt);
  }
  // the robots start 0.3 m apart: a range of 0.2 m carries nothing
  const auto far = exchange(0.2, 0.0, 10);
  for (const auto& step : far->got) EXPECT_TRUE(step.empty());
}

TEST(Team, ADeclarationIsScoredByItsDistanceToTheSource) {
  Scenario s = scenario(Algorithm::kCasting, 60.0);
  // the source in the odometry frame of a robot at the start facing -x: ahead by the offset
  const double ahead = s.robot.start.x - s.source.center.x;
  const auto declare_at = [&](double miss) {
    World w(s, kSeed, 0,
            std::make_unique<Scripted>(
                [=](const Observation&) {
                  return Command::declare_source({ahead, miss});
                },
                kReadsBinary));
    while (!w.done()) w.step();
    return w.result();
  };
  const RunResult hit = declare_at(0.3);
  EXPECT_EQ(hit.outcome, Outcome::kSuccess);
  EXPECT_NEAR(hit.declaration_error, 0.3, 1e-12);
  EXPECT_EQ(hit.steps, 1);
  const RunResult miss = declare_at(0.7);
  EXPECT_EQ(miss.outcome, Outcome::kWrongDeclaration);
  EXPECT_NEAR(miss.declaration_error, 0.7, 1e-12);
  // without a declaration the error is NaN
  EXPECT_TRUE(std::isnan(run_once(s, kSeed, 0).declaration_error));
}

TEST(Team, UnderTheDeclareRuleReachingTheSourceIsNotSuccess) {
  Scenario s = scenario(Algorithm::kSurgeSpiral, 400.0);
  const RunResult reach = run_once(s, kSeed, 0);
  ASSERT_EQ(reach.outcome, Outcome::kSuccess);
  s.supervisor.success = SuccessRule::kDeclare;
  const RunResult declare = run_once(s, kSeed, 0);
  EXPECT_NE(declare.outcome, Outcome::kSuccess);
  EXPECT_GT(declare.time, reach.time);
}

TEST(Team, WallsThatBlockKeepTheRobotInsideAndNeverEndTheRun) {
  Scenario s = scenario(Algorithm::kCasting, 60.0);
  s.supervisor.walls = WallRule::kBlock;
  // drive to the right-hand wall (world heading -pi/2 is odometry pi/2)
  World w(s, kSeed, 0,
          std::make_unique<Scripted>([](const Observation&) { return Command::go(kPi / 2); }, 0));
  const double r = s.robot.radius;
  while (!w.done()) {
    w.step();
    EXPECT_GE(w.robot().pose.y - s.arena.y_min, r);
  }
  EXPECT_EQ(w.outcome(), Outcome::kTimeout);
  EXPECT_LT(w.robot().pose.y - s.arena.y_min, r + 0.01);
  s.supervisor.walls = WallRule::kEnd;
  World end(s, kSeed, 0,
            std::make_unique<Scripted>([](const Observation&) { return Command::go(kPi / 2); }, 0));
  while (!end.done()) end.step();
  EXPECT_EQ(end.outcome(), Outcome::kWall);
}

TEST(Team, StartsInARegionAreInsideItApartAndUniform) {
  Scenario s = scenario(Algorithm::kCasting, 60.0);
  s.start.region = StartRegion::kRectangle;
  s.team.count = 5;
  validate(s);
  const Environment env = make_environment(s, kSeed, 0);
  double mean_x = 0.0, mean_y = 0.0;
  const int trials = 400;
  for (int t = 0; t < trials; ++t) {
    const std::vector<Pose> starts = team_starts(s, kSeed, static_cast<std::uint64_t>(t), env);
    ASSERT_EQ(starts.size(), 5u);
    for (std::size_t i = 0; i < starts.size(); ++i) {
      const double x = starts[i].x - s.source.center.x, y = starts[i].y - s.source.center.y;
      EXPECT_GE(x, s.start.x_min);
      EXPECT_LE(x, s.start.x_max);
      EXPECT_GE(y, s.start.y_min);
      EXPECT_LE(y, s.start.y_max);
      EXPECT_DOUBLE_EQ(starts[i].heading, s.robot.start.heading);
      for (std::size_t j = 0; j < i; ++j) {
        EXPECT_GE(std::hypot(starts[i].x - starts[j].x, starts[i].y - starts[j].y),
                  2.0 * s.robot.radius);
      }
      mean_x += x;
      mean_y += y;
    }
  }
  // uniform: the means of 2000 draws within 4 standard errors of the centre
  const double n = 5.0 * trials;
  const double w = s.start.x_max - s.start.x_min, h = s.start.y_max - s.start.y_min;
  EXPECT_NEAR(mean_x / n, (s.start.x_min + s.start.x_max) / 2, 4.0 * w / std::sqrt(12.0 * n));
  EXPECT_NEAR(mean_y / n, (s.start.y_min + s.start.y_max) / 2, 4.0 * h / std::sqrt(12.0 * n));
  // the same (seed, trial) gives the same starts
  const auto again = team_starts(s, kSeed, 7, env), once = team_starts(s, kSeed, 7, env);
  for (std::size_t i = 0; i < once.size(); ++i) EXPECT_EQ(bits(again[i].x), bits(once[i].x));
}

TEST(Team, AStartInOdorPerceivesOdorAtRelease) {
  Scenario s = scenario(Algorithm::kCasting, 60.0);
  s.start.region = StartRegion::kDisc;
  s.start.condition = StartCondition::kInOdor;
  s.start.heading = StartHeading::kRandom;
  validate(s);
  Environment env = make_environment(s, kSeed, 3);
  warm_up(s, env);
  const std::vector<Pose> starts = team_starts(s, kSeed, 3, env);
  ASSERT_EQ(starts.size(), 1u);
  EXPECT_TRUE(sense_odor(s.odor, *env.odor, starts[0]));
  EXPECT_NE(starts[0].heading, s.robot.start.heading);
  // the plume-finding metrics of a robot released in odor: it perceives odor within steps
  const RunResult r = run_once(s, kSeed, 3);
  EXPECT_FALSE(std::isnan(r.t_first_odor));
  EXPECT_LE(r.d_first_odor, r.d_t);
}

TEST(Team, ARobotThatNeverMeetsOdorHasNoFirstDetection) {
  Scenario s = scenario(Algorithm::kCasting, 5.0);
  // upwind of the source, where no filament goes
  s.robot.start_x_auto = false;
  s.robot.start.x = 0.5;
  validate(s);
  const RunResult r = run_once(s, kSeed, 0);
  EXPECT_TRUE(std::isnan(r.t_first_odor));
  EXPECT_TRUE(std::isnan(r.d_first_odor));
}

// A built-in controller that also asks for the concentration, and checks what it gets.
class Reading final : public Controller {
 public:
  Reading(std::unique_ptr<Controller> inner, double threshold)
      : inner_(std::move(inner)), threshold_(threshold) {}
  Command step(const Observation& obs, WindProbe& wind) override {
    EXPECT_FALSE(std::isnan(obs.concentration));
    EXPECT_EQ(obs.odor, obs.concentration >= threshold_);
    ++readings;
    return inner_->step(obs, wind);
  }
  std::string_view state() const override { return inner_->state(); }
  int losses() const override { return inner_->losses(); }
  unsigned reads() const override { return kReadsConcentration; }
  int readings = 0;

 private:
  std::unique_ptr<Controller> inner_;
  double threshold_;
};

TEST(Team, ReadingTheConcentrationChangesNothingWithTheIdealSensor) {
  for (const Algorithm a : builtin_algorithms()) {
    const Scenario s = scenario(a, 300.0);
    const RunResult binary = run_once(s, kSeed, 5);
    const RunResult reading = run_once(s, kSeed, 5, {}, [](const Scenario& sc, Rng rng) {
      return std::make_unique<Reading>(make_controller(sc.controller, rng), sc.odor.threshold);
    });
    expect_same(reading, binary);
  }
}

TEST(Team, AFirstOrderSensorDelaysTheFirstDetection) {
  Scenario s = scenario(Algorithm::kSurgeSpiral, 300.0);
  s.start.region = StartRegion::kRectangle;  // mostly outside odor: a first detection to delay
  validate(s);
  int earlier = 0, later = 0;
  for (std::uint64_t t = 0; t < 10; ++t) {
    const RunResult ideal = run_once(s, kSeed, t);
    Scenario mox = s;
    mox.odor.model = SensorModel::kFirstOrder;
    // why: fast enough to reach the threshold on this plume's brief filament peaks (the MOX
    // defaults smooth them below it: docs/agents.md)
    mox.odor.get<FirstOrderSensorParams>().tau_rise = 0.1;
    mox.odor.get<FirstOrderSensorParams>().tau_decay = 0.5;
    const RunResult slow = run_once(mox, kSeed, t);
    if (std::isnan(ideal.t_first_odor) || std::isnan(slow.t_first_odor)) continue;
    // the same start and path up to the ideal sensor's first detection, which the lagging
    // sensor cannot make sooner
    if (slow.t_first_odor < ideal.t_first_odor) ++earlier;
    if (slow.t_first_odor > ideal.t_first_odor) ++later;
  }
  EXPECT_EQ(earlier, 0);
  EXPECT_GT(later, 0);
}

// the settings are refused before any run, with a message naming `key`
void refused(const std::vector<Setting>& settings, const std::string& key) {
  try {
    build_scenario(settings);
    ADD_FAILURE() << "accepted; expected an error naming " << key;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

TEST(Team, BadTeamsAndStartsAreRefusedNamingTheKey) {
  const auto set = [](const char* key, ConfigValue v) {
    return Setting{key, std::move(v), false, "test", Layer::kCommandLine};
  };
  refused({set("team.count", std::int64_t{0})}, "team.count");
  refused({set("team.count", std::int64_t{kMaxTeam + 1})}, "team.count");
  refused({set("team.count", std::int64_t{2}), set("team.spacing", 0.1)}, "team.spacing");
  refused({set("team.count", std::int64_t{20})}, "team.count");  // 3 m to one side: a wall
  refused({set("team.range", -1.0)}, "team.range");
  refused({set("team.delay", -0.5)}, "team.delay");
  refused({set("supervisor.declaration_radius", 0.0)}, "supervisor.declaration_radius");
  refused({set("odor.model", std::string("mox"))}, "odor.model");
  refused({set("start.region", std::string("rectangle")), set("start.y_min", 3.0),
           set("start.y_max", 4.0)},
          "start.y_min");
  refused({set("start.region", std::string("disc")), set("start.cy", 5.0)}, "start.cx");
  refused({set("start.region", std::string("disc")), set("start.radius", 0.2),
           set("team.count", std::int64_t{10})},
          "team.count");
  refused({set("start.condition", std::string("in_odor"))}, "start.condition");
}

Setting setting(const char* key, ConfigValue v) {
  return Setting{key, std::move(v), false, "test", Layer::kCommandLine};
}

// A mixed team: robot 1 runs surge-spiral with its own d_lost beside robot 0's casting. With
// contacts off the robots do not meet, so each takes exactly the steps it takes in a team of
// its own algorithm and keys: its own keys reach it and no other robot.
TEST(Team, ARobotOfAMixedTeamRunsItsOwnAlgorithmAndKeys) {
  const auto team = [](std::vector<Setting> extra) {
    std::vector<Setting> settings{setting("team.count", std::int64_t{2}),
                                  setting("team.contact", std::string("off")),
                                  setting("supervisor.timeout", 300.0)};
    settings.insert(settings.end(), extra.begin(), extra.end());
    return build_scenario(settings);
  };
  const Scenario mixed =
      team({setting("member.1.controller.algorithm", std::string("surge-spiral")),
            setting("member.1.surge_spiral.d_lost", 0.5)});
  const Scenario casting = team({});
  const Scenario spiral = team({setting("controller.algorithm", std::string("surge-spiral")),
                                setting("surge_spiral.d_lost", 0.5)});
  for (std::uint64_t t = 0; t < 3; ++t) {
    const std::vector<RunResult> m = run_team(mixed, kSeed, t);
    const std::vector<RunResult> c = run_team(casting, kSeed, t);
    const std::vector<RunResult> sp = run_team(spiral, kSeed, t);
    ASSERT_EQ(m.size(), 2u);
    expect_same(m[0], c[0]);
    expect_same(m[1], sp[1]);
  }
  // the robot's scenario is the team's with its keys; robot 0's is the team's
  EXPECT_EQ(member_scenario(mixed, 1).controller.algorithm, Algorithm::kSurgeSpiral);
  EXPECT_EQ(member_scenario(mixed, 0).controller.algorithm, Algorithm::kCasting);
  // a mixed team is another run: its identity differs, and it reads back from its own file
  EXPECT_NE(canonical_config(mixed), canonical_config(casting));
  Scenario back = team({});
  std::vector<Setting> again;
  for_each_value(mixed, [&](const FieldValue& f) {
    if (std::string(f.table).starts_with("member.")) {
      again.push_back(Setting{std::string(f.table) + "." + std::string(f.name), f.value, false,
                              "test", Layer::kFile});
    }
  });
  EXPECT_EQ(again.size(), 2u);
  for (const Setting& x : again) set_field(back, x.key, x.value);
  EXPECT_EQ(canonical_config(back), canonical_config(mixed));
  EXPECT_NE(scenario_to_toml(mixed).find("[member.1.surge_spiral]"), std::string::npos);
}

TEST(Team, ARobotWithItsOwnStartIsReleasedThere) {
  const Scenario s = build_scenario(
      {setting("team.count", std::int64_t{3}), setting("member.2.robot.start_x", 12.0),
       setting("member.2.robot.start_y", 1.0), setting("member.2.robot.start_heading_deg", 90.0)});
  const std::vector<Pose> starts = point_starts(s);
  ASSERT_EQ(starts.size(), 3u);
  // robots 0 and 1 in the line, robot 2 where it says
  EXPECT_EQ(starts[0].x, s.robot.start.x);
  EXPECT_NEAR(std::hypot(starts[1].x - starts[0].x, starts[1].y - starts[0].y), s.team.spacing,
              1e-12);
  EXPECT_EQ(starts[2].x, 12.0);
  EXPECT_EQ(starts[2].y, 1.0);
  EXPECT_NEAR(starts[2].heading, kPi / 2, 1e-12);
  World w({&s}, kSeed, 0);
  EXPECT_EQ(w.agent(2).robot().pose.x, 12.0);
  EXPECT_EQ(w.agent(2).robot().pose.y, 1.0);
}

TEST(Team, BadMemberKeysAreRefusedNamingTheKey) {
  const Setting two = setting("team.count", std::int64_t{2});
  const std::string spiral = "surge-spiral";
  // no such robot, robot 0 (the scenario's own keys), no robot number
  refused({two, setting("member.2.controller.algorithm", spiral)}, "member.2.controller.algorithm");
  refused({two, setting("member.0.controller.algorithm", spiral)}, "member.0.controller");
  refused({two, setting("member.x.controller.algorithm", spiral)}, "member.x.controller");
  // the world's and the team's keys are one for all; so is the body's radius
  refused({two, setting("member.1.wind.vx", 0.5)}, "member.1.wind.vx");
  refused({two, setting("member.1.team.range", 1.0)}, "member.1.team.range");
  refused({two, setting("member.1.robot.radius", 0.1)}, "member.1.robot.radius");
  // an unknown key, a bad value, an unknown algorithm
  refused({two, setting("member.1.casting.nope", 1.0)}, "member.1.casting.nope");
  refused({two, setting("member.1.casting.d_lost", -1.0)}, "member.1.casting.d_lost");
  refused({two, setting("member.1.controller.algorithm", std::string("zigzag9"))},
          "member.1.controller.algorithm");
  // an own start inside robot 0, outside the arena, or in a start region
  refused({two, setting("member.1.robot.start_y", 0.05)}, "member.1.robot.start_x");
  refused({two, setting("member.1.robot.start_y", 5.0)}, "member.1");
  refused({two, setting("start.region", std::string("rectangle")),
           setting("member.1.robot.start_x", 12.0)},
          "member.1.robot.start_x");
}

// A controller's stand-in in a world driven from outside: it reads and counts losses as the
// controller it holds, which the test asks for the commands instead of the world.
class Held final : public Controller {
 public:
  explicit Held(std::unique_ptr<Controller> inner) : inner_(std::move(inner)) {}
  Command step(const Observation&, WindProbe&) override {
    throw std::logic_error("a held controller is asked from outside");
  }
  std::string_view state() const override { return inner_->state(); }
  int losses() const override { return inner_->losses(); }
  unsigned reads() const override { return inner_->reads(); }
  Controller& inner() { return *inner_; }

 private:
  std::unique_ptr<Controller> inner_;
};

// run (seed, trial) of the scenario's team, every robot decided from outside by the
// controller the built-in run gives it (the same algorithm, keys and controller stream)
std::vector<RunResult> driven_from_outside(const Scenario& s, std::uint64_t seed,
                                           std::uint64_t trial) {
  std::vector<Held*> held;
  const ControllerFactory factory = [&held](const Scenario& own, Rng rng) {
    auto h = std::make_unique<Held>(make_controller(own.controller, rng));
    held.push_back(h.get());
    return h;
  };
  World w({&s}, seed, trial, factory);
  std::vector<Command> commands(w.agent_count());
  while (!w.done()) {
    const std::vector<Observation>& seen = w.observe_team();
    for (std::size_t i = 0; i < commands.size(); ++i) {
      if (!w.agent(i).done()) commands[i] = held[i]->inner().step(seen[i], w.wind_probe(i));
    }
    w.act_team(commands);
  }
  return w.results();
}

// Every library algorithm in a team of three on the benchmark's team task (strong meander,
// walls that block, robots 0.3 m apart, contacts on), with messages that carry 1 m and arrive
// after 0.1 s: observe_team and act_team with the controllers' commands are World::step, bit
// for bit, for every robot.
TEST(Team, ATeamDrivenFromOutsideWithItsControllersCommandsIsTheBuiltInRun) {
  for (const Algorithm a : library_algorithms()) {
    const std::string name(algorithm_name(a));
    const Scenario s = build_scenario(
        {setting("controller.algorithm", name), setting("supervisor.timeout", 25.0),
         setting("supervisor.walls", std::string("block")), setting("team.count", std::int64_t{3}),
         setting("team.range", 1.0), setting("team.delay", 0.1),
         setting("wind.model", std::string("meander")), setting("meander.gain", 0.14),
         setting("member.1.hayes.origin_y", 0.3), setting("member.2.hayes.origin_y", -0.3)});
    const std::vector<RunResult> built_in = run_team(s, kSeed, 2);
    const std::vector<RunResult> outside = driven_from_outside(s, kSeed, 2);
    ASSERT_EQ(outside.size(), 3u) << name;
    for (std::size_t k = 0; k < 3; ++k) {
      SCOPED_TRACE(name + ", robot " + std::to_string(k));
      expect_same(outside[k], built_in[k]);
      EXPECT_EQ(bits(outside[k].declaration_error), bits(built_in[k].declaration_error));
      EXPECT_EQ(bits(outside[k].odor_fraction), bits(built_in[k].odor_fraction));
    }
  }
}

TEST(Team, StepsFromOutsideAreRefusedOutOfOrderOrWithAValueThatIsNotFinite) {
  Scenario s = scenario(Algorithm::kCasting, 10.0);
  s.team.count = 2;
  validate(s);
  World w({&s}, kSeed, 0);
  std::vector<Command> commands(2, Command::go(0.0));
  EXPECT_THROW(w.act_team(commands), std::logic_error);  // no observation yet
  w.observe_team();
  EXPECT_THROW(w.observe_team(), std::logic_error);  // twice
  EXPECT_THROW(w.step(), std::logic_error);          // a step in the middle
  const Vec2 before = w.agent(0).position();
  commands[1] = Command::go(NAN);
  try {
    w.act_team(commands);
    ADD_FAILURE() << "a NaN heading was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("agent 1"), std::string::npos) << e.what();
  }
  EXPECT_EQ(w.agent(0).position().x, before.x);  // nothing moved
  EXPECT_THROW(w.act_team(std::vector<Command>(3)), std::invalid_argument);
  commands[1] = Command::go(0.0);
  w.act_team(commands);  // the refused call left the observation waiting
  EXPECT_LT(w.agent(0).position().x, before.x);
  while (!w.done()) {
    w.observe_team();
    w.act_team(commands);
  }
  EXPECT_THROW(w.observe_team(), std::logic_error);  // every run has ended
}

}  // namespace
}  // namespace plumetrace
