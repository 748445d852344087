#include "plumetrace/experiment/stats.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "plumetrace/core/rng.hpp"

namespace plumetrace {
namespace {

// Wilson: p = k/n, centre = (p + z^2/2n) / (1 + z^2/n),
// half = z sqrt(p(1-p)/n + z^2/4n^2) / (1 + z^2/n). Values below evaluated with that formula in
// Python (z = 1.959963984540054), and the boundary cases also in closed form.

TEST(Wilson, NoSuccessesReachesZeroAndZSquaredOverNPlusZSquared) {
  // k = 0: lo = 0, hi = z^2 / (n + z^2) = 3.84146 / 13.84146
  const Interval w = wilson_interval(0, 10);
  EXPECT_EQ(w.lo, 0.0);
  EXPECT_NEAR(w.hi, kZ95 * kZ95 / (10 + kZ95 * kZ95), 1e-15);
  EXPECT_NEAR(w.hi, 0.277532799863, 1e-12);
}

TEST(Wilson, HalfIsSymmetricAboutOneHalf) {
  // k = 5, n = 10: centre 0.5, half = z sqrt(0.025 + z^2/400) / (1 + z^2/10)
  const Interval w = wilson_interval(5, 10);
  EXPECT_NEAR(w.lo, 0.236593090513, 1e-12);
  EXPECT_NEAR(w.hi, 0.763406909487, 1e-12);
  EXPECT_NEAR(w.lo + w.hi, 1.0, 1e-15);
}

TEST(Wilson, AllSuccessesReachesOneAndNOverNPlusZSquared) {
  // k = n: lo = n / (n + z^2) = 10 / 13.84146, hi = 1
  const Interval w = wilson_interval(10, 10);
  EXPECT_NEAR(w.lo, 10.0 / (10 + kZ95 * kZ95), 1e-15);
  EXPECT_NEAR(w.lo, 0.722467200137, 1e-12);
  EXPECT_EQ(w.hi, 1.0);
}

TEST(Wilson, MatchesTheFormulaAtIntermediateCounts) {
  const Interval a = wilson_interval(45, 50);
  EXPECT_NEAR(a.lo, 0.786397685625, 1e-12);
  EXPECT_NEAR(a.hi, 0.956524235068, 1e-12);
  const Interval b = wilson_interval(1342, 1350);
  EXPECT_NEAR(b.lo, 0.988350099081, 1e-12);
  EXPECT_NEAR(b.hi, 0.996994227101, 1e-12);
}

TEST(Wilson, NoRunsGivesTheWholeUnitInterval) {
  const Interval w = wilson_interval(0, 0);
  EXPECT_EQ(w.lo, 0.0);
  EXPECT_EQ(w.hi, 1.0);
}

TEST(Newcombe, CombinesTheTwoWilsonIntervals) {
  // method 10: delta -+ sqrt((p1 - l1)^2 + (u2 - p2)^2), sqrt((u1 - p1)^2 + (p2 - l2)^2)
  const Interval w1 = wilson_interval(45, 50), w2 = wilson_interval(5, 10);
  const Interval d = newcombe_difference(45, 50, 5, 10);
  EXPECT_NEAR(d.lo, 0.4 - std::hypot(0.9 - w1.lo, w2.hi - 0.5), 1e-15);
  EXPECT_NEAR(d.hi, 0.4 + std::hypot(w1.hi - 0.9, 0.5 - w2.lo), 1e-15);
  // identical all-success groups: symmetric about zero, width set by n / (n + z^2)
  const Interval same = newcombe_difference(50, 50, 50, 50);
  EXPECT_NEAR(same.lo, -(1.0 - 50.0 / (50 + kZ95 * kZ95)), 1e-15);
  EXPECT_NEAR(same.hi, 1.0 - 50.0 / (50 + kZ95 * kZ95), 1e-15);
  EXPECT_TRUE(std::isnan(newcombe_difference(1, 0, 1, 2).lo));
}

// t quantiles: textbook values (nu = 1 and 2 also in closed form: tan(pi (p - 1/2)) and
// (2p - 1) / sqrt(2 p (1 - p))); the others evaluated with mpmath at 40 digits.

TEST(StudentT, MatchesTextbookQuantiles) {
  EXPECT_NEAR(student_t_quantile(0.975, 1), 12.7062047361747, 1e-9);
  EXPECT_NEAR(student_t_quantile(0.975, 2), 4.30265272974946, 1e-9);
  EXPECT_NEAR(student_t_quantile(0.975, 7), 2.36462425159279, 1e-9);
  EXPECT_NEAR(student_t_quantile(0.975, 9), 2.26215716279821, 1e-9);
  EXPECT_NEAR(student_t_quantile(0.975, 49), 2.00957523712924, 1e-9);
  EXPECT_NEAR(student_t_quantile(0.975, 1000), 1.96233908082641, 1e-9);
  EXPECT_NEAR(student_t_quantile(0.999, 3), 10.214531852407387, 1e-9);
  EXPECT_NEAR(student_t_quantile(0.975, 2.5), 3.5746548420036832, 1e-9);
}

TEST(StudentT, MatchesClosedFormsInTheFarTails) {
  const double pi = 3.14159265358979323846;
  for (double p : {0.6, 0.9, 0.999, 0.9999999}) {
    EXPECT_NEAR(student_t_quantile(p, 1), std::tan(pi * (p - 0.5)),
                1e-9 * std::max(1.0, std::tan(pi * (p - 0.5))));
    EXPECT_NEAR(student_t_quantile(p, 2), (2 * p - 1) / std::sqrt(2 * p * (1 - p)), 1e-9);
  }
}

TEST(StudentT, IsAntisymmetric) {
  for (double dof : {1.0, 3.0, 9.0, 49.0, 1e4}) {
    for (double p : {0.001, 0.05, 0.3, 0.49}) {
      EXPECT_NEAR(student_t_quantile(p, dof), -student_t_quantile(1 - p, dof), 1e-12);
    }
  }
  EXPECT_EQ(student_t_quantile(0.5, 7), 0.0);
}

TEST(StudentT, InvertsItsCdf) {
  for (double dof : {0.7, 1.0, 4.0, 30.0, 500.0}) {
    for (double p : {0.01, 0.2, 0.8, 0.975}) {
      EXPECT_NEAR(student_t_cdf(student_t_quantile(p, dof), dof), p, 1e-12);
    }
  }
  // mpmath: 1 - I_{5/(5 + 2.25)}(2.5, 0.5) / 2
  EXPECT_NEAR(student_t_cdf(1.5, 5), 0.90304815987876328, 1e-14);
}

TEST(StudentT, ConvergesToTheNormalQuantile) {
  double previous_gap = INFINITY;
  for (double dof : {10.0, 100.0, 1e3, 1e4, 1e5, 1e6, 1e9}) {
    const double gap = student_t_quantile(0.975, dof) - kZ95;
    EXPECT_GT(gap, 0.0);
    EXPECT_LT(gap, previous_gap);
    // first term of the expansion: (z^3 + z) / (4 dof)
    EXPECT_NEAR(gap * dof, (kZ95 * kZ95 * kZ95 + kZ95) / 4, 2.0 / std::sqrt(dof) + 10.0 / dof);
    previous_gap = gap;
  }
  EXPECT_NEAR(student_t_quantile(0.975, 123456), 1.9599832002451868, 1e-12);
  // either side of the switch from the incomplete beta (below 1e4 dof) to the expansion (mpmath)
  EXPECT_NEAR(student_t_quantile(0.999, 9999.0), 3.091047597579455, 1e-11);
  EXPECT_NEAR(student_t_quantile(0.999, 10001.0), 3.0910474344980813, 1e-11);
  EXPECT_NEAR(student_t_quantile(0.9, 9999.0), 1.2816362381983139, 1e-11);
  EXPECT_NEAR(student_t_quantile(0.9, 10001.0), 1.2816362212643347, 1e-11);
  EXPECT_NEAR(student_t_quantile(0.999, 99999.0), 3.0903138102422981, 1e-12);
  EXPECT_NEAR(student_t_quantile(0.999, 1e6), 3.0902404563165196, 1e-12);
}

TEST(StudentT, RejectsInvalidArguments) {
  EXPECT_TRUE(std::isnan(student_t_quantile(0.0, 3)));
  EXPECT_TRUE(std::isnan(student_t_quantile(1.0, 3)));
  EXPECT_TRUE(std::isnan(student_t_quantile(0.9, 0)));
  EXPECT_TRUE(std::isnan(student_t_quantile(NAN, 3)));
}

TEST(NormalQuantile, MatchesHighPrecisionValues) {
  EXPECT_NEAR(normal_quantile(0.975), kZ95, 1e-15);
  EXPECT_NEAR(normal_quantile(1e-10), -6.3613409024040562, 1e-13);
  EXPECT_NEAR(normal_quantile(0.3), -0.52440051270804078, 1e-15);
  EXPECT_NEAR(normal_quantile(0.999), 3.0902323061678135, 1e-14);
}

TEST(RegularizedBeta, MatchesPolynomialAndHighPrecisionValues) {
  // I_0.4(2, 3) = sum_{j=2..4} C(4, j) 0.4^j 0.6^(4-j) = 0.3456 + 0.1536 + 0.0256
  EXPECT_NEAR(regularized_beta(0.4, 2, 3), 0.5248, 1e-15);
  EXPECT_NEAR(regularized_beta(0.001, 0.5, 200), 0.47275589297476464, 1e-13);
  EXPECT_EQ(regularized_beta(0.0, 2, 3), 0.0);
  EXPECT_EQ(regularized_beta(1.0, 2, 3), 1.0);
}

TEST(MeanCi, MatchesAHandComputedInterval) {
  // {1, 2, 3}: mean 2, s = 1, half = t_{0.975,2} / sqrt(3) = 4.30265272974946 / 1.7320508
  const std::vector<double> v{3.0, 1.0, 2.0};
  const MeanCi m = mean_ci(v);
  EXPECT_EQ(m.n, 3);
  EXPECT_DOUBLE_EQ(m.mean, 2.0);
  EXPECT_DOUBLE_EQ(m.stddev, 1.0);
  EXPECT_NEAR(m.lo, 2.0 - 2.48413771175033, 1e-9);
  EXPECT_NEAR(m.hi, 2.0 + 2.48413771175033, 1e-9);
}

TEST(MeanCi, HonoursTheLevel) {
  // {2, 4, 4, 4, 5, 5, 7, 9}: mean 5, s^2 = 32/7; 90%: t_{0.95,7} = 1.894578605
  const std::vector<double> v{2, 4, 4, 4, 5, 5, 7, 9};
  const MeanCi m = mean_ci(v, 0.90);
  const double half = student_t_quantile(0.95, 7) * std::sqrt(32.0 / 7.0) / std::sqrt(8.0);
  EXPECT_NEAR(student_t_quantile(0.95, 7), 1.894578605, 1e-9);
  EXPECT_NEAR(m.lo, 5.0 - half, 1e-12);
  EXPECT_NEAR(m.hi, 5.0 + half, 1e-12);
}

TEST(MeanCi, SmallSamplesGiveNaN) {
  const MeanCi empty = mean_ci({});
  EXPECT_EQ(empty.n, 0);
  EXPECT_TRUE(std::isnan(empty.mean));
  EXPECT_TRUE(std::isnan(empty.lo));
  const std::vector<double> one{1.5, NAN};
  const MeanCi single = mean_ci(one);
  EXPECT_EQ(single.n, 1);
  EXPECT_EQ(single.mean, 1.5);
  EXPECT_TRUE(std::isnan(single.lo));
  EXPECT_TRUE(std::isnan(single.hi));
  EXPECT_TRUE(std::isnan(single.stddev));
}

TEST(PooledMeanCi, EqualsTheIntervalOfTheConcatenatedSample) {
  const std::vector<double> a{1.1, 1.4, 1.2, 1.9}, b{2.0, 2.5}, c{1.7};
  std::vector<double> all = a;
  all.insert(all.end(), b.begin(), b.end());
  all.insert(all.end(), c.begin(), c.end());
  const std::vector<MeanCi> parts{mean_ci(a), mean_ci(b), mean_ci(c), mean_ci({})};
  const MeanCi pooled = pooled_mean_ci(parts);
  const MeanCi direct = mean_ci(all);
  EXPECT_EQ(pooled.n, direct.n);
  EXPECT_NEAR(pooled.mean, direct.mean, 1e-14);
  EXPECT_NEAR(pooled.stddev, direct.stddev, 1e-14);
  EXPECT_NEAR(pooled.lo, direct.lo, 1e-13);
  EXPECT_NEAR(pooled.hi, direct.hi, 1e-13);
}

TEST(Welch, UsesTheSatterthwaiteDegreesOfFreedom) {
  // a: n 10, mean 3, s 1; b: n 5, mean 2, s 2. va = 0.1, vb = 0.8, se = sqrt(0.9),
  // dof = 0.81 / (0.01 / 9 + 0.64 / 4) = 5.0235...
  MeanCi a, b;
  a.n = 10, a.mean = 3, a.stddev = 1;
  b.n = 5, b.mean = 2, b.stddev = 2;
  const double dof = 0.81 / (0.01 / 9 + 0.64 / 4);
  const double half = student_t_quantile(0.975, dof) * std::sqrt(0.9);
  const Interval d = welch_difference(a, b);
  EXPECT_NEAR(d.lo, 1.0 - half, 1e-12);
  EXPECT_NEAR(d.hi, 1.0 + half, 1e-12);
  b.n = 1;
  EXPECT_TRUE(std::isnan(welch_difference(a, b).lo));
}

TEST(Quartiles, MatchNumpysDefaultLinearInterpolation) {
  // numpy.percentile([1, 2, 3, 4], [25, 50, 75]) = 1.75, 2.5, 3.25 (h = 3q)
  Quartiles q = quartiles({4, 1, 3, 2});
  EXPECT_DOUBLE_EQ(q.q1, 1.75);
  EXPECT_DOUBLE_EQ(q.median, 2.5);
  EXPECT_DOUBLE_EQ(q.q3, 3.25);
  // [1, 2, 4, 8, 16, 32]: h = 1.25 -> 2 + 0.25*2, h = 2.5 -> 4 + 0.5*4, h = 3.75 -> 8 + 0.75*8
  q = quartiles({32, 16, 8, 4, 2, 1});
  EXPECT_DOUBLE_EQ(q.q1, 2.5);
  EXPECT_DOUBLE_EQ(q.median, 6.0);
  EXPECT_DOUBLE_EQ(q.q3, 14.0);
  // odd count lands on order statistics: [1, 3, 5, 7, 9]
  q = quartiles({9, 7, 5, 3, 1, NAN});
  EXPECT_DOUBLE_EQ(q.q1, 3.0);
  EXPECT_DOUBLE_EQ(q.median, 5.0);
  EXPECT_DOUBLE_EQ(q.q3, 7.0);
  q = quartiles({2.5});
  EXPECT_DOUBLE_EQ(q.q1, 2.5);
  EXPECT_DOUBLE_EQ(q.q3, 2.5);
  EXPECT_TRUE(std::isnan(quartiles({}).median));
}

RunResult run(Outcome outcome, double overhead, double time, int losses) {
  RunResult r;
  r.outcome = outcome;
  r.overhead = overhead;
  r.time = time;
  r.losses = losses;
  return r;
}

TEST(Summarize, CountsEachOutcomeAndUsesSuccessfulRunsForTheOverhead) {
  const std::vector<RunResult> runs{
      run(Outcome::kSuccess, 1.2, 100, 1),  run(Outcome::kSuccess, 1.4, 120, 3),
      run(Outcome::kSuccess, 1.6, 140, 2),  run(Outcome::kWall, 9.0, 50, 4),
      run(Outcome::kTimeout, 7.0, 1200, 0), run(Outcome::kGaveUp, 5.0, 30, 1),
      run(Outcome::kWall, NAN, 10, 0),
  };
  const PointStats s = summarize(runs);
  EXPECT_EQ(s.runs, 7);
  EXPECT_EQ(s.successes, 3);
  EXPECT_EQ(s.walls, 2);
  EXPECT_EQ(s.timeouts, 1);
  EXPECT_EQ(s.gave_up, 1);
  EXPECT_DOUBLE_EQ(s.success_rate, 3.0 / 7.0);
  EXPECT_DOUBLE_EQ(s.success_ci.lo, wilson_interval(3, 7).lo);
  EXPECT_DOUBLE_EQ(s.success_ci.hi, wilson_interval(3, 7).hi);
  // overhead from the three successes only: mean 1.4, s = 0.2
  EXPECT_EQ(s.overhead.n, 3);
  EXPECT_NEAR(s.overhead.mean, 1.4, 1e-15);
  EXPECT_NEAR(s.overhead.stddev, 0.2, 1e-15);
  EXPECT_NEAR(s.overhead.hi - s.overhead.mean, 4.30265272974946 * 0.2 / std::sqrt(3.0), 1e-9);
  EXPECT_NEAR(s.overhead_quartiles.q1, 1.3, 1e-15);
  EXPECT_NEAR(s.overhead_quartiles.median, 1.4, 1e-15);
  EXPECT_NEAR(s.overhead_quartiles.q3, 1.5, 1e-15);
  EXPECT_NEAR(s.mean_time, (100 + 120 + 140 + 50 + 1200 + 30 + 10) / 7.0, 1e-12);
  EXPECT_NEAR(s.mean_time_success, 120.0, 1e-12);
  EXPECT_NEAR(s.mean_losses, 11.0 / 7.0, 1e-15);
}

TEST(Summarize, NoRunsGivesNaNRatesAndAnUninformativeInterval) {
  const PointStats s = summarize({});
  EXPECT_EQ(s.runs, 0);
  EXPECT_TRUE(std::isnan(s.success_rate));
  EXPECT_EQ(s.success_ci.lo, 0.0);
  EXPECT_EQ(s.success_ci.hi, 1.0);
  EXPECT_TRUE(std::isnan(s.overhead.mean));
  EXPECT_TRUE(std::isnan(s.mean_time));
  EXPECT_TRUE(std::isnan(s.mean_time_success));
}

TEST(Bootstrap, StaysWithinTheSampleSoAnOverheadIntervalNeverGoesBelowOne) {
  // a skewed overhead sample whose t interval reaches below the bound of 1
  const std::vector<double> overheads{1.0, 1.0, 1.01, 5.0};
  const MeanCi t = mean_ci(overheads);
  ASSERT_LT(t.lo, 1.0);
  const Interval b = bootstrap_mean_interval(overheads);
  EXPECT_GE(b.lo, 1.0);
  EXPECT_LE(b.hi, 5.0);
  EXPECT_LE(b.lo, t.mean);
  EXPECT_GE(b.hi, t.mean);
  // and for many overhead samples of every size
  Rng rng(7);
  for (int n = 2; n < 40; ++n) {
    std::vector<double> v;
    for (int i = 0; i < n; ++i) v.push_back(1.0 - 0.3 * std::log(rng.uniform_open0()));
    const Interval iv = bootstrap_mean_interval(v, 0.95, 500, static_cast<std::uint64_t>(n));
    EXPECT_GE(iv.lo, *std::min_element(v.begin(), v.end())) << n;
    EXPECT_LE(iv.hi, *std::max_element(v.begin(), v.end())) << n;
    EXPECT_GE(iv.lo, 1.0) << n;
  }
}

TEST(Bootstrap, MatchesTheTIntervalForALargeNormalSample) {
  // n = 2000 normal values: both intervals estimate mean +- 1.96 se. The percentile ends of
  // 2000 resamples scatter by sqrt(0.025 * 0.975 / 2000) / phi(1.96) = 0.06 se, so 4 sigma is
  // 0.24 se; t versus z and n versus n - 1 add less than 0.001 se.
  Rng rng(11);
  std::vector<double> v;
  for (int i = 0; i < 2000; ++i) v.push_back(rng.normal(1.2, 0.1));
  const MeanCi t = mean_ci(v);
  const Interval b = bootstrap_mean_interval(v);
  const double se = t.stddev / std::sqrt(2000.0);
  EXPECT_NEAR(b.lo, t.lo, 0.24 * se);
  EXPECT_NEAR(b.hi, t.hi, 0.24 * se);
}

TEST(Bootstrap, IsTheSameOnEveryCallAndFollowsItsSeed) {
  const std::vector<double> v{1.1, 1.3, 1.02, 1.8, 1.25, 1.07};
  const Interval a = bootstrap_mean_interval(v), b = bootstrap_mean_interval(v);
  EXPECT_EQ(a.lo, b.lo);
  EXPECT_EQ(a.hi, b.hi);
  const Interval other = bootstrap_mean_interval(v, 0.95, kBootstrapResamples, 99);
  EXPECT_TRUE(other.lo != a.lo || other.hi != a.hi);
}

TEST(Bootstrap, NeedsTwoValuesAndSkipsNaN) {
  EXPECT_TRUE(std::isnan(bootstrap_mean_interval(std::vector<double>{1.2}).lo));
  EXPECT_TRUE(std::isnan(bootstrap_mean_interval(std::vector<double>{1.2, NAN}).hi));
  const Interval with_nan = bootstrap_mean_interval(std::vector<double>{1.1, NAN, 1.3, 1.2});
  const Interval without = bootstrap_mean_interval(std::vector<double>{1.1, 1.3, 1.2});
  EXPECT_EQ(with_nan.lo, without.lo);
  EXPECT_EQ(with_nan.hi, without.hi);
}

TEST(Summarize, GivesTheBootstrapIntervalOfTheSuccessfulRunsOverheads) {
  const std::vector<RunResult> runs{run(Outcome::kSuccess, 1.2, 100, 1),
                                    run(Outcome::kWall, 9.0, 50, 4),
                                    run(Outcome::kSuccess, 1.6, 140, 2)};
  const PointStats s = summarize(runs);
  const Interval b = bootstrap_mean_interval(std::vector<double>{1.2, 1.6});
  EXPECT_EQ(s.overhead_bootstrap.lo, b.lo);
  EXPECT_EQ(s.overhead_bootstrap.hi, b.hi);
  EXPECT_GE(s.overhead_bootstrap.lo, 1.2);
  EXPECT_LE(s.overhead_bootstrap.hi, 1.6);
}

}  // namespace
}  // namespace plumetrace
