// The switching wind (src/env/switching_wind.cpp; docs/model.md section 3.2): a uniform wind whose
// direction changes at switch times, as in Singh et al. (2023): its switches, the plume it
// carries and the runs in it.
#include "plumetrace/env/switching_wind.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <type_traits>
#include <vector>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/env/environment.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/trace.hpp"
#include "plumetrace/sim/world.hpp"
#include "support/shared_runs.hpp"

namespace plumetrace {
namespace {

constexpr double kDt = 0.032;  // the default sim.dt
constexpr double kDegree = std::numbers::pi / 180.0;

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

// the default scenario in the switching wind: one switch of 45 degrees, `first` s after release
Scenario switching_scenario(double first = 2.0) {
  Scenario s;
  s.wind.model = WindModel::kSwitching;
  s.wind.get<SwitchingParams>().first = first;
  validate(s);
  return s;
}

// a field of `params` around `mean`, released at `release` s
SwitchingWind make_switching(const SwitchingParams& params, std::uint64_t seed,
                             const Vec3& mean = {1.0, 0.0, 0.0}, double release = 20.0) {
  return SwitchingWind(params, {mean, {0.0, 16.0, -2.0, 2.0}, kDt, release}, Rng(seed));
}

// the direction of a horizontal wind (rad)
double direction(const Vec3& v) { return std::atan2(v.y, v.x); }

// an angle in (-pi, pi]
double wrapped(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

// expects an estimate within 4 standard errors of the expected value, and prints both
void expect_within_4_sigma(double mean, double error, double expected, const char* what) {
  std::printf("[ measured ] %s: %.6g +- %.2g (expected %.6g, %.2f sigma)\n", what, mean, error,
              expected, (mean - expected) / error);
  EXPECT_LE(std::abs(mean - expected), 4.0 * error) << what;
}

// --- the field alone ---------------------------------------------------------------------------

TEST(SwitchingWind, BeforeTheFirstSwitchItIsTheMeanWindBitForBit) {
  SwitchingParams p;
  p.first = 3.0;
  const Vec3 mean{0.9, -0.1, 0.01};
  SwitchingWind wind = make_switching(p, 5, mean, 1.0);
  EXPECT_TRUE(wind.uniform_in_space());
  ASSERT_EQ(wind.switches().size(), 1u);
  // the switch at release + first = 4 s: the steps after the boundary at 4 s (step 125's end)
  // blow the new wind
  for (int k = 1; k <= 125; ++k) {
    wind.step(kDt);
    const Vec3 a = wind.velocity({3.0 * k, -1.0, 0.5});
    ASSERT_EQ(bits(a.x), bits(mean.x)) << k;
    ASSERT_EQ(bits(a.y), bits(mean.y)) << k;
    ASSERT_EQ(bits(a.z), bits(mean.z)) << k;
    ASSERT_EQ(wind.started(), 0u);
  }
  wind.step(kDt);
  EXPECT_EQ(wind.started(), 1u);
  EXPECT_NE(bits(wind.velocity({}).y), bits(mean.y));
}

TEST(SwitchingWind, ASwitchTurnsTheDirectionByItsAngleAndKeepsTheSpeed) {
  const Vec3 mean{0.9, -0.3, 0.02};
  const double speed = std::hypot(mean.x, mean.y);
  for (const double angle : {15.0, 45.0, 90.0, 170.0}) {
    int turned_left = 0;
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
      SwitchingParams p;
      p.angle_deg = angle;
      p.first = 0.5;
      SwitchingWind wind = make_switching(p, seed, mean, 0.0);
      for (int k = 0; k < 20; ++k) wind.step(kDt);
      ASSERT_EQ(wind.started(), 1u);
      const Vec3 v = wind.velocity({});
      const double turn = wrapped(direction(v) - direction(mean));
      EXPECT_NEAR(std::abs(turn), angle * kDegree, 1e-12) << angle;
      EXPECT_NEAR(std::hypot(v.x, v.y), speed, 1e-15) << angle;
      EXPECT_EQ(bits(v.z), bits(mean.z));
      EXPECT_EQ(bits(wind.angle()), bits(wind.switches()[0].angle));
      turned_left += turn > 0.0;
    }
    // the sign is a fair coin: both ways in 40 runs
    EXPECT_GT(turned_left, 0) << angle;
    EXPECT_LT(turned_left, 40) << angle;
  }
}

TEST(SwitchingWind, NoSwitchOrNoAngleIsTheMeanWindBitForBit) {
  const Vec3 mean{0.9, -0.1, 0.01};
  for (const auto& [count, angle] : {std::pair{0, 45.0}, std::pair{5, 0.0}}) {
    SwitchingParams p;
    p.count = count;
    p.angle_deg = angle;
    p.first = -20.0;
    EXPECT_TRUE(SwitchingWind::steady(p));
    SwitchingWind wind = make_switching(p, 9, mean);
    EXPECT_TRUE(wind.switches().empty());
    for (int k = 0; k < 2000; ++k) {
      wind.step(kDt);
      ASSERT_EQ(bits(wind.velocity({}).x), bits(mean.x));
      ASSERT_EQ(bits(wind.velocity({}).y), bits(mean.y));
    }
  }
  SwitchingParams p;
  EXPECT_FALSE(SwitchingWind::steady(p));
}

TEST(SwitchingWind, ATransitionTurnsLinearlyFromTheOldDirectionToTheNew) {
  SwitchingParams p;
  p.count = 2;
  p.first = 1.01;
  p.interval = 1.0;  // the second switch starts before the first has turned
  p.jitter = 0.0;
  p.transition = 1.6;
  p.draw = SwitchDraw::kUniform;
  p.angle_deg = 90.0;
  SwitchingWind wind = make_switching(p, 3, {1.0, 0.0, 0.0}, 0.0);
  const auto& s = wind.switches();
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].from, 0.0);
  // the second starts from where the first had got to after 1 s of its 1.6 s
  EXPECT_NEAR(s[1].from, s[0].angle * (1.0 / 1.6), 1e-15);
  for (int k = 1; k <= 200; ++k) {
    wind.step(kDt);
    const double t = k * kDt;
    double expected = 0.0;
    if (t - kDt / 2 > 2.01) {
      expected = s[1].from + (s[1].angle - s[1].from) * std::clamp((t - 2.01) / 1.6, 0.0, 1.0);
    } else if (t - kDt / 2 > 1.01) {
      expected = s[0].angle * std::clamp((t - 1.01) / 1.6, 0.0, 1.0);
    }
    ASSERT_NEAR(wind.angle(), expected, 1e-12) << "t = " << t;
    ASSERT_NEAR(direction(wind.velocity({})), expected, 1e-12) << "t = " << t;
  }
  EXPECT_EQ(bits(wind.angle()), bits(s[1].angle));  // turned: exactly the new angle
}

// --- the switches' draws -----------------------------------------------------------------------

TEST(SwitchingWind, DrawsStayWithinTheAngleWithTheLawOfTheirRule) {
  const int n = 20000;
  const double a = 60.0 * kDegree;
  SwitchingParams p;
  p.count = n;
  p.angle_deg = 60.0;
  // sign: exactly +-angle, a fair coin
  p.draw = SwitchDraw::kSign;
  double left = 0.0;
  const SwitchingWind drawn1 = make_switching(p, 1);
  for (const WindSwitch& s : drawn1.switches()) {
    ASSERT_EQ(std::abs(s.angle), a);
    left += s.angle > 0.0;
  }
  expect_within_4_sigma(left / n, std::sqrt(0.25 / n), 0.5, "sign: fraction to the left");
  // uniform: within +-angle, mean 0, mean square a^2 / 3
  p.draw = SwitchDraw::kUniform;
  double sum = 0.0, sum2 = 0.0;
  const SwitchingWind drawn2 = make_switching(p, 2);
  for (const WindSwitch& s : drawn2.switches()) {
    ASSERT_LE(std::abs(s.angle), a);
    sum += s.angle;
    sum2 += s.angle * s.angle;
  }
  expect_within_4_sigma(sum / n, a / std::sqrt(3.0 * n), 0.0, "uniform: mean angle (rad)");
  expect_within_4_sigma(sum2 / n, a * a * std::sqrt(4.0 / 45.0 / n), a * a / 3.0,
                        "uniform: mean squared angle (rad^2)");
  // normal: std angle / 2, clipped to +-angle: 4.55% at the clip, mean 0
  p.draw = SwitchDraw::kNormal;
  double clipped = 0.0;
  sum = 0.0;
  const SwitchingWind drawn3 = make_switching(p, 3);
  for (const WindSwitch& s : drawn3.switches()) {
    ASSERT_LE(std::abs(s.angle), a);
    clipped += std::abs(s.angle) == a;
    sum += s.angle;
  }
  const double p_clip = std::erfc(2.0 / std::sqrt(2.0));  // P(|N| > 2 sigma) = 0.0455
  expect_within_4_sigma(clipped / n, std::sqrt(p_clip * (1.0 - p_clip) / n), p_clip,
                        "normal: fraction clipped");
  expect_within_4_sigma(sum / n, 0.5 * a / std::sqrt(n), 0.0, "normal: mean angle (rad)");
}

TEST(SwitchingWind, FixedSwitchesComeOnTheirGridWithinTheJitter) {
  SwitchingParams p;
  p.count = 500;
  p.first = -5.0;  // the first before release
  p.interval = 3.0;
  p.jitter = 0.0;
  const double release = 20.0;
  const SwitchingWind exact = make_switching(p, 4, {1.0, 0.0, 0.0}, release);
  for (int k = 0; k < p.count; ++k) {
    ASSERT_NEAR(exact.switches()[k].time, release + p.first + k * p.interval, 1e-12) << k;
  }
  p.jitter = 0.1;
  const SwitchingWind jittered = make_switching(p, 4, {1.0, 0.0, 0.0}, release);
  double largest = 0.0;
  EXPECT_EQ(jittered.switches()[0].time, release + p.first);  // the first exactly
  for (int k = 1; k < p.count; ++k) {
    const double off = jittered.switches()[k].time - (release + p.first + k * p.interval);
    ASSERT_LE(std::abs(off), 0.1 * p.interval + 1e-12) << k;
    largest = std::max(largest, std::abs(off));
  }
  EXPECT_GT(largest, 0.29);  // 499 uniform draws in +-0.3 s reach near its ends
}

TEST(SwitchingWind, TheSwitchesStartedByATimeFollowTheTimingRule) {
  SwitchingParams p;
  p.count = 40;
  p.first = 1.013;
  p.interval = 2.47;
  p.jitter = 0.0;
  SwitchingWind wind = make_switching(p, 8, {1.0, 0.0, 0.0}, 10.0);
  for (int k = 1; k <= 5000; ++k) {
    wind.step(kDt);
    const double t = k * kDt;
    // the count by time t: switches at 11.013, 13.483, 15.953, ... s, each started by the step
    // whose middle (t - dt / 2) it precedes (none lies within 1e-3 s of a middle)
    const double since = t - kDt / 2 - 11.013;
    const auto expected =
        since <= 0.0 ? 0 : std::min<long>(p.count, static_cast<long>(std::ceil(since / 2.47)));
    ASSERT_EQ(static_cast<long>(wind.started()), expected) << "t = " << t;
  }
  EXPECT_EQ(wind.started(), 40u);
}

TEST(SwitchingWind, RandomTimingHasExponentialGapsOfTheMeanInterval) {
  SwitchingParams p;
  p.count = 20001;
  p.timing = SwitchTiming::kRandom;
  p.interval = 3.0;
  const SwitchingWind wind = make_switching(p, 6);
  const auto& s = wind.switches();
  EXPECT_EQ(s[0].time, 20.0 + p.first);
  const double n = static_cast<double>(s.size() - 1);
  double sum = 0.0, longer = 0.0;
  for (std::size_t k = 1; k < s.size(); ++k) {
    const double gap = s[k].time - s[k - 1].time;
    ASSERT_GT(gap, 0.0);
    sum += gap;
    longer += gap > p.interval;
  }
  expect_within_4_sigma(sum / n, p.interval / std::sqrt(n), p.interval, "mean gap (s)");
  const double e = std::exp(-1.0);
  expect_within_4_sigma(longer / n, std::sqrt(e * (1.0 - e) / n), e, "P(gap > interval)");
}

TEST(SwitchingWind, TheSameSeedAndTrialGiveTheSameSwitchesAndOtherTrialsOthers) {
  Scenario s = switching_scenario();
  SwitchingParams& p = s.wind.get<SwitchingParams>();
  p.count = 50;
  p.draw = SwitchDraw::kNormal;
  p.angle_deg = 60.0;
  const auto switches = [&](std::uint64_t seed, std::uint64_t trial) {
    const Environment env = make_environment(s, seed, trial);
    std::vector<std::uint64_t> out;
    for (const WindSwitch& w : dynamic_cast<const SwitchingWind&>(*env.wind).switches()) {
      for (double v : {w.time, w.from, w.angle}) out.push_back(bits(v));
    }
    return out;
  };
  EXPECT_EQ(switches(7, 3), switches(7, 3));
  EXPECT_NE(switches(7, 3), switches(7, 4));
  EXPECT_NE(switches(7, 3), switches(8, 3));
  // the run's field is the one of its own stream, Stream::kWind, released after the warm-up
  const Environment env = make_environment(s, 7, 3);
  const SwitchingWind own(p, wind_context(s), Rng(derive_seed(7, 3, Stream::kWind)));
  EXPECT_EQ(bits(own.switches()[9].angle),
            bits(dynamic_cast<const SwitchingWind&>(*env.wind).switches()[9].angle));
  EXPECT_NEAR(own.switches()[0].time, s.sim.warmup + p.first, 1e-12);
}

// --- the plume and the robot in it -------------------------------------------------------------

TEST(SwitchingWind, AFilamentMovesWithTheOldWindThenTheNew) {
  Scenario s = switching_scenario(3.0);
  s.sim.warmup = 1.0;
  s.plume.sigma_p = 0.0;  // no random walk: filaments move by the wind alone
  s.wind.velocity = {0.8, 0.3, 0.0};
  validate(s);
  Environment env = make_environment(s, 11, 2);
  const auto& wind = dynamic_cast<const SwitchingWind&>(*env.wind);
  // 2 s in: well before the switch at 4 s; then 6 s on, 2 s after it
  const long before = 62, after = 188;  // steps
  for (long k = 0; k < before; ++k) step(env, s.sim.dt);
  const FilamentSpans f0 = env.odor->snapshot().filaments;
  const std::vector<double> x0(f0.x.begin(), f0.x.end()), y0(f0.y.begin(), f0.y.end());
  for (long k = before; k < after; ++k) step(env, s.sim.dt);
  const FilamentSpans f1 = env.odor->snapshot().filaments;
  ASSERT_GE(f1.size(), x0.size());  // the ring is not full: every filament kept its slot
  // the integral of the piecewise wind: the old wind up to the switch, at the step boundary
  // nearest release + first = 0.992 s + 3 s (release after 31 whole steps): 4.0 s, the new wind
  // after it
  const double switch_time = 125 * s.sim.dt;
  ASSERT_EQ(wind.started(), 1u);
  const double c = std::cos(wind.angle()), sn = std::sin(wind.angle());
  const Vec3 v0 = s.wind.velocity;
  const Vec3 v1{v0.x * c - v0.y * sn, v0.x * sn + v0.y * c, 0.0};
  const double t0 = before * s.sim.dt, t1 = after * s.sim.dt;
  const double dx = v0.x * (switch_time - t0) + v1.x * (t1 - switch_time);
  const double dy = v0.y * (switch_time - t0) + v1.y * (t1 - switch_time);
  for (std::size_t i = 0; i < x0.size(); ++i) {
    ASSERT_NEAR(f1.x[i] - x0[i], dx, 1e-9) << i;
    ASSERT_NEAR(f1.y[i] - y0[i], dy, 1e-9) << i;
  }
  // a bent plume: the turn moved the old filaments sideways of the old wind by the new wind's
  // crosswind part for 2 s, 2 s x 0.854 m/s x sin 45 deg = 1.21 m
  const double aside = (-v0.y * dx + v0.x * dy) / std::hypot(v0.x, v0.y);
  EXPECT_NEAR(std::abs(aside), (t1 - switch_time) * std::hypot(v0.x, v0.y) * std::sin(45 * kDegree),
              1e-9);
}

TEST(SwitchingWind, ATurningWindMovesAFilamentByItsIntegral) {
  Scenario s = switching_scenario(1.0);
  s.sim.warmup = 1.0;
  s.plume.sigma_p = 0.0;
  SwitchingParams& p = s.wind.get<SwitchingParams>();
  p.transition = 3.0;
  p.angle_deg = 80.0;
  validate(s);
  Environment env = make_environment(s, 5, 0);
  const auto& wind = dynamic_cast<const SwitchingWind&>(*env.wind);
  for (int k = 0; k < 31; ++k) step(env, s.sim.dt);  // 0.99 s
  const FilamentSpans f0 = env.odor->snapshot().filaments;
  const double x0 = f0.x[0], y0 = f0.y[0];
  for (int k = 31; k < 250; ++k) step(env, s.sim.dt);  // to 8 s: turning from 2 to 5 s
  const double a = wind.angle();
  ASSERT_EQ(std::abs(a), 80.0 * kDegree);
  // the old wind to 2 s, the turn over 3 s (the integral of (cos, sin) of a linear angle), the
  // new wind to 8 s
  const double t0 = 31 * s.sim.dt;
  const double dx = (2.0 - t0) + 3.0 / a * std::sin(a) + 3.0 * std::cos(a);
  const double dy = 3.0 / a * (1.0 - std::cos(a)) + 3.0 * std::sin(a);
  // the steps read the wind at their ends: the sum differs from the integral by less than one
  // step of the turn's change in velocity
  const FilamentSpans f1 = env.odor->snapshot().filaments;
  EXPECT_NEAR(f1.x[0] - x0, dx, s.sim.dt * std::abs(a));
  EXPECT_NEAR(f1.y[0] - y0, dy, s.sim.dt * std::abs(a));
}

// what a run records, every step and every filament snapshot, as bits
std::vector<std::uint64_t> run_bits(const Scenario& s, std::uint64_t trial) {
  Trace trace;
  TraceRecorder recorder(trace, 2.0, s.sim.dt);
  const RunResult r = run_once(s, 20080101, trial, [&](const World& w) { recorder(w); });
  std::vector<std::uint64_t> out;
  RunResult::fields(r, [&](const ResultField&, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    if constexpr (std::is_floating_point_v<T>) {
      out.push_back(bits(static_cast<double>(value)));
    } else {
      out.push_back(static_cast<std::uint64_t>(value));
    }
  });
  for (const TraceStep& t : trace.agents.front().steps) {
    for (double v : {t.time, t.pose.x, t.pose.y, t.pose.heading, t.odometer, t.concentration,
                     t.wind_body.x, t.wind_body.y, t.wind_body.z}) {
      out.push_back(bits(v));
    }
    out.push_back(std::hash<std::string>{}(t.state));
  }
  for (const FilamentSnapshot& f : trace.snapshots) {
    for (const auto* v : {&f.x, &f.y, &f.z, &f.w, &f.wind_x, &f.wind_y}) {
      for (double x : *v) out.push_back(bits(x));
    }
  }
  return out;
}

TEST(SwitchingWind, NoSwitchRunsAreTheConstantWindsBitForBit) {
  for (Algorithm algorithm : all_algorithms()) {
    Scenario laminar;
    laminar.controller.algorithm = algorithm;
    laminar.supervisor.timeout = 150.0;
    Scenario none = laminar;
    none.wind.model = WindModel::kSwitching;
    none.wind.get<SwitchingParams>().count = 0;
    none.wind.get<SwitchingParams>().first = -20.0;
    validate(none);
    const auto a = run_bits(laminar, 1);
    ASSERT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == run_bits(none, 1)) << algorithm_name(algorithm);
  }
  // with a switch the same run differs
  Scenario laminar, once = switching_scenario(5.0);
  laminar.supervisor.timeout = once.supervisor.timeout = 150.0;
  EXPECT_FALSE(run_bits(laminar, 1) == run_bits(once, 1));
}

// Stands still and takes one wind sample per step (body frame).
class WindLogger final : public Controller {
 public:
  explicit WindLogger(std::vector<Vec2>& log) : log_(log) {}
  Command step(const Observation&, WindProbe& wind) override {
    log_.push_back(wind.measure_wind_body());
    return Command::stop();
  }
  std::string_view state() const override { return "logging"; }
  int losses() const override { return 0; }

 private:
  std::vector<Vec2>& log_;
};

TEST(SwitchingWind, TheWindSensorMeasuresTheSwitchedWind) {
  Scenario s = switching_scenario(1.0);
  s.wind_sensor.sigma_a = 0.0;  // the sensor reads the wind itself
  s.robot.start.heading = 0.0;  // body frame = world frame
  std::vector<Vec2> sensed;
  World world(s, 20080101, 0, std::make_unique<WindLogger>(sensed));
  const auto& wind = dynamic_cast<const SwitchingWind&>(*world.environment().wind);
  for (int k = 1; k <= 60; ++k) {
    world.step();
    const Vec3 now = wind.velocity({});
    ASSERT_EQ(bits(sensed.back().x), bits(now.x)) << k;
    ASSERT_EQ(bits(sensed.back().y), bits(now.y)) << k;
  }
  // 1 s after release the sensor reads the wind turned by 45 degrees
  EXPECT_NEAR(std::abs(std::atan2(sensed.back().y, sensed.back().x)), 45.0 * kDegree, 1e-12);
  EXPECT_EQ(sensed.front().x, 1.0);
  EXPECT_EQ(sensed.front().y, 0.0);
}

TEST(SwitchingWind, AgentsSharingTheSwitchingPlumeEqualSeparateRuns) {
  std::vector<Scenario> scenarios;
  for (Algorithm algorithm : all_algorithms()) {
    Scenario s = switching_scenario(10.0);
    SwitchingParams& p = s.wind.get<SwitchingParams>();
    p.count = 30;
    p.interval = 3.0;
    p.draw = SwitchDraw::kNormal;
    p.angle_deg = 60.0;
    s.controller.algorithm = algorithm;
    s.supervisor.timeout = 120.0;
    scenarios.push_back(s);
  }
  scenarios[1].wind_sensor.sigma_a = 0.4;
  testing::expect_shared_plume_equals_runs_alone(scenarios, 20080101, 1);
}

// --- keys ----------------------------------------------------------------------------------------

TEST(SwitchingWind, BadKeysAreRefusedNamingThem) {
  Scenario s;
  const auto message = [&](const char* key, const char* text) {
    try {
      set_field_text(s, key, text);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  for (const auto& [key, text] : {std::pair{"switching.count", "-1"},
                                  {"switching.count", "100001"},
                                  {"switching.count", "1.5"},
                                  {"switching.first", "nan"},
                                  {"switching.first", "2e6"},
                                  {"switching.interval", "0"},
                                  {"switching.interval", "-3"},
                                  {"switching.jitter", "0.5"},
                                  {"switching.jitter", "-0.1"},
                                  {"switching.angle_deg", "181"},
                                  {"switching.angle_deg", "-1"},
                                  {"switching.draw", "gaussian"},
                                  {"switching.timing", "poisson"},
                                  {"switching.transition", "-1"}}) {
    EXPECT_NE(message(key, text).find(key), std::string::npos) << key << " = " << text;
  }
  // and the bounds themselves are accepted
  for (const auto& [key, text] : {std::pair{"switching.count", "0"},
                                  {"switching.count", "100000"},
                                  {"switching.first", "-1e6"},
                                  {"switching.jitter", "0.49"},
                                  {"switching.angle_deg", "180"},
                                  {"switching.draw", "uniform"},
                                  {"switching.timing", "random"},
                                  {"switching.transition", "0"}}) {
    EXPECT_EQ(message(key, text), "") << key << " = " << text;
  }
}

TEST(SwitchingWind, ItsRegistrationSaysWhatItIs) {
  WindParams wind;
  wind.model = WindModel::kSwitching;
  const WindRegion arena{0.0, 16.0, -2.0, 2.0};
  EXPECT_FALSE(wind_is_steady(wind));
  EXPECT_EQ(wind_identity(wind, arena), "");  // the same over any region
  EXPECT_NO_THROW(check_wind_field(wind, {wind.velocity, arena, kDt}));
  wind.get<SwitchingParams>().count = 0;
  EXPECT_TRUE(wind_is_steady(wind));
  const auto& entry = wind_field_registry()[static_cast<std::size_t>(WindModel::kSwitching)];
  EXPECT_EQ(entry.name, "switching");
  EXPECT_EQ(entry.table, "switching");
}

}  // namespace
}  // namespace plumetrace
