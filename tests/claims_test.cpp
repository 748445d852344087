#include "lochmatter2008/claims.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace plumetrace {
namespace {

// Synthetic experiment sets: each point is given by its successes (of `runs`), the mean overhead
// of its successful runs and their standard deviation, from which its intervals follow as
// summarize would compute them.

MeanCi make_mean(std::int64_t n, double mean, double sd) {
  MeanCi m;
  m.n = n;
  if (n == 0) return m;
  m.mean = mean;
  if (n == 1) return m;
  m.stddev = sd;
  const double half = student_t_quantile(0.975, static_cast<double>(n - 1)) * sd /
                      std::sqrt(static_cast<double>(n));
  m.lo = mean - half;
  m.hi = mean + half;
  return m;
}

PointStats make_point(int runs, int successes, double mean, double sd) {
  PointStats p;
  p.runs = runs;
  p.successes = successes;
  p.walls = runs - successes;
  p.success_rate = static_cast<double>(successes) / runs;
  p.success_ci = wilson_interval(successes, runs);
  p.overhead = make_mean(successes, mean, sd);
  return p;
}

struct Profile {
  std::vector<int> successes;  // of 50 runs
  std::vector<double> means;   // mean overhead of the successful runs
  double sd = 0.1;             // their standard deviation
};

SetStats make_set(const std::string& name, const std::string& algorithm, const std::string& key,
                  const std::vector<double>& values, int fixed, const Profile& profile,
                  int runs = 50) {
  SetStats s;
  s.name = name;
  s.algorithm = algorithm;
  s.key = key;
  s.values = values;
  s.fixed_index = fixed;
  for (std::size_t i = 0; i < values.size(); ++i) {
    s.points.push_back(make_point(runs, profile.successes[i], profile.means[i], profile.sd));
  }
  return s;
}

std::vector<double> multiples(double step) {
  std::vector<double> v;
  for (int k = 1; k <= 9; ++k) v.push_back(step * k);
  return v;
}

const std::vector<double> kBeta{5, 10, 15, 20, 25, 30, 35, 40, 45};
const std::vector<double> kSigma{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8};
const std::vector<double> kDLost = multiples(0.1535);
const std::vector<double> kDGap = multiples(0.0555);
const std::vector<double> kDCast = multiples(0.0675);

// The three fixed-value configurations; with the shared master seed the fixed points of an
// algorithm's three sets are the same runs, hence identical statistics.
struct Fixed {
  PointStats casting = make_point(50, 44, 1.6, 0.15);
  PointStats spiral = make_point(50, 50, 1.35, 0.1);
  PointStats surge = make_point(50, 50, 1.42, 0.1);
};

void set_fixed(std::map<std::string, SetStats>& sets, const Fixed& f) {
  for (const char* n : {"A", "B", "C"}) sets[n].points[sets[n].fixed_index] = f.casting;
  for (const char* n : {"D", "E", "F"}) sets[n].points[sets[n].fixed_index] = f.spiral;
  for (const char* n : {"G", "H", "I"}) sets[n].points[sets[n].fixed_index] = f.surge;
}

// Data shaped like the paper's findings, with 50 runs per value: every claim holds.
std::map<std::string, SetStats> paper_like() {
  std::map<std::string, SetStats> s;
  s["A"] = make_set("A", "casting", "casting.beta_deg", kBeta, 4,
                    {{2, 5, 10, 20, 44, 45, 47, 48, 50},
                     {1.10, 1.12, 1.15, 1.20, 1.6, 1.7, 1.8, 1.9, 2.0},
                     0.15});
  s["B"] = make_set("B", "casting", "casting.d_lost", kDLost, 3,
                    {{40, 41, 42, 44, 45, 46, 47, 48, 49},
                     {1.50, 1.52, 1.54, 1.6, 1.58, 1.60, 1.62, 1.64, 1.66}});
  s["C"] = make_set("C", "casting", "wind_sensor.sigma_a", kSigma, 1,
                    {{44, 44, 45, 44, 44, 43, 38, 3, 1},
                     {1.58, 1.6, 1.6, 1.61, 1.62, 1.63, 1.8, 2.5, 3.0},
                     0.15});
  s["D"] = make_set("D", "surge-spiral", "surge_spiral.d_gap", kDGap, 3,
                    {std::vector<int>(9, 50), {1.2, 1.25, 1.3, 1.35, 1.45, 1.6, 1.75, 1.9, 2.0}});
  s["E"] =
      make_set("E", "surge-spiral", "surge_spiral.d_lost", kDLost, 3,
               {std::vector<int>(9, 50), {1.40, 1.39, 1.37, 1.35, 1.34, 1.33, 1.32, 1.31, 1.30}});
  s["F"] =
      make_set("F", "surge-spiral", "wind_sensor.sigma_a", kSigma, 1,
               {std::vector<int>(9, 50), {1.33, 1.35, 1.38, 1.42, 1.47, 1.52, 1.58, 1.65, 1.75}});
  std::vector<double> linear;
  for (double x : kDCast) linear.push_back(1.30 + 4.0 / 9.0 * x);
  s["G"] = make_set("G", "surge-cast", "surge_cast.d_cast", kDCast, 3,
                    {{20, 45, 48, 50, 50, 50, 50, 50, 50}, linear});
  s["H"] =
      make_set("H", "surge-cast", "surge_cast.d_lost", kDLost, 3,
               {std::vector<int>(9, 50), {1.44, 1.43, 1.43, 1.42, 1.42, 1.41, 1.41, 1.40, 1.40}});
  s["I"] = make_set("I", "surge-cast", "wind_sensor.sigma_a", kSigma, 1,
                    {{50, 50, 49, 48, 45, 40, 30, 20, 10},
                     {1.41, 1.42, 1.43, 1.44, 1.45, 1.46, 1.47, 1.48, 1.50}});
  set_fixed(s, Fixed{});
  return s;
}

// The same sets with fewer runs per value (the sensitivity study's 10): successes scale, the
// overhead means and spreads stay.
std::map<std::string, SetStats> with_runs(std::map<std::string, SetStats> sets, int runs) {
  for (auto& [name, s] : sets) {
    for (PointStats& p : s.points) {
      const int k = static_cast<int>(
          std::lround(static_cast<double>(p.successes) * runs / static_cast<double>(p.runs)));
      p = make_point(runs, k, p.overhead.mean,
                     std::isnan(p.overhead.stddev) ? 0.1 : p.overhead.stddev);
    }
  }
  return sets;
}

ClaimResult claim(const std::map<std::string, SetStats>& sets, int id,
                  ClaimRules rules = kDefaultRules) {
  const auto all = evaluate_claims(sets, rules);
  for (const auto& c : all) {
    if (c.id == id) return c;
  }
  ADD_FAILURE() << "no claim " << id;
  return {};
}

#define EXPECT_VERDICT(sets, id, expected)                      \
  do {                                                          \
    const ClaimResult c_ = claim(sets, id);                     \
    EXPECT_EQ(verdict_name(c_.verdict), verdict_name(expected)) \
        << "claim " << (id) << ": " << c_.evidence;             \
  } while (0)

// the verdict under rules 0.3.0 (docs/claims.md, "Two rule sets")
#define EXPECT_VERDICT_030(sets, id, expected)                     \
  do {                                                             \
    const ClaimResult c_ = claim(sets, id, ClaimRules::kRules030); \
    EXPECT_EQ(verdict_name(c_.verdict), verdict_name(expected))    \
        << "claim " << (id) << " (rules 0.3.0): " << c_.evidence;  \
  } while (0)

void set_profile(SetStats& s, const std::vector<int>& successes, const std::vector<double>& means,
                 double sd = 0.1) {
  for (std::size_t i = 0; i < s.values.size(); ++i) {
    if (static_cast<int>(i) == s.fixed_index) continue;  // shared with the other sets
    s.points[i] = make_point(static_cast<int>(s.points[i].runs), successes[i], means[i], sd);
  }
}

TEST(Claims, ListsElevenClaimsWithSpecWording) {
  const auto all = evaluate_claims(paper_like());
  ASSERT_EQ(all.size(), 11u);
  for (int i = 0; i < 11; ++i) EXPECT_EQ(all[i].id, i + 1);
  EXPECT_EQ(all[0].text, "Surge-spiral: virtually all runs of D, E, F succeed.");
  EXPECT_EQ(all[10].text, "d_lost matters much less than beta, d_gap or d_cast.");
  EXPECT_EQ(verdict_name(Verdict::kHolds), "holds");
  EXPECT_EQ(verdict_name(Verdict::kDoesNotHold), "does not hold");
  EXPECT_EQ(verdict_name(Verdict::kUnclear), "unclear");
}

TEST(Claims, AllHoldOnPaperLikeData) {
  for (const auto& c : evaluate_claims(paper_like())) {
    EXPECT_EQ(c.verdict, Verdict::kHolds) << "claim " << c.id << ": " << c.evidence;
  }
}

TEST(Claims, MissingSetsAreUnclearAndSaySo) {
  for (const auto& c : evaluate_claims({})) {
    EXPECT_EQ(c.verdict, Verdict::kUnclear) << c.id;
    EXPECT_NE(c.evidence.find("missing"), std::string::npos) << c.id << ": " << c.evidence;
  }
  auto sets = paper_like();
  sets.erase("E");
  EXPECT_VERDICT(sets, 1, Verdict::kUnclear);
  EXPECT_NE(claim(sets, 1).evidence.find("missing set E"), std::string::npos);
  EXPECT_VERDICT(sets, 6, Verdict::kUnclear);
  EXPECT_VERDICT(sets, 11, Verdict::kUnclear);
  EXPECT_VERDICT(sets, 5, Verdict::kHolds);   // D alone decides claim 5
  EXPECT_VERDICT(sets, 10, Verdict::kHolds);  // D and F still give surge-spiral's fixed point
}

TEST(Claims, MalformedSetsAreUnclear) {
  auto sets = paper_like();
  sets["D"].points.pop_back();
  EXPECT_VERDICT(sets, 5, Verdict::kUnclear);
  EXPECT_NE(claim(sets, 5).evidence.find("malformed"), std::string::npos);
  sets = paper_like();
  std::swap(sets["G"].values[0], sets["G"].values[1]);
  EXPECT_VERDICT(sets, 8, Verdict::kUnclear);
}

// Claim 1: pooled D+E+F success rate against 0.95.

TEST(Claims, Claim1CountsTheSharedFixedPointOnce) {
  const ClaimResult c = claim(paper_like(), 1);
  EXPECT_EQ(c.verdict, Verdict::kHolds);
  // 27 points of 50 runs, the two repeats of the fixed point dropped
  EXPECT_NE(c.evidence.find("1250/1250"), std::string::npos) << c.evidence;
}

TEST(Claims, Claim1FailsWhenManySpiralRunsFail) {
  auto sets = paper_like();
  Fixed f;
  f.spiral = make_point(50, 42, 1.35, 0.1);
  set_fixed(sets, f);
  for (const char* n : {"D", "E", "F"}) {
    set_profile(sets[n], std::vector<int>(9, 42), std::vector<double>(9, 1.4));
  }
  EXPECT_VERDICT(sets, 1, Verdict::kDoesNotHold);
}

TEST(Claims, Claim1UnclearNearTheThresholdWithFewRuns) {
  auto sets = with_runs(paper_like(), 10);
  // 9 failures in 250 distinct runs: 0.964 [0.933, 0.981] straddles 0.95
  set_profile(sets["F"], {9, 0, 9, 9, 9, 9, 9, 9, 9}, std::vector<double>(9, 1.4));
  EXPECT_VERDICT(sets, 1, Verdict::kUnclear);
}

// Claim 2: casting, split at beta = 20 deg.

TEST(Claims, Claim2FailsWhenSmallBetaSucceedsAsWell) {
  auto sets = paper_like();
  set_profile(sets["A"], {48, 48, 48, 48, 0, 45, 47, 48, 50},
              {1.10, 1.12, 1.15, 1.20, 0, 1.7, 1.8, 1.9, 2.0});
  EXPECT_VERDICT(sets, 2, Verdict::kDoesNotHold);
}

TEST(Claims, Claim2FailsWhenSmallBetaCostsMoreOverhead) {
  auto sets = paper_like();
  set_profile(sets["A"], {2, 5, 10, 20, 0, 45, 47, 48, 50},
              {2.5, 2.4, 2.3, 2.2, 0, 1.7, 1.8, 1.9, 2.0});
  EXPECT_VERDICT(sets, 2, Verdict::kDoesNotHold);
}

TEST(Claims, Claim2UnclearWithTenRunsNearTheAcceptableRate) {
  auto sets = with_runs(paper_like(), 10);
  // beta = 20 at 6/10 = 0.6 [0.31, 0.83]: cannot tell whether it is acceptable
  set_profile(sets["A"], {0, 1, 2, 6, 0, 9, 9, 10, 10},
              {1.10, 1.12, 1.15, 1.20, 0, 1.7, 1.8, 1.9, 2.0});
  EXPECT_VERDICT(sets, 2, Verdict::kUnclear);
}

TEST(Claims, Claim2ReadsAnAxisInRadiansWhenTheKeyHasNoDegreeSuffix) {
  auto sets = paper_like();
  sets["A"].key = "casting.beta";
  for (double& v : sets["A"].values) v *= 3.14159265358979323846 / 180.0;
  const ClaimResult c = claim(sets, 2);
  EXPECT_EQ(c.verdict, Verdict::kHolds) << c.evidence;
  EXPECT_NE(c.evidence.find("best A beta 0.349"), std::string::npos) << c.evidence;  // 20 deg
}

// Claim 3: success and overhead move together along d_lost, in either direction.

TEST(Claims, Claim3HoldsInTheMirroredDirectionToo) {
  auto sets = paper_like();
  set_profile(sets["B"], {49, 48, 47, 0, 45, 44, 42, 41, 40},
              {1.66, 1.64, 1.62, 0, 1.58, 1.54, 1.52, 1.50, 1.48});
  EXPECT_VERDICT(sets, 3, Verdict::kHolds);
}

// An effect of exactly none lies on the one threshold of rules 0.4 (m = 0): no number of runs
// can say which side it is on. Rules 0.3.0 said no, their m being above it.
TEST(Claims, Claim3UnclearWhenDLostChangesNothingNotHeldUnder030) {
  auto sets = paper_like();
  set_profile(sets["B"], std::vector<int>(9, 44), std::vector<double>(9, 1.6), 0.15);
  EXPECT_VERDICT(sets, 3, Verdict::kUnclear);
  EXPECT_VERDICT_030(sets, 3, Verdict::kDoesNotHold);
}

TEST(Claims, Claim3FailsWhenOneEndIsBetterInBoth) {
  auto sets = paper_like();
  // high d_lost: more successes and lower overhead, no trade-off
  set_profile(sets["B"], {40, 41, 42, 0, 45, 46, 47, 48, 49},
              {1.80, 1.76, 1.72, 0, 1.58, 1.52, 1.48, 1.44, 1.40});
  EXPECT_VERDICT(sets, 3, Verdict::kDoesNotHold);
}

TEST(Claims, Claim3UnclearWithTenRuns) {
  EXPECT_VERDICT(with_runs(paper_like(), 10), 3, Verdict::kUnclear);
}

// Claim 4: casting against sigma_a: flat from the low to the middle values, failing at the top.

TEST(Claims, Claim4FailsWhenTheTopStillWorks) {
  auto sets = paper_like();
  set_profile(sets["C"], {44, 0, 45, 44, 44, 43, 40, 38, 36},
              {1.58, 0, 1.6, 1.61, 1.62, 1.63, 1.7, 1.8, 1.9}, 0.15);
  EXPECT_VERDICT(sets, 4, Verdict::kDoesNotHold);
}

TEST(Claims, Claim4FailsWhenSuccessDeclinesGradually) {
  auto sets = paper_like();
  set_profile(sets["C"], {46, 0, 40, 34, 28, 22, 14, 3, 1},
              {1.58, 0, 1.6, 1.61, 1.62, 1.63, 1.8, 2.5, 3.0}, 0.15);
  EXPECT_VERDICT(sets, 4, Verdict::kDoesNotHold);
}

TEST(Claims, Claim4UnclearWithTenRuns) {
  EXPECT_VERDICT(with_runs(paper_like(), 10), 4, Verdict::kUnclear);
}

// Claims 5 and 6: surge-spiral overhead against d_gap and d_lost.

TEST(Claims, Claim5FailsWhenALargerGapIsCheaper) {
  auto sets = paper_like();
  set_profile(sets["D"], std::vector<int>(9, 50), {1.6, 1.55, 1.5, 0, 1.3, 1.25, 1.2, 1.15, 1.1});
  EXPECT_VERDICT(sets, 5, Verdict::kDoesNotHold);
}

TEST(Claims, Claim5UnclearWhenTheGapChangesNothingNotHeldUnder030) {
  auto sets = paper_like();
  set_profile(sets["D"], std::vector<int>(9, 50), std::vector<double>(9, 1.35));
  EXPECT_VERDICT(sets, 5, Verdict::kUnclear);
  EXPECT_VERDICT_030(sets, 5, Verdict::kDoesNotHold);
}

TEST(Claims, Claim5FailsWhenASmallerGapGivesAHigherOverhead) {
  auto sets = paper_like();
  set_profile(sets["D"], std::vector<int>(9, 50),
              {1.50, 1.48, 1.46, 0, 1.40, 1.38, 1.36, 1.34, 1.32});
  EXPECT_VERDICT(sets, 5, Verdict::kDoesNotHold);
  EXPECT_VERDICT_030(sets, 5, Verdict::kDoesNotHold);
}

TEST(Claims, Claim5UnclearWhenNoisy) {
  auto sets = with_runs(paper_like(), 10);
  set_profile(sets["D"], std::vector<int>(9, 10), {1.3, 1.32, 1.34, 0, 1.36, 1.37, 1.38, 1.4, 1.42},
              0.3);
  EXPECT_VERDICT(sets, 5, Verdict::kUnclear);
}

TEST(Claims, Claim6FailsWhenOverheadRisesWithDLost) {
  auto sets = paper_like();
  set_profile(sets["E"], std::vector<int>(9, 50),
              {1.30, 1.31, 1.33, 0, 1.37, 1.39, 1.41, 1.43, 1.45});
  EXPECT_VERDICT(sets, 6, Verdict::kDoesNotHold);
}

TEST(Claims, Claim6UnclearWithTenNoisyRuns) {
  auto sets = with_runs(paper_like(), 10);
  set_profile(sets["E"], std::vector<int>(9, 10),
              {1.40, 1.39, 1.37, 0, 1.34, 1.33, 1.32, 1.31, 1.30}, 0.3);
  EXPECT_VERDICT(sets, 6, Verdict::kUnclear);
}

// Claim 7: surge-spiral against sigma_a: overhead up, success not down.

TEST(Claims, Claim7FailsWhenNoiseCostsSuccesses) {
  auto sets = paper_like();
  set_profile(sets["F"], {50, 0, 50, 49, 45, 40, 35, 30, 25},
              {1.33, 0, 1.38, 1.42, 1.47, 1.52, 1.58, 1.65, 1.75});
  EXPECT_VERDICT(sets, 7, Verdict::kDoesNotHold);
}

TEST(Claims, Claim7UnclearWhenOverheadDoesNotRiseNotHeldUnder030) {
  auto sets = paper_like();
  set_profile(sets["F"], std::vector<int>(9, 50), std::vector<double>(9, 1.35));
  EXPECT_VERDICT(sets, 7, Verdict::kUnclear);
  EXPECT_VERDICT_030(sets, 7, Verdict::kDoesNotHold);
}

TEST(Claims, Claim7FailsWhenOverheadFallsWithNoise) {
  auto sets = paper_like();
  set_profile(sets["F"], std::vector<int>(9, 50),
              {1.60, 0, 1.54, 1.50, 1.45, 1.42, 1.39, 1.36, 1.33});
  EXPECT_VERDICT(sets, 7, Verdict::kDoesNotHold);
}

TEST(Claims, Claim7UnclearWithTenRuns) {
  // all 40 runs of each half succeed: the failure-rate change is within [-0.088, 0.088], but
  // one failure more at high noise leaves it open
  auto sets = with_runs(paper_like(), 10);
  set_profile(sets["F"], {10, 0, 10, 10, 10, 10, 9, 9, 9},
              {1.33, 0, 1.38, 1.42, 1.47, 1.52, 1.58, 1.65, 1.75});
  EXPECT_VERDICT(sets, 7, Verdict::kUnclear);
}

// Claim 8: surge-cast overhead linear in d_cast at a low rate; the smallest d_cast fails.

std::vector<double> g_means(double (*f)(double)) {
  std::vector<double> m;
  for (double x : kDCast) m.push_back(f(x));
  return m;
}

TEST(Claims, Claim8FailsWhenOverheadGrowsSteeply) {
  auto sets = paper_like();
  set_profile(sets["G"], {20, 45, 48, 0, 50, 50, 50, 50, 50},
              g_means([](double x) { return 1.2 + 3.0 * x; }));
  EXPECT_VERDICT(sets, 8, Verdict::kDoesNotHold);
}

TEST(Claims, Claim8FailsWhenOverheadIsStronglyCurved) {
  auto sets = paper_like();
  // flat, then a jump over the last values: detectable and far from a line
  set_profile(sets["G"], {20, 45, 48, 0, 50, 50, 50, 50, 50},
              {1.42, 1.42, 1.42, 0, 1.42, 1.42, 1.42, 1.50, 1.65});
  EXPECT_VERDICT(sets, 8, Verdict::kDoesNotHold);
}

TEST(Claims, Claim8UnclearWhenTheSmallestCastSucceedsAsOftenNotHeldUnder030) {
  auto sets = paper_like();
  std::vector<double> linear;
  for (double x : kDCast) linear.push_back(1.30 + 4.0 / 9.0 * x);
  set_profile(sets["G"], std::vector<int>(9, 50), linear);
  EXPECT_VERDICT(sets, 8, Verdict::kUnclear);
  EXPECT_VERDICT_030(sets, 8, Verdict::kDoesNotHold);
}

TEST(Claims, Claim8FailsWhenTheSmallestCastSucceedsMoreOften) {
  auto sets = paper_like();
  std::vector<double> linear;
  for (double x : kDCast) linear.push_back(1.30 + 4.0 / 9.0 * x);
  set_profile(sets["G"], {50, 40, 40, 0, 40, 40, 40, 40, 40}, linear);
  sets["G"].points[3] = make_point(50, 40, linear[3], 0.1);
  EXPECT_VERDICT(sets, 8, Verdict::kDoesNotHold);
}

TEST(Claims, Claim8UnclearWithTenRunsAndNoise) {
  auto sets = with_runs(paper_like(), 10);
  std::vector<double> linear;
  for (double x : kDCast) linear.push_back(1.30 + 4.0 / 9.0 * x);
  set_profile(sets["G"], {6, 9, 10, 0, 10, 10, 10, 10, 10}, linear, 0.4);
  EXPECT_VERDICT(sets, 8, Verdict::kUnclear);
}

TEST(Claims, Claim8UnclearWithTooFewOverheadsToFitALine) {
  auto sets = paper_like();
  // overheads of only two points known (the others' successful runs had none computable)
  for (int i = 2; i < 9; ++i) sets["G"].points[i].overhead = make_mean(1, 1.4, 0.1);
  const ClaimResult c = claim(sets, 8);
  EXPECT_EQ(c.verdict, Verdict::kUnclear) << c.evidence;
  EXPECT_NE(c.evidence.find("too few points"), std::string::npos) << c.evidence;
}

// Claim 9: surge-cast against sigma_a: mainly success falls.

TEST(Claims, Claim9FailsWhenSuccessDoesNotFall) {
  auto sets = paper_like();
  set_profile(sets["I"], std::vector<int>(9, 50), {1.41, 0, 1.5, 1.6, 1.7, 1.8, 1.9, 2.0, 2.1});
  EXPECT_VERDICT(sets, 9, Verdict::kDoesNotHold);
}

TEST(Claims, Claim9FailsWhenOverheadRisesMoreThanSuccessFalls) {
  auto sets = paper_like();
  set_profile(sets["I"], {50, 0, 50, 49, 48, 47, 46, 45, 44},
              {1.41, 0, 1.6, 1.8, 2.0, 2.2, 2.4, 2.6, 2.8});
  EXPECT_VERDICT(sets, 9, Verdict::kDoesNotHold);
}

TEST(Claims, Claim9UnclearWhenBothChangeAlike) {
  auto sets = paper_like();
  // success falls by about 25%, overhead rises by about 25%
  set_profile(sets["I"], {50, 0, 49, 47, 45, 42, 39, 36, 33},
              {1.41, 0, 1.45, 1.5, 1.55, 1.62, 1.7, 1.8, 1.9}, 0.2);
  EXPECT_VERDICT(sets, 9, Verdict::kUnclear);
}

// Claim 10: the three algorithms at their fixed values.

TEST(Claims, Claim10UnclearWhenCastingSucceedsAsOftenNotHeldUnder030) {
  auto sets = paper_like();
  Fixed f;
  f.casting = make_point(50, 50, 1.6, 0.15);
  set_fixed(sets, f);
  EXPECT_VERDICT(sets, 10, Verdict::kUnclear);
  EXPECT_VERDICT_030(sets, 10, Verdict::kDoesNotHold);
}

TEST(Claims, Claim10FailsWhenCastingSucceedsMoreOften) {
  auto sets = paper_like();
  Fixed f;
  f.casting = make_point(50, 50, 1.6, 0.15);
  f.spiral = make_point(50, 38, 1.35, 0.1);
  f.surge = make_point(50, 38, 1.42, 0.1);
  set_fixed(sets, f);
  EXPECT_VERDICT(sets, 10, Verdict::kDoesNotHold);
}

TEST(Claims, Claim10FailsWhenSurgeCastIsFarWorseThanSurgeSpiral) {
  auto sets = paper_like();
  Fixed f;
  f.casting = make_point(50, 30, 2.4, 0.15);
  f.surge = make_point(50, 50, 1.9, 0.1);
  set_fixed(sets, f);
  EXPECT_VERDICT(sets, 10, Verdict::kDoesNotHold);
}

TEST(Claims, Claim10UnclearWithTenRuns) {
  EXPECT_VERDICT(with_runs(paper_like(), 10), 10, Verdict::kUnclear);
}

TEST(Claims, Claim10PoolsDistinctFixedPoints) {
  auto sets = paper_like();
  // sets run with different seeds: the three fixed points differ and are pooled
  sets["B"].points[3] = make_point(50, 43, 1.61, 0.15);
  const ClaimResult c = claim(sets, 10);
  EXPECT_NE(c.evidence.find("casting (A+B+C, 2 distinct)"), std::string::npos) << c.evidence;
  EXPECT_NE(c.evidence.find("surge-spiral (D+E+F, 1 distinct)"), std::string::npos) << c.evidence;
}

// Claim 11: spread over d_lost against spread over the specific parameter.

TEST(Claims, Claim11FailsWhenDLostMattersAsMuch) {
  auto sets = paper_like();
  set_profile(sets["E"], std::vector<int>(9, 50), {2.0, 1.9, 1.75, 0, 1.45, 1.3, 1.25, 1.2, 1.2});
  EXPECT_VERDICT(sets, 11, Verdict::kDoesNotHold);
}

TEST(Claims, Claim11UnclearWithTenRuns) {
  EXPECT_VERDICT(with_runs(paper_like(), 10), 11, Verdict::kUnclear);
}

// Rules 0.4 score claim 11 on the overhead spread alone (the paper's "performance"); rules 0.3.0
// on the larger of the success and overhead spreads.
TEST(Claims, Claim11WeighsOverheadAloneUnderRules04) {
  auto sets = paper_like();
  // surge-spiral's d_lost decides success (50 down to 20 of 50) but not the overhead
  set_profile(sets["E"], {50, 50, 50, 0, 40, 35, 30, 25, 20}, std::vector<double>(9, 1.35));
  EXPECT_VERDICT(sets, 11, Verdict::kHolds);
  EXPECT_VERDICT_030(sets, 11, Verdict::kDoesNotHold);
  const ClaimResult c = claim(sets, 11);
  EXPECT_NE(c.evidence.find("not tested"), std::string::npos) << c.evidence;
  // an overhead that d_lost moves as much as d_gap does fails under both
  set_profile(sets["E"], std::vector<int>(9, 50), {2.0, 1.9, 1.75, 0, 1.45, 1.3, 1.25, 1.2, 1.2});
  EXPECT_VERDICT(sets, 11, Verdict::kDoesNotHold);
  EXPECT_VERDICT_030(sets, 11, Verdict::kDoesNotHold);
}

// The case (docs/claims.md, "Rules 0.4"): claim 5 with a true effect of +1% of
// overhead, below rules 0.3.0's m of 5%. Rules 0.3.0 say "does not hold" at 50 runs per value and
// "holds" at 200; rules 0.4 never say "does not hold", and "holds" once the interval is narrow.
TEST(ClaimRules, ASmallTrueEffectConvergesUnder04AndFlipsUnder030) {
  const auto small_rise = [](int runs) {
    auto sets = paper_like();
    SetStats& d = sets["D"];
    for (int i = 0; i < 9; ++i) {
      // 1.35 in the lower half, 1.3635 (+1%) in the upper half
      d.points[i] = make_point(runs, runs, i < 4 ? 1.35 : 1.3635, 0.1);
    }
    return sets;
  };
  const ClaimResult at50 = claim(small_rise(50), 5), at200 = claim(small_rise(200), 5);
  EXPECT_EQ(at50.verdict, Verdict::kUnclear) << at50.evidence;
  EXPECT_EQ(at200.verdict, Verdict::kHolds) << at200.evidence;
  EXPECT_EQ(claim(small_rise(50), 5, ClaimRules::kRules030).verdict, Verdict::kDoesNotHold);
  EXPECT_EQ(claim(small_rise(200), 5, ClaimRules::kRules030).verdict, Verdict::kHolds);
  // the part carries its figures: +1% in an interval around it, against m = 0
  ASSERT_EQ(at200.parts.size(), 1u);
  const ClaimPart& p = at200.parts[0];
  EXPECT_NEAR(p.estimate, 0.01, 1e-9);
  EXPECT_LT(p.lo, p.estimate);
  EXPECT_GT(p.hi, p.estimate);
  EXPECT_GT(p.lo, 0.0);
  EXPECT_EQ(p.threshold, 0.0);
  EXPECT_EQ(claim(small_rise(200), 5, ClaimRules::kRules030).parts[0].threshold, 0.05);
}

// Under rules 0.4 a directional verdict moves one way as runs grow: from unclear to the side of
// its true effect, never from yes to no or back, for effects on either side of m = 0.
TEST(ClaimRules, DirectionalVerdictsMoveOnlyTowardTheTruthAsRunsGrow) {
  for (double effect : {-0.03, -0.01, 0.01, 0.03}) {
    Verdict seen = Verdict::kUnclear;
    for (int runs : {10, 20, 50, 100, 200, 500, 1000, 5000}) {
      auto sets = paper_like();
      for (int i = 0; i < 9; ++i) {
        sets["D"].points[i] = make_point(runs, runs, i < 4 ? 1.35 : 1.35 * (1 + effect), 0.1);
      }
      const Verdict v = claim(sets, 5).verdict;
      if (seen != Verdict::kUnclear) {
        EXPECT_EQ(v, seen) << effect << " at " << runs;
      }
      if (v != Verdict::kUnclear) seen = v;
    }
    EXPECT_EQ(seen, effect > 0 ? Verdict::kHolds : Verdict::kDoesNotHold) << effect;
  }
}

// Every part's figures: a tested quantity inside its interval, and a threshold wherever there is
// an interval.
TEST(ClaimRules, EveryPartWithAnIntervalCarriesItsEstimateAndThreshold) {
  for (ClaimRules rules : {ClaimRules::kRules04, ClaimRules::kRules030}) {
    for (const ClaimResult& c : evaluate_claims(paper_like(), rules)) {
      for (const ClaimPart& p : c.parts) {
        if (std::isnan(p.lo)) continue;
        EXPECT_LE(p.lo, p.estimate + 1e-12) << c.id << ": " << p.text;
        EXPECT_GE(p.hi, p.estimate - 1e-12) << c.id << ": " << p.text;
        EXPECT_FALSE(std::isnan(p.threshold)) << c.id << ": " << p.text;
      }
    }
  }
  EXPECT_EQ(rules_name(ClaimRules::kRules04), "0.4");
  EXPECT_EQ(rules_name(ClaimRules::kRules030), "0.3.0");
  EXPECT_EQ(kDefaultRules, ClaimRules::kRules04);
}

// margins (docs/claims.md, "Margins")

// Every part's margin agrees in sign with its support; a claim's margin is its weakest part's.
void expect_consistent_margins(const std::map<std::string, SetStats>& sets) {
  for (const ClaimResult& c : evaluate_claims(sets)) {
    ASSERT_FALSE(c.parts.empty()) << "claim " << c.id;
    double weakest = INFINITY;
    for (const ClaimPart& p : c.parts) {
      if (p.support == Verdict::kHolds) {
        EXPECT_GE(p.margin, 0.0) << "claim " << c.id << ": " << p.text;
      } else if (!std::isnan(p.margin)) {
        EXPECT_LT(p.margin, 0.0) << "claim " << c.id << ": " << p.text;
      }
      EXPECT_NE(c.evidence.find(p.text), std::string::npos) << "claim " << c.id;
      weakest = std::isnan(p.margin) || std::isnan(weakest) ? NAN : std::fmin(weakest, p.margin);
    }
    if (std::isnan(weakest)) {
      EXPECT_TRUE(std::isnan(c.margin)) << "claim " << c.id;
    } else {
      EXPECT_DOUBLE_EQ(c.margin, weakest) << "claim " << c.id;
    }
    if (c.verdict == Verdict::kHolds) {
      EXPECT_GE(c.margin, 0.0) << "claim " << c.id;
    }
  }
}

TEST(ClaimMargins, AgreeInSignWithEveryPartsVerdict) {
  expect_consistent_margins(paper_like());
  expect_consistent_margins(with_runs(paper_like(), 10));
  auto flat = paper_like();
  set_profile(flat["D"], std::vector<int>(9, 50), std::vector<double>(9, 1.35));
  set_profile(flat["G"], std::vector<int>(9, 30), std::vector<double>(9, 1.4));
  set_profile(flat["A"], std::vector<int>(9, 45), std::vector<double>(9, 1.5));
  expect_consistent_margins(flat);
}

TEST(ClaimMargins, AreNotANumberWhenASetIsMissing) {
  auto sets = paper_like();
  sets.erase("D");
  const ClaimResult c = claim(sets, 5);
  EXPECT_TRUE(c.parts.empty());
  EXPECT_TRUE(std::isnan(c.margin));
}

// The margin rises monotonically with the size of the claimed effect, and crosses zero where the
// verdict turns to "holds".
TEST(ClaimMargins, GrowWithTheEffect) {
  // claim 5: the overhead's rise along d_gap, scaled from none to twice the paper-like one
  double previous = -INFINITY;
  bool held_before = false;
  for (double k : {0.0, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0}) {
    auto sets = paper_like();
    std::vector<double> means;
    for (int i = 0; i < 9; ++i) means.push_back(1.35 + k * 0.1 * (i - 3));
    set_profile(sets["D"], std::vector<int>(9, 50), means);
    const ClaimResult c = claim(sets, 5);
    EXPECT_GT(c.margin, previous) << "k = " << k;
    EXPECT_EQ(c.verdict == Verdict::kHolds, c.margin > 0.0) << "k = " << k;
    if (held_before) {
      EXPECT_EQ(c.verdict, Verdict::kHolds) << "k = " << k;
    }
    held_before = c.verdict == Verdict::kHolds;
    previous = c.margin;
  }
  EXPECT_TRUE(held_before);
  // claim 1: the pooled surge-spiral success rate from 80% to 100%
  previous = -INFINITY;
  for (int k : {40, 44, 46, 48, 49, 50}) {
    auto sets = paper_like();
    for (const char* n : {"D", "E", "F"}) {
      for (PointStats& p : sets[n].points) p = make_point(50, k, 1.35, 0.1);
    }
    const ClaimResult c = claim(sets, 1);
    EXPECT_GT(c.margin, previous) << k << "/50";
    previous = c.margin;
  }
  EXPECT_GT(previous, 0.0);
}

}  // namespace
}  // namespace plumetrace
