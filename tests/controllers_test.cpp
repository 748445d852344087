#include "plumetrace/agent/controllers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "plumetrace/agent/robot.hpp"

namespace plumetrace {
namespace {

constexpr double kDt = 0.032;
// path length of one full-speed step (m): the resolution of every distance a controller sees
const double kStepTravel = RobotParams{}.wheel_speed * kDt;
// the true upwind direction of the scripted worlds: the wind blows along +x
constexpr double kUpwind = kPi;

bool same_angle(double a, double b, double tol = 1e-12) {
  return std::fabs(wrap_angle(a - b)) <= tol;
}

// unit vector pointing left of the heading a (rad)
Vec2 left_of(double a) { return {std::cos(a + kPi / 2.0), std::sin(a + kPi / 2.0)}; }

double dot(const Vec2& a, const Vec2& b) { return a.x * b.x + a.y * b.y; }

// Odor as a function of position (m) and time since release (s).
using OdorField = std::function<bool(double x, double y, double t)>;

// Angle error (rad) of the i-th wind sample (0-based).
using WindError = std::function<double(int i)>;

// A wind sensor for scripted worlds: the true wind (1, 0) m/s, turned by a scripted error per
// sample, seen from the robot's current heading. Counts its samples.
class ScriptedWind final : public WindProbe {
 public:
  ScriptedWind(const RobotState& robot, WindError error)
      : robot_(robot), error_(std::move(error)) {}

  Vec2 measure_wind_body() override {
    const double error = error_ ? error_(calls_) : 0.0;
    ++calls_;
    return rotate(rotate(Vec2{1.0, 0.0}, error), -robot_.pose.heading);
  }
  int calls() const { return calls_; }

 private:
  const RobotState& robot_;
  WindError error_;
  int calls_ = 0;
};

// One step of a scripted run.
struct StepRecord {
  Observation obs;     // what the controller saw
  Command command;     // what it decided
  std::string state;   // its state after deciding
  int losses = 0;      // its loss count after deciding
  int wind_calls = 0;  // wind samples it took during this step
  RobotState robot;    // true state after moving
};

// A world without plume, walls or supervisor: odor is scripted, the robot moves by step_robot.
class ScriptedWorld {
 public:
  explicit ScriptedWorld(OdorField odor, WindError wind_error = {},
                         Pose start = RobotParams{}.start)
      : odor_(std::move(odor)), robot_{start, 0.0}, wind_(robot_, std::move(wind_error)) {}

  // Runs up to `steps` more steps (the first decision at t = dt, as in World) or until give-up.
  std::vector<StepRecord> run(Controller& controller, int steps) {
    std::vector<StepRecord> log;
    for (int k = 0; k < steps; ++k) {
      const double t = static_cast<double>(++steps_) * kDt;
      Observation obs;
      obs.time = t;
      obs.odor = odor_(robot_.pose.x, robot_.pose.y, t);
      obs.odometry = robot_.pose;
      obs.odometer = robot_.odometer;
      const int calls_before = wind_.calls();
      const Command command = controller.step(obs, wind_);
      if (!command.give_up) step_robot(params_, command, kDt, robot_);
      log.push_back({obs, command, std::string(controller.state()), controller.losses(),
                     wind_.calls() - calls_before, robot_});
      if (command.give_up) break;
    }
    return log;
  }

  int wind_calls() const { return wind_.calls(); }

 private:
  OdorField odor_;
  RobotParams params_;
  RobotState robot_;
  ScriptedWind wind_;
  long steps_ = 0;
};

bool never(double, double, double) { return false; }
bool always(double, double, double) { return true; }

// A bias on the release sample only: the surge heading errs by `error` (rad, + is CCW).
WindError release_bias(double error) {
  return [error](int i) { return i == 0 ? error : 0.0; };
}

// Indices of the steps at which the controller's state changed.
std::vector<std::size_t> switches(const std::vector<StepRecord>& log, std::string_view initial) {
  std::vector<std::size_t> out;
  std::string_view before = initial;
  for (std::size_t i = 0; i < log.size(); ++i) {
    if (log[i].state != before) out.push_back(i);
    before = log[i].state;
  }
  return out;
}

std::unique_ptr<Controller> make(Algorithm algorithm, double d_lost, std::uint64_t seed) {
  ControllerParams params;
  params.algorithm = algorithm;
  params.get<CastingParams>().d_lost = d_lost;
  params.get<SurgeSpiralParams>().d_lost = d_lost;
  params.get<SurgeCastParams>().d_lost = d_lost;
  return make_controller(params, Rng(seed));
}

// the registry

TEST(ControllerRegistry, BuiltInsAreRegisteredInTheOrderOfAlgorithm) {
  EXPECT_EQ(algorithm_name(Algorithm::kCasting), "casting");
  EXPECT_EQ(algorithm_name(Algorithm::kSurgeSpiral), "surge-spiral");
  EXPECT_EQ(algorithm_name(Algorithm::kSurgeCast), "surge-cast");
  const ControllerRegistry& r = controller_registry();
  EXPECT_EQ(r.index_of<CastingParams>(), static_cast<std::size_t>(Algorithm::kCasting));
  EXPECT_EQ(r.index_of<SurgeSpiralParams>(), static_cast<std::size_t>(Algorithm::kSurgeSpiral));
  EXPECT_EQ(r.index_of<SurgeCastParams>(), static_cast<std::size_t>(Algorithm::kSurgeCast));
  EXPECT_EQ(r[static_cast<std::size_t>(Algorithm::kSurgeSpiral)].table, "surge_spiral");
}

// an algorithm no entry has is an error, never another algorithm in its place
TEST(ControllerRegistry, AnAlgorithmNoEntryHasIsRefusedNotReplaced) {
  const auto beyond = static_cast<Algorithm>(controller_registry().size());
  EXPECT_THROW(algorithm_name(beyond), std::invalid_argument);
  ControllerParams params;
  params.algorithm = beyond;
  EXPECT_THROW(make_controller(params, Rng(1)), std::invalid_argument);
}

#ifdef PLUMETRACE_WITH_ZIGZAG
// this program registers examples/zigzag: the tests of this file run with it registered
TEST(ControllerRegistry, ThisProgramRegistersZigzagAfterThePapersThree) {
  const ControllerRegistry& r = controller_registry();
  ASSERT_EQ(r.size(), library_algorithms().size() + 1);
  EXPECT_EQ(r.find("zigzag"), library_algorithms().size());
  EXPECT_EQ(all_algorithms().size(), r.size());
  ControllerParams params;
  params.algorithm = all_algorithms().back();
  EXPECT_EQ(algorithm_name(params.algorithm), "zigzag");
  EXPECT_NE(make_controller(params, Rng(1)), nullptr);
}
#endif

TEST(ControllerRegistry, MakesTheChosenAlgorithmWithItsOwnParams) {
  ControllerParams params;
  params.algorithm = Algorithm::kSurgeCast;
  params.get<SurgeCastParams>().d_cast = 0.5;
  EXPECT_NE(dynamic_cast<SurgeCast*>(make_controller(params, Rng(1)).get()), nullptr);
  params.algorithm = Algorithm::kSurgeSpiral;
  EXPECT_NE(dynamic_cast<SurgeSpiral*>(make_controller(params, Rng(1)).get()), nullptr);
  // the params written are this config's own: the registry's defaults are untouched
  EXPECT_EQ(ControllerParams{}.get<SurgeCastParams>().d_cast, SurgeCastParams{}.d_cast);
}

// guess_plume_side

TEST(GuessPlumeSide, SurgeErringCounterClockwiseGuessesPlumeRight) {
  Rng rng(1);
  EXPECT_EQ(guess_plume_side(1.0 + 0.1, 1.0, rng), -1);
  // across the +-pi seam: -pi + 0.05 is 0.1 counter-clockwise of pi - 0.05
  EXPECT_EQ(guess_plume_side(-kPi + 0.05, kPi - 0.05, rng), -1);
}

TEST(GuessPlumeSide, SurgeErringClockwiseGuessesPlumeLeft) {
  Rng rng(1);
  EXPECT_EQ(guess_plume_side(1.0 - 0.1, 1.0, rng), 1);
  EXPECT_EQ(guess_plume_side(kPi - 0.05, -kPi + 0.05, rng), 1);
}

TEST(GuessPlumeSide, NoTieLeavesTheRngUntouched) {
  Rng rng(7), copy(7);
  guess_plume_side(0.3, 0.2, rng);
  guess_plume_side(0.1, 0.2, rng);
  EXPECT_EQ(rng.next_u64(), copy.next_u64());
}

TEST(GuessPlumeSide, TieIsBrokenByTheRngAndBothSidesOccur) {
  std::set<int> seen;
  for (std::uint64_t seed = 0; seed < 64; ++seed) {
    Rng rng(seed), copy(seed);
    const int side = guess_plume_side(kPi, kPi, rng);
    EXPECT_EQ(side, copy.sign());
    seen.insert(side);
  }
  EXPECT_EQ(seen, (std::set<int>{-1, 1}));
}

// Casting

TEST(Casting, UpwindLegHeadsBetaOffTheMeasuredUpwindOnTheChosenSide) {
  const CastingParams params;
  std::set<int> sides;
  for (double error : {0.0, 0.2}) {
    for (std::uint64_t seed = 0; seed < 16; ++seed) {
      Casting casting(params, Rng(seed));
      ScriptedWorld world(always, [error](int) { return error; });
      const auto log = world.run(casting, 40);
      const int s = casting.side();
      sides.insert(s);
      // after the turn on the spot the robot drives at upwind + s*beta
      const double expected = kUpwind + error + s * params.beta;
      EXPECT_TRUE(same_angle(log.back().robot.pose.heading, expected))
          << "seed " << seed << " heading " << log.back().robot.pose.heading;
      const Pose& a = log[30].robot.pose;
      const Pose& b = log.back().robot.pose;
      EXPECT_TRUE(same_angle(std::atan2(b.y - a.y, b.x - a.x), expected, 1e-9));
      EXPECT_EQ(casting.state(), "upwind");
      EXPECT_EQ(world.wind_calls(), 1);
    }
  }
  EXPECT_EQ(sides, (std::set<int>{-1, 1}));
}

TEST(Casting, ZigzagAlternatesSidesAcrossAStripPlume) {
  CastingParams params;
  params.reacquire_side = ReacquireSide::kAlternate;
  const double half_width = 0.3;
  for (std::uint64_t seed : {1, 2, 3, 4}) {
    Casting casting(params, Rng(seed));
    ScriptedWorld world([&](double, double y, double) { return std::fabs(y) < half_width; });
    // step by step, reading the side in force at the end of every leg
    std::string before = "upwind";
    int leg_side = 0;
    double leg_heading = 0.0;
    std::vector<int> upwind_sides;
    std::vector<double> upwind_headings, crosswind_headings;
    for (int i = 0; i < 12000; ++i) {
      const StepRecord r = world.run(casting, 1).front();
      if (r.state != before) {
        if (before == "upwind") {
          upwind_sides.push_back(leg_side);
          upwind_headings.push_back(leg_heading);
        } else {
          crosswind_headings.push_back(leg_heading);
        }
      }
      leg_side = casting.side();
      leg_heading = r.robot.pose.heading;
      before = r.state;
    }
    ASSERT_GE(upwind_sides.size(), 4u) << "seed " << seed;
    ASSERT_GE(crosswind_headings.size(), 4u) << "seed " << seed;
    for (std::size_t k = 0; k < upwind_sides.size(); ++k) {
      EXPECT_TRUE(same_angle(upwind_headings[k], kUpwind + upwind_sides[k] * params.beta))
          << "leg " << k;
      if (k > 0) {
        EXPECT_EQ(upwind_sides[k], -upwind_sides[k - 1]) << "leg " << k;
      }
    }
    // the crosswind leg after UPWIND(s) heads upwind - s*90 deg, back across the strip
    for (std::size_t k = 0; k < crosswind_headings.size(); ++k) {
      EXPECT_TRUE(same_angle(crosswind_headings[k], kUpwind - upwind_sides[k] * kPi / 2.0))
          << "crosswind leg " << k;
    }
  }
}

TEST(Casting, SamplesWindOnlyAtReleaseLossAndReacquisition) {
  Casting casting(CastingParams{}, Rng(5));
  ScriptedWorld world([](double, double y, double) { return std::fabs(y) < 0.3; });
  const auto log = world.run(casting, 12000);
  const auto sw = switches(log, "upwind");
  ASSERT_GE(sw.size(), 8u);
  std::size_t next = 0;
  for (std::size_t i = 0; i < log.size(); ++i) {
    const bool is_switch = next < sw.size() && sw[next] == i;
    if (is_switch) ++next;
    EXPECT_EQ(log[i].wind_calls, (i == 0 ? 1 : 0) + (is_switch ? 1 : 0)) << "step " << i;
  }
  EXPECT_EQ(world.wind_calls(), 1 + static_cast<int>(sw.size()));
}

// Odor in the first 3.2 s and again from 12 s to 16 s: one loss, one reacquisition, a second
// loss. The headings held at the end of the four legs (upwind, crosswind, upwind, crosswind).
std::vector<double> reacquire_legs(ReacquireSide reacquire, std::uint64_t seed) {
  CastingParams params;
  params.reacquire_side = reacquire;
  Casting casting(params, Rng(seed));
  ScriptedWorld world([](double, double, double t) { return t < 3.2 || (t >= 12.0 && t < 16.0); });
  const auto log = world.run(casting, 900);
  const auto sw = switches(log, "upwind");
  EXPECT_EQ(sw.size(), 3u);
  if (sw.size() != 3u) return {};
  std::vector<double> headings;
  for (std::size_t end : {sw[0] - 1, sw[1] - 1, sw[2] - 1, log.size() - 1}) {
    headings.push_back(log[end].robot.pose.heading);
  }
  return headings;
}

TEST(Casting, ReacquireSideChoosesTheUpwindLegAfterReacquisition) {
  const double beta = CastingParams{}.beta;
  std::set<int> sides;
  for (std::uint64_t seed : {1, 2, 3, 4, 5, 6}) {
    for (ReacquireSide reacquire : {ReacquireSide::kAlternate, ReacquireSide::kSame}) {
      const std::vector<double> legs = reacquire_legs(reacquire, seed);
      ASSERT_EQ(legs.size(), 4u);
      // the side at release, from the first upwind leg (noise-free: upwind + s beta exactly)
      const int s = same_angle(legs[0], kUpwind + beta) ? 1 : -1;
      ASSERT_TRUE(same_angle(legs[0], kUpwind + s * beta));
      sides.insert(s);
      // the crosswind leg after UPWIND(s) goes toward -s either way
      EXPECT_TRUE(same_angle(legs[1], kUpwind - s * kPi / 2.0));
      // reacquired: alternate zigzags to UPWIND(-s), same keeps UPWIND(s)
      const int after = reacquire == ReacquireSide::kAlternate ? -s : s;
      EXPECT_TRUE(same_angle(legs[2], kUpwind + after * beta))
          << "seed " << seed << " heading " << legs[2];
      // the next crosswind leg goes toward minus the side held
      EXPECT_TRUE(same_angle(legs[3], kUpwind - after * kPi / 2.0)) << "seed " << seed;
    }
  }
  EXPECT_EQ(sides, (std::set<int>{-1, 1}));
}

TEST(Casting, OdorFreeWorldLosesAfterDLostThenGoesCrosswindForever) {
  const CastingParams params;
  for (std::uint64_t seed : {1, 2, 3}) {
    Casting casting(params, Rng(seed));
    ScriptedWorld world(never);
    const auto log = world.run(casting, 6000);  // 192 s
    ASSERT_EQ(log.size(), 6000u) << "casting never gives up";
    const auto sw = switches(log, "upwind");
    ASSERT_EQ(sw.size(), 1u);
    const StepRecord& loss = log[sw[0]];
    EXPECT_EQ(loss.state, "crosswind");
    EXPECT_GE(loss.obs.odometer, params.d_lost);
    EXPECT_LE(loss.obs.odometer, params.d_lost + kStepTravel);
    EXPECT_EQ(casting.losses(), 1);
    EXPECT_EQ(world.wind_calls(), 2);

    // the whole rest of the run: crosswind toward -s, straight, never giving up
    const int s = casting.side();
    const double crosswind = kUpwind - s * kPi / 2.0;
    for (std::size_t i = sw[0]; i < log.size(); ++i) {
      EXPECT_FALSE(log[i].command.give_up);
      EXPECT_EQ(log[i].command.motion, Motion::kGo);
      EXPECT_TRUE(same_angle(log[i].command.heading, crosswind));
    }
    const Pose& a = log[sw[0] + 100].robot.pose;
    const Pose& b = log.back().robot.pose;
    EXPECT_NEAR(b.x, a.x, 1e-9);
    const double travelled = log.back().robot.odometer - log[sw[0] + 100].robot.odometer;
    EXPECT_NEAR(dot({b.x - a.x, b.y - a.y}, left_of(kUpwind)), -s * travelled, 1e-9);
  }
}

// Loss detection and wind sampling, for each of the paper's algorithms: rules of theirs, not of
// every controller a program may register

class EveryAlgorithm : public ::testing::TestWithParam<Algorithm> {};

INSTANTIATE_TEST_SUITE_P(Controllers, EveryAlgorithm, ::testing::ValuesIn(builtin_algorithms()),
                         [](const auto& info) {
                           std::string name(algorithm_name(info.param));
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

TEST_P(EveryAlgorithm, DeclaresLossAfterExactlyDLostOfPathSinceLastDetection) {
  for (double d_lost : {0.614, 0.3}) {
    for (std::uint64_t seed : {1, 2}) {
      auto controller = make(GetParam(), d_lost, seed);
      // odor only in the first 0.7 m of the way upwind
      ScriptedWorld world([](double x, double, double) { return x > 14.8; });
      const std::string initial(controller->state());
      const auto log = world.run(*controller, 2000);
      const auto sw = switches(log, initial);
      ASSERT_FALSE(sw.empty());
      const std::size_t loss = sw.front();
      EXPECT_EQ(log[loss].losses, 1);
      EXPECT_EQ(log[loss - 1].losses, 0);
      double last_odor = 0.0;
      for (std::size_t i = 0; i < loss; ++i) {
        if (log[i].obs.odor) last_odor = log[i].obs.odometer;
      }
      ASSERT_GT(last_odor, 0.5) << "the detections end after a stretch of path";
      const double without_odor = log[loss].obs.odometer - last_odor;
      EXPECT_GE(without_odor, d_lost);
      EXPECT_LE(without_odor, d_lost + kStepTravel + 1e-12);
    }
  }
}

TEST_P(EveryAlgorithm, SamplesWindOnlyAtStateSwitches) {
  // a strip plume and a wind sensor erring +-0.35 rad on alternate samples, so that every
  // algorithm keeps leaving and re-finding the strip
  auto controller = make(GetParam(), 0.614, 11);
  ScriptedWorld world([](double, double y, double) { return std::fabs(y) < 0.3; },
                      [](int i) { return i % 2 == 0 ? 0.35 : -0.35; });
  const std::string initial(controller->state());
  const auto log = world.run(*controller, 8000);
  int measured_switches = 0;
  std::string before = initial;
  for (std::size_t i = 0; i < log.size(); ++i) {
    const std::string& now = log[i].state;
    // why: surge-cast turns from its first cast to its second without a new wind sample
    const bool measured = now != before && !(before == "cast1" && now == "cast2");
    measured_switches += measured;
    EXPECT_EQ(log[i].wind_calls, (i == 0 ? 1 : 0) + (measured ? 1 : 0))
        << "step " << i << ": " << before << " -> " << now;
    before = now;
  }
  EXPECT_GE(measured_switches, 6);
  EXPECT_EQ(world.wind_calls(), 1 + measured_switches);
}

// Surge-spiral

// A noise-free surge-spiral run that never meets odor: the robot loses the plume and spirals.
struct LostSpiral {
  std::vector<StepRecord> log;
  std::size_t losses = 0;  // switches out of "surge": 1 expected
  std::size_t start = 0;   // the first spiral step
  double curl = 0.0;       // the spiral's turning direction
};

LostSpiral lost_spiral(const SurgeSpiralParams& params, int steps) {
  SurgeSpiral spiral(params, Rng(3));
  ScriptedWorld world(never);
  LostSpiral run{world.run(spiral, steps)};
  const auto sw = switches(run.log, "surge");
  run.losses = sw.size();
  run.start = sw.empty() ? 0 : sw[0];
  run.curl = spiral.curl();
  return run;
}

// Radii (m) at which the path crosses the ray from `centre` in direction `dir` (rad).
std::vector<double> ray_crossings(const std::vector<StepRecord>& log, std::size_t from,
                                  const Pose& centre, double dir) {
  const Vec2 u{std::cos(dir), std::sin(dir)};
  std::vector<double> radii;
  double prev_along = 0.0, prev_perp = 0.0;
  for (std::size_t i = from; i < log.size(); ++i) {
    const Vec2 q{log[i].robot.pose.x - centre.x, log[i].robot.pose.y - centre.y};
    const double along = dot(q, u);
    const double perp = u.x * q.y - u.y * q.x;
    if (prev_perp * perp < 0.0) {
      const double f = prev_perp / (prev_perp - perp);
      const double r = prev_along + f * (along - prev_along);
      if (r > 0.0) radii.push_back(r);
    }
    prev_along = along;
    prev_perp = perp;
  }
  return radii;
}

TEST(SurgeSpiral, SpiralGapMatchesDGapAfterTheFirstTurn) {
  for (double d_gap : {0.222, 0.111, 0.333}) {
    SurgeSpiralParams params;
    params.d_gap = d_gap;
    params.start_radius = 0.0;  // the spiral's centre is where the robot lost the plume
    const LostSpiral run = lost_spiral(params, 9000);
    ASSERT_EQ(run.losses, 1u);
    const auto& log = run.log;
    // noise-free: the robot already faces upwind, so the spiral starts where it was lost
    const std::size_t start = run.start;
    EXPECT_EQ(log[start].command.motion, Motion::kCurve);
    const Pose centre = log[start].obs.odometry;
    const auto radii = ray_crossings(log, start, centre, kUpwind);
    ASSERT_GE(radii.size(), 5u) << "d_gap " << d_gap;
    // the k-th crossing of the upwind ray lies k*d_gap out; compare the gaps after the first turn
    for (std::size_t k = 1; k < radii.size(); ++k) {
      EXPECT_NEAR(radii[k] - radii[k - 1], d_gap, 0.1 * d_gap)
          << "d_gap " << d_gap << " turn " << k;
    }
    // the downwind ray is crossed half a gap out of phase, with the same gap
    const auto back = ray_crossings(log, start, centre, kUpwind + kPi);
    ASSERT_GE(back.size(), 5u);
    for (std::size_t k = 1; k < back.size(); ++k) {
      EXPECT_NEAR(back[k] - back[k - 1], d_gap, 0.1 * d_gap) << "d_gap " << d_gap << " turn " << k;
    }
  }
}

// Radius (m) of the circle through three points.
double circumradius(const Pose& a, const Pose& b, const Pose& c) {
  const double ab = std::hypot(b.x - a.x, b.y - a.y), bc = std::hypot(c.x - b.x, c.y - b.y);
  const double ca = std::hypot(a.x - c.x, a.y - c.y);
  const double cross = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  return ab * bc * ca / (2.0 * std::fabs(cross));
}

TEST(SurgeSpiral, StartRadiusStartsWithTheSpiralsCurvatureThere) {
  const SurgeSpiralParams defaults;
  const double b = defaults.d_gap / (2.0 * kPi);
  for (double r0 : {0.0, 0.02, 0.1, 0.5, 2.0}) {
    SurgeSpiralParams params;
    params.start_radius = r0;
    const LostSpiral run = lost_spiral(params, 400);
    ASSERT_EQ(run.losses, 1u);
    const auto& log = run.log;
    // noise-free: the robot already faces upwind, so the first spiral step curves
    const std::size_t i = run.start;
    ASSERT_EQ(log[i].command.motion, Motion::kCurve);
    const double theta0 = r0 / b;
    const double t2 = theta0 * theta0;
    const double radius = b * std::pow(t2 + 1.0, 1.5) / (t2 + 2.0);
    // the first step's arc: path length over heading change
    const RobotState& before = log[i - 1].robot;
    const RobotState& after = log[i].robot;
    const double turn = std::fabs(wrap_angle(after.pose.heading - before.pose.heading));
    EXPECT_NEAR((after.odometer - before.odometer) / turn, radius, 1e-9 * radius) << "r0 " << r0;
    // the circle through three poses of the first two steps: between the spiral's radius of
    // curvature at theta0 and the one a step's path length further on
    const double ds = after.odometer - before.odometer;
    const double theta1 = spiral_angle_at(b, spiral_arc_length(b, theta0) + ds, theta0);
    const double next_radius = 1.0 / spiral_curvature(b, theta1);
    const double fitted = circumradius(before.pose, after.pose, log[i + 1].robot.pose);
    EXPECT_GT(fitted, radius * (1.0 - 1e-9)) << "r0 " << r0;
    EXPECT_LT(fitted, next_radius * (1.0 + 1e-9)) << "r0 " << r0;
    EXPECT_LT(next_radius - radius, 0.05 * radius) << "r0 " << r0;  // a tight bracket
  }
}

TEST(SurgeSpiral, ZeroStartRadiusFollowsTheSpiralFromItsCentre) {
  // r0 = 0: the commands of the spiral from its centre, curvature 2 / b first
  SurgeSpiralParams params;
  params.start_radius = 0.0;
  const double b = params.d_gap / (2.0 * kPi);
  const LostSpiral run = lost_spiral(params, 1500);
  ASSERT_EQ(run.losses, 1u);
  const auto& log = run.log;
  const std::size_t start = run.start;
  EXPECT_EQ(std::fabs(log[start].command.curvature), 2.0 / b);
  double theta = 0.0;
  for (std::size_t i = start; i < log.size(); ++i) {
    theta = spiral_angle_at(b, log[i].obs.odometer - log[start].obs.odometer, theta);
    EXPECT_EQ(log[i].command.curvature, run.curl * spiral_curvature(b, theta)) << i;
  }
}

// Net signed turn (rad) of the robot heading over a stretch of the run.
double net_turn(const std::vector<StepRecord>& log, std::size_t from, std::size_t to) {
  double turn = 0.0;
  for (std::size_t i = from + 1; i < to; ++i) {
    turn += wrap_angle(log[i].robot.pose.heading - log[i - 1].robot.pose.heading);
  }
  return turn;
}

TEST(SurgeSpiral, CurlsTowardTheSideOppositeTheSurgeError) {
  // error > 0: the surge heading erred counter-clockwise, the robot drifted left, so the plume
  // is guessed right and the spiral turns clockwise; and the mirror case
  for (double error : {0.1, -0.1}) {
    const int guessed_side = error > 0.0 ? -1 : 1;
    SurgeSpiral spiral(SurgeSpiralParams{}, Rng(1));
    ScriptedWorld world(never, release_bias(error));
    const auto log = world.run(spiral, 3000);
    const auto sw = switches(log, "surge");
    ASSERT_EQ(sw.size(), 1u);
    EXPECT_EQ(spiral.curl(), guessed_side);
    // it first turns on the spot to the new upwind, then curves
    std::size_t first_curve = sw[0];
    while (log[first_curve].command.motion != Motion::kCurve) {
      EXPECT_EQ(log[first_curve].command.motion, Motion::kTurnTo);
      EXPECT_TRUE(same_angle(log[first_curve].command.heading, kUpwind));
      ++first_curve;
    }
    EXPECT_TRUE(same_angle(log[first_curve].obs.odometry.heading, kUpwind));
    for (std::size_t i = first_curve; i < log.size(); ++i) {
      EXPECT_EQ(log[i].command.curvature > 0.0 ? 1 : -1, guessed_side);
    }
    // the heading winds several turns in the curl's direction
    EXPECT_GT(guessed_side * net_turn(log, first_curve, log.size()), 4.0 * kPi);
    // the first half turn bulges toward the guessed side of the upwind direction
    const Pose start = log[first_curve].obs.odometry;
    double extreme = 0.0;
    for (std::size_t i = first_curve; i < log.size(); ++i) {
      if (std::fabs(net_turn(log, first_curve, i + 1)) > kPi) break;
      const Pose& p = log[i].robot.pose;
      const double side = dot({p.x - start.x, p.y - start.y}, left_of(kUpwind));
      if (std::fabs(side) > std::fabs(extreme)) extreme = side;
    }
    EXPECT_GT(guessed_side * extreme, 0.05);
  }
}

TEST(SurgeSpiral, NoiseFreeTieCurlsEitherWayAtRandom) {
  std::set<int> curls;
  for (std::uint64_t seed = 0; seed < 32; ++seed) {
    SurgeSpiral spiral(SurgeSpiralParams{}, Rng(seed));
    ScriptedWorld world(never);
    const auto log = world.run(spiral, 600);
    ASSERT_EQ(spiral.losses(), 1);
    const auto sw = switches(log, "surge");
    EXPECT_EQ(spiral.curl() > 0 ? 1 : -1, net_turn(log, sw[0], log.size()) > 0.0 ? 1 : -1);
    curls.insert(spiral.curl());
  }
  EXPECT_EQ(curls, (std::set<int>{-1, 1}));
}

TEST(SurgeSpiral, ReturnsToSurgeWithANewWindSampleOnOdor) {
  // odor again once the spiral has drifted 0.15 m to either side of the surge line
  SurgeSpiral spiral(SurgeSpiralParams{}, Rng(2));
  ScriptedWorld world([](double x, double y, double) { return x > 15.0 || std::fabs(y) > 0.15; },
                      [](int i) { return i == 2 ? 0.2 : 0.0; });
  const auto log = world.run(spiral, 3000);
  const auto sw = switches(log, "surge");
  ASSERT_GE(sw.size(), 2u);
  EXPECT_EQ(log[sw[1]].state, "surge");
  EXPECT_TRUE(log[sw[1]].obs.odor);
  EXPECT_EQ(log[sw[1]].wind_calls, 1);
  // the surge follows the third sample's upwind, which erred by 0.2 rad
  EXPECT_TRUE(same_angle(log[sw[1] + 60].robot.pose.heading, kUpwind + 0.2));
}

// Surge-cast

TEST(SurgeCast, CastsTowardGuessedSideThenTwiceAsFarBackThenGivesUp) {
  const SurgeCastParams params;
  for (double error : {0.1, -0.1}) {
    const int guessed_side = error > 0.0 ? -1 : 1;
    SurgeCast cast(params, Rng(1));
    ScriptedWorld world(never, release_bias(error));
    const auto log = world.run(cast, 20000);
    ASSERT_TRUE(log.back().command.give_up) << "an odor-free world ends in giving up";
    for (std::size_t i = 0; i + 1 < log.size(); ++i) EXPECT_FALSE(log[i].command.give_up);
    EXPECT_EQ(cast.cast_side(), guessed_side);
    EXPECT_EQ(world.wind_calls(), 2);
    EXPECT_EQ(cast.losses(), 1);

    const auto sw = switches(log, "surge");
    ASSERT_EQ(sw.size(), 2u);
    const StepRecord& loss = log[sw[0]];
    const StepRecord& turn = log[sw[1]];
    const StepRecord& end = log.back();
    EXPECT_EQ(loss.state, "cast1");
    EXPECT_EQ(turn.state, "cast2");

    // path lengths: d_cast, then 2*d_cast, each to within one step
    const double cast1 = turn.obs.odometer - loss.obs.odometer;
    const double cast2 = end.obs.odometer - turn.obs.odometer;
    EXPECT_GE(cast1, params.d_cast);
    EXPECT_LE(cast1, params.d_cast + kStepTravel + 1e-12);
    EXPECT_GE(cast2, 2.0 * params.d_cast);
    EXPECT_LE(cast2, 2.0 * params.d_cast + kStepTravel + 1e-12);

    // both casts are crosswind: cast 1 ends d_cast toward the guessed side of the loss point,
    // cast 2 ends d_cast on the other side
    const Pose& p0 = loss.obs.odometry;
    const Vec2 side = left_of(kUpwind);
    const Vec2 u{std::cos(kUpwind), std::sin(kUpwind)};
    const Vec2 d1{turn.obs.odometry.x - p0.x, turn.obs.odometry.y - p0.y};
    const Vec2 d2{end.obs.odometry.x - p0.x, end.obs.odometry.y - p0.y};
    EXPECT_NEAR(dot(d1, u), 0.0, 1e-9);
    EXPECT_NEAR(dot(d2, u), 0.0, 1e-9);
    EXPECT_NEAR(guessed_side * dot(d1, side), params.d_cast, kStepTravel);
    EXPECT_NEAR(guessed_side * dot(d2, side), -params.d_cast, kStepTravel);
  }
}

TEST(SurgeCast, ReturnsToSurgeWithANewWindSampleOnOdorDuringACast) {
  // The surge errs +0.1 rad (left, toward -y), so the first cast goes right (+y).
  // Odor beyond y = +0.1 is met by the first cast; odor below y = -0.2 only by the second.
  struct Case {
    const char* name;
    OdorField odor;
    const char* cast_state;
  };
  const std::vector<Case> cases{
      {"first cast", [](double x, double y, double) { return x > 15.3 || y > 0.1; }, "cast1"},
      {"second cast", [](double x, double y, double) { return x > 15.3 || y < -0.2; }, "cast2"},
  };
  for (const Case& c : cases) {
    SurgeCast cast(SurgeCastParams{}, Rng(1));
    ScriptedWorld world(c.odor, [](int i) { return i == 0 ? 0.1 : i == 2 ? -0.25 : 0.0; });
    const auto log = world.run(cast, 4000);
    const auto sw = switches(log, "surge");
    // the first return to surge
    std::size_t found = 0;
    for (std::size_t k : sw) {
      if (log[k].state == "surge") {
        found = k;
        break;
      }
    }
    ASSERT_GT(found, 0u) << c.name;
    EXPECT_EQ(log[found - 1].state, c.cast_state) << c.name;
    EXPECT_TRUE(log[found].obs.odor) << c.name;
    EXPECT_EQ(log[found].wind_calls, 1) << c.name;
    // the new surge follows the new sample (third sample: upwind erred by -0.25 rad)
    EXPECT_TRUE(same_angle(log[found + 60].robot.pose.heading, kUpwind - 0.25)) << c.name;
  }
}

}  // namespace
}  // namespace plumetrace
