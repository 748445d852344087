// Tests of agent/controllers/random_walks.hpp: the correlated random walk and the Levy walk
// (docs/algorithms.md, "crw" and "levy").
#include "plumetrace/agent/controllers/random_walks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/world.hpp"
#include "support/fixed_wind.hpp"

namespace plumetrace {
namespace {

using testing::FixedWind;
using testing::InstantRobot;

// Drives `walk` through `legs` legs, each driven to its length in one step; calls `on_leg` with
// each leg as it begins.
template <class Walk, class OnLeg>
void drive_legs(Walk& walk, FixedWind& wind, int legs, OnLeg on_leg) {
  InstantRobot robot;
  for (int k = 0; k < legs; ++k) {
    wind.heading = robot.obs.odometry.heading;
    const Command c = walk.step(robot.obs, wind);
    ASSERT_EQ(walk.legs(), k + 1);
    on_leg(walk.leg());
    // why: past the length by a nanometre, so that rounding never leaves the leg unfinished
    robot.obey(c, walk.leg().length() + 1e-9);
  }
}

// mean and standard error of the mean of a sample
struct Estimate {
  double mean = 0.0;
  double se = 0.0;
};
Estimate estimate(const std::vector<double>& v) {
  double sum = 0.0, sum2 = 0.0;
  for (double x : v) {
    sum += x;
    sum2 += x * x;
  }
  const double n = static_cast<double>(v.size());
  const double mean = sum / n;
  return {mean, std::sqrt((sum2 / n - mean * mean) / (n - 1.0))};
}

TEST(RandomWalks, WrappedCauchyTurnsHaveMeanCosineRhoAndMeanSineZero) {
  for (const double rho : {0.0, 0.3, 0.8}) {
    Rng rng(11);
    std::vector<double> c, s;
    for (int k = 0; k < 40000; ++k) {
      const double phi = wrapped_cauchy(rho, rng);
      ASSERT_LE(std::fabs(phi), kPi);
      c.push_back(std::cos(phi));
      s.push_back(std::sin(phi));
    }
    const Estimate ec = estimate(c), es = estimate(s);
    EXPECT_NEAR(ec.mean, rho, 4.0 * ec.se) << rho;
    EXPECT_NEAR(es.mean, 0.0, 4.0 * es.se) << rho;
  }
  Rng rng(3);
  for (int k = 0; k < 100; ++k) EXPECT_EQ(wrapped_cauchy(1.0, rng), 0.0);
}

TEST(RandomWalks, KareivaShigesadaFormulaMatchesHandComputedCases) {
  // one step: E[l^2]; two steps: 2 E[l^2] + 2 E[l]^2 c
  EXPECT_DOUBLE_EQ(crw_mean_squared_displacement(1, 0.5, 0.25, 0.6), 0.25);
  EXPECT_DOUBLE_EQ(crw_mean_squared_displacement(2, 0.5, 0.25, 0.6), 0.5 + 2.0 * 0.25 * 0.6);
  // three steps: 3 E[l^2] + 2 E[l]^2 (2c + c^2)
  EXPECT_DOUBLE_EQ(crw_mean_squared_displacement(3, 1.0, 2.0, 0.5), 6.0 + 2.0 * (1.0 + 0.25));
  // uniform turns (c = 0): a simple random walk, n E[l^2]
  EXPECT_DOUBLE_EQ(crw_mean_squared_displacement(20, 1.0, 2.0, 0.0), 40.0);
}

// the squared net displacement of `legs` legs of a CRW, from its own headings and lengths
std::vector<double> crw_squared_displacements(const CrwParams& p, int walks, int legs) {
  std::vector<double> r2;
  for (int w = 0; w < walks; ++w) {
    Crw walk(p, Rng(1000 + w));
    FixedWind wind;
    double x = 0.0, y = 0.0;
    drive_legs(walk, wind, legs, [&](const Leg& leg) {
      x += leg.length() * std::cos(leg.heading());
      y += leg.length() * std::sin(leg.heading());
    });
    r2.push_back(x * x + y * y);
  }
  return r2;
}

TEST(RandomWalks, CrwMeanSquaredDisplacementIsKareivaShigesadas) {
  const int n = 20;
  CrwParams p;
  p.rho = 0.6;
  // fixed steps: E[l] = step, E[l^2] = step^2
  const Estimate fixed = estimate(crw_squared_displacements(p, 8000, n));
  const double fixed_expected = crw_mean_squared_displacement(n, p.step, p.step * p.step, p.rho);
  EXPECT_NEAR(fixed.mean, fixed_expected, 4.0 * fixed.se);
  // exponential steps: E[l^2] = 2 step^2
  p.step_law = StepLaw::kExponential;
  const Estimate expo = estimate(crw_squared_displacements(p, 8000, n));
  const double expo_expected = crw_mean_squared_displacement(n, p.step, 2 * p.step * p.step, p.rho);
  EXPECT_NEAR(expo.mean, expo_expected, 4.0 * expo.se);
  // and the two differ by more than their errors: the test tells the step laws apart
  EXPECT_GT(expo_expected - fixed_expected, 4.0 * (fixed.se + expo.se));
}

TEST(RandomWalks, CrwBiasWeighsUpwindAgainstPersistence) {
  // rho = 1: no turning noise, so the heading is the mean direction itself
  CrwParams p;
  p.rho = 1.0;
  struct Case {
    double w, expected;
  };
  // persistence along 0 (the release heading), upwind along pi/2
  for (const Case c : {Case{0.0, 0.0}, Case{0.5, kPi / 4.0}, Case{1.0, kPi / 2.0}}) {
    p.upwind_bias = c.w;
    Crw walk(p, Rng(1));
    FixedWind wind(kPi / 2.0);
    std::vector<double> headings;
    drive_legs(walk, wind, 1, [&](const Leg& leg) { headings.push_back(leg.heading()); });
    EXPECT_NEAR(headings[0], c.expected, 1e-12) << c.w;
    // the unbiased walk takes no wind sample: it uses nothing but its own stream
    EXPECT_EQ(wind.calls, c.w > 0.0 ? 1 : 0) << c.w;
  }
}

TEST(RandomWalks, ABlockedLegEndsAndTheWalkTurnsAwayFromWhatBlockedIt) {
  CrwParams p;
  p.rho = 1.0;  // no noise: the next heading is the reversed one
  Crw walk(p, Rng(1));
  FixedWind wind;
  InstantRobot robot;
  robot.obs.odometry.heading = 0.3;
  Command c = walk.step(robot.obs, wind);
  EXPECT_NEAR(c.heading, 0.3, 1e-15);
  robot.obey(c, 0.01);  // moved a centimetre
  c = walk.step(robot.obs, wind);
  EXPECT_EQ(walk.legs(), 1);
  robot.obey(c, 0.0);  // pressed a wall: neither moved nor turned
  c = walk.step(robot.obs, wind);
  EXPECT_EQ(walk.legs(), 2);
  EXPECT_NEAR(c.heading, wrap_angle(0.3 + kPi), 1e-12);
  // a turn on the spot is not a block
  robot.obs.odometry.heading = 1.0;
  c = walk.step(robot.obs, wind);
  EXPECT_EQ(walk.legs(), 2);
}

TEST(RandomWalks, LevyStepMatchesHandComputedInverse) {
  // mu = 2, l in [0.2, 1]: F(l) = (5 - 1/l) / 4, so F^-1(0.5) = 1/3 and P(l > 0.5) = 1/4
  EXPECT_NEAR(levy_step(2.0, 0.2, 1.0, 0.5), 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(levy_tail(2.0, 0.2, 1.0, 0.5), 0.25, 1e-15);
  EXPECT_EQ(levy_step(2.0, 0.2, 1.0, 0.0), 0.2);
  EXPECT_LE(levy_step(1.1, 0.2, 1.0, 1.0 - 0x1.0p-53), 1.0);
  EXPECT_EQ(levy_tail(3.0, 0.2, 1.0, 0.1), 1.0);
  EXPECT_EQ(levy_tail(3.0, 0.2, 1.0, 2.0), 0.0);
}

TEST(RandomWalks, LevyStepLengthsFollowTheTruncatedPowerLaw) {
  const int n = 20000;
  for (const double mu : {1.5, 2.0, 3.0}) {
    LevyParams p;
    p.mu = mu;
    Levy walk(p, Rng(7));
    FixedWind wind;
    std::vector<double> lengths;
    drive_legs(walk, wind, n, [&](const Leg& leg) { lengths.push_back(leg.length()); });
    for (const double x : {0.3, 1.0, 4.0}) {
      const double q = levy_tail(mu, p.l_min, p.l_max, x);
      int above = 0;
      for (double l : lengths) above += l > x;
      // binomial: mean n q, standard deviation sqrt(n q (1 - q)); a 4-sigma bound
      EXPECT_NEAR(above, n * q, 4.0 * std::sqrt(n * q * (1.0 - q))) << "mu " << mu << " x " << x;
    }
    for (double l : lengths) ASSERT_TRUE(l >= p.l_min && l <= p.l_max) << l;
    EXPECT_EQ(wind.calls, 0);
  }
}

TEST(RandomWalks, LevyTaxisHeadingsHaveMeanCosineBiasAboutUpwind) {
  LevyParams p;
  for (const double w : {0.0, 0.7}) {
    p.upwind_bias = w;
    Levy walk(p, Rng(5));
    FixedWind wind(2.0);
    std::vector<double> c, s;
    drive_legs(walk, wind, 20000, [&](const Leg& leg) {
      c.push_back(std::cos(leg.heading() - 2.0));
      s.push_back(std::sin(leg.heading() - 2.0));
    });
    const Estimate ec = estimate(c), es = estimate(s);
    EXPECT_NEAR(ec.mean, w, 4.0 * ec.se) << w;
    EXPECT_NEAR(es.mean, 0.0, 4.0 * es.se) << w;
    EXPECT_EQ(wind.calls, w > 0.0 ? 20000 : 0);
  }
}

TEST(RandomWalks, SnapshotIsTheRecentLegsEndingAtThePlannedEnd) {
  CrwParams p;
  p.rho = 1.0;  // straight on along heading 0
  Crw walk(p, Rng(1));
  EXPECT_TRUE(walk.snapshot().empty());
  FixedWind wind;
  drive_legs(walk, wind, 3, [](const Leg&) {});
  const Snapshot s = walk.snapshot();
  ASSERT_EQ(s.path.size(), 4u);  // three leg starts and the planned end of the third leg
  EXPECT_NEAR(s.path[2].x, 1.0, 1e-8);
  EXPECT_NEAR(s.path[3].x, 1.5, 1e-8);
  EXPECT_NEAR(s.path[3].y, 0.0, 1e-12);
  // the ring keeps the newest kWalkHistory starts
  Crw longer(p, Rng(1));
  drive_legs(longer, wind, 2 * kWalkHistory, [](const Leg&) {});
  const Snapshot l = longer.snapshot();
  ASSERT_EQ(l.path.size(), static_cast<std::size_t>(kWalkHistory) + 1);
  EXPECT_NEAR(l.path[0].x, kWalkHistory * 0.5, 1e-6);
}

// the behaviour test: runs per bias, their timeout (s), the bias, and a success rate the
// biased walk beats
constexpr int kBehaviourRuns = 12;
constexpr double kBehaviourTimeout = 300.0;
constexpr double kBehaviourBias = 1.0;
constexpr double kNullRate = 0.2;

// Successes of `n` runs (seed 1, trials 0 to n - 1) of the paper's laminar scenario with walls
// that block and the robot starting 4 m downwind of the source, for the walk `algorithm` with
// upwind bias `w`, timing out after `timeout` (s).
int laminar_successes(Algorithm algorithm, double w, int n, double timeout) {
  const std::string name(algorithm_name(algorithm));
  const Scenario s = build_scenario(
      {parse_override("controller.algorithm=" + name),
       parse_override(name + ".upwind_bias=" + std::to_string(w)),
       parse_override("supervisor.walls=block"), parse_override("robot.start_offset_x=4"),
       parse_override("supervisor.timeout=" + std::to_string(timeout))});
  int k = 0;
  for (int trial = 0; trial < n; ++trial) {
    const RunResult r = run_once(s, 1, static_cast<std::uint64_t>(trial));
    // walls block: a walk's run ends only at the source or the timeout
    EXPECT_TRUE(r.outcome == Outcome::kSuccess || r.outcome == Outcome::kTimeout)
        << outcome_name(r.outcome);
    k += r.outcome == Outcome::kSuccess;
  }
  return k;
}

// The upper tail of Binomial(n, p) at k: P(K >= k).
double binomial_upper_tail(int k, int n, double p) {
  double total = 0.0;
  for (int j = k; j <= n; ++j) {
    total += std::exp(std::lgamma(n + 1.0) - std::lgamma(j + 1.0) - std::lgamma(n - j + 1.0) +
                      j * std::log(p) + (n - j) * std::log1p(-p));
  }
  return total;
}

TEST(RandomWalks, LevyTaxisFindsTheSourceMoreOftenThanTheUnbiasedLevyWalk) {
  // 4 m downwind of the source, 300 s (32 m of path at 0.106 m/s), walls that block
  const int n = kBehaviourRuns;
  const int unbiased = laminar_successes(Algorithm::kLevy, 0.0, n, kBehaviourTimeout);
  const int biased = laminar_successes(Algorithm::kLevy, kBehaviourBias, n, kBehaviourTimeout);
  // had the biased walk succeeded no more often than kNullRate, `biased` or more successes in
  // n would have a chance below 1e-4; and the unbiased walk does worse
  EXPECT_LT(binomial_upper_tail(biased, n, kNullRate), 1e-4) << biased << " of " << n;
  EXPECT_GT(biased, unbiased);
}

}  // namespace
}  // namespace plumetrace
