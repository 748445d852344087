#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "plumetrace/sim/world.hpp"

namespace plumetrace {

/// The standard normal quantile at 0.975: the z of a two-sided 95% interval.
inline constexpr double kZ95 = 1.959963984540054;

/// A closed interval; NaN ends when it cannot be computed.
struct Interval {
  double lo = NAN;  ///< lower end
  double hi = NAN;  ///< upper end
};

/// Regularized incomplete beta function I_x(a, b) for x in [0, 1], a > 0, b > 0 (NaN otherwise).
double regularized_beta(double x, double a, double b);

/// Quantile of the standard normal distribution, p in (0, 1) (NaN otherwise); accurate to 1e-15.
double normal_quantile(double p);

/// Cumulative distribution function of Student's t distribution with dof > 0 degrees of freedom.
double student_t_cdf(double t, double dof);

/// Quantile of Student's t distribution with dof > 0 degrees of freedom, p in (0, 1) (NaN
/// otherwise); accurate to 1e-9.
double student_t_quantile(double p, double dof);

/// Wilson score interval for a binomial proportion (successes of n), z = kZ95 by default; n = 0
/// gives {0, 1}.
Interval wilson_interval(std::int64_t successes, std::int64_t n, double z = kZ95);

/// Newcombe's hybrid score interval (his method 10, from two Wilson intervals) for the difference
/// p1 - p2 of two independent proportions; NaN ends when a group is empty.
Interval newcombe_difference(std::int64_t successes1, std::int64_t n1, std::int64_t successes2,
                             std::int64_t n2, double z = kZ95);

/// A sample's size, mean, its t-based confidence interval and the sample standard deviation.
struct MeanCi {
  std::int64_t n = 0;   ///< values used
  double mean = NAN;    ///< sample mean
  double lo = NAN;      ///< lower end of the interval for the mean
  double hi = NAN;      ///< upper end of the interval for the mean
  double stddev = NAN;  ///< sample standard deviation (n - 1 in the denominator)
};

/// Mean and its two-sided t-based confidence interval at `level` (default 0.95):
/// mean +- t_{(1+level)/2, n-1} s/sqrt(n); NaN values are skipped. n = 0: all NaN; n = 1: mean
/// only, interval and stddev NaN.
MeanCi mean_ci(std::span<const double> values, double level = 0.95);

/// The mean and interval of the union of several samples, each given by its MeanCi (n, mean,
/// stddev), exactly as mean_ci on the concatenated values would give them.
MeanCi pooled_mean_ci(std::span<const MeanCi> parts, double level = 0.95);

/// Welch's t interval at `level` for the difference a.mean - b.mean of two independent samples;
/// NaN ends unless both have n >= 2.
Interval welch_difference(const MeanCi& a, const MeanCi& b, double level = 0.95);

/// The lower quartile, median and upper quartile of a sample.
struct Quartiles {
  double q1 = NAN;      ///< 25th percentile
  double median = NAN;  ///< 50th percentile
  double q3 = NAN;      ///< 75th percentile
};

/// Quartiles by linear interpolation between order statistics (the default of R and NumPy,
/// "type 7"); NaN values are skipped; empty gives NaN.
Quartiles quartiles(std::vector<double> values);

/// The seed of bootstrap_mean_interval's resamples when none is given (fixed, so that the
/// interval of a sample is the same on every call and every machine).
inline constexpr std::uint64_t kBootstrapSeed = 20080101;

/// Resamples bootstrap_mean_interval draws when none is given.
inline constexpr int kBootstrapResamples = 2000;

/// Percentile bootstrap interval at `level` (default 0.95) of the mean of a sample: the
/// (1-level)/2 and (1+level)/2 quantiles (type 7) of the means of `resamples` resamples drawn
/// with replacement by our own Rng seeded with `seed`. NaN values are skipped; fewer than two
/// values give NaN ends. It lies within [min, max] of the sample, so it respects any bound the
/// values obey (an overhead is never below 1).
Interval bootstrap_mean_interval(std::span<const double> values, double level = 0.95,
                                 int resamples = kBootstrapResamples,
                                 std::uint64_t seed = kBootstrapSeed);

/// Statistics of one sweep point (docs/experiments.md, "Statistics").
struct PointStats {
  std::int64_t runs = 0;           ///< runs at this point
  std::int64_t successes = 0;      ///< runs that reached the source
  std::int64_t walls = 0;          ///< runs that touched a wall
  std::int64_t timeouts = 0;       ///< runs that timed out
  std::int64_t gave_up = 0;        ///< runs whose controller gave up
  std::int64_t wrong_declarations = 0;  ///< runs that declared the source where it is not
  double success_rate = NAN;       ///< successes / runs
  Interval success_ci;             ///< Wilson 95% interval of the success rate
  MeanCi overhead;                 ///< overhead d_t/d_u over successful runs only, t 95% interval
  Interval overhead_bootstrap;     ///< percentile bootstrap 95% interval of the mean overhead
  Quartiles overhead_quartiles;    ///< overhead quartiles over successful runs
  double mean_time = NAN;          ///< mean run time over all runs (s)
  double mean_time_success = NAN;  ///< mean run time over successful runs (s)
  double mean_losses = NAN;        ///< mean number of plume losses over all runs
};

/// Statistics of the runs of one sweep point; overheads that are NaN (d_u <= 0) are skipped.
PointStats summarize(std::span<const RunResult> runs);

}  // namespace plumetrace
