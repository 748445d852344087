#include "plumetrace/core/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <vector>

namespace plumetrace {
namespace {

TEST(Rng, SameSeedSameSequence) {
  Rng a(42), b(42);
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(a.next_u64(), b.next_u64());
}

TEST(Rng, NormalMomentsWithinFourSigma) {
  Rng rng(7);
  const int n = 1'000'000;
  double s1 = 0, s2 = 0, s4 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = rng.normal();
    s1 += x;
    s2 += x * x;
    s4 += x * x * x * x;
  }
  const double mean = s1 / n, var = s2 / n, kurt = s4 / n;
  // standard errors: mean 1/sqrt(n), variance sqrt(2/n), fourth moment sqrt(96/n)
  EXPECT_NEAR(mean, 0.0, 4.0 / std::sqrt(n));
  EXPECT_NEAR(var, 1.0, 4.0 * std::sqrt(2.0 / n));
  EXPECT_NEAR(kurt, 3.0, 4.0 * std::sqrt(96.0 / n));
}

}  // namespace
}  // namespace plumetrace

namespace plumetrace {
namespace {

// standard normal CDF
double phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

TEST(Rng, NormalHistogramMatchesTheCdfIncludingWedgesAndTails) {
  // bins chosen to cover the ziggurat's layers, wedges and the tail beyond r = 3.44
  const double edges[] = {-INFINITY, -3.8, -3.44, -3.0, -2.0, -1.0, -0.5,    0.0,
                          0.5,       1.0,  2.0,   3.0,  3.44, 3.8,  INFINITY};
  const int bins = static_cast<int>(std::size(edges)) - 1;
  std::vector<long> counts(bins, 0);
  Rng rng(2024);
  const long n = 4'000'000;
  for (long i = 0; i < n; ++i) {
    const double x = rng.normal();
    int b = 0;
    while (x >= edges[b + 1]) ++b;
    ++counts[b];
  }
  for (int b = 0; b < bins; ++b) {
    const double p = phi(edges[b + 1]) - phi(edges[b]);
    const double expected = p * n;
    const double sigma = std::sqrt(n * p * (1.0 - p));
    EXPECT_NEAR(counts[b], expected, 4.0 * sigma + 1.0) << "bin " << b;
  }
}

TEST(Rng, DerivedSeedsDifferByStreamTrialAndSeed) {
  const auto a = derive_seed(1, 0, Stream::kPlume);
  EXPECT_NE(a, derive_seed(1, 0, Stream::kWindSensor));
  EXPECT_NE(a, derive_seed(1, 1, Stream::kPlume));
  EXPECT_NE(a, derive_seed(2, 0, Stream::kPlume));
  EXPECT_EQ(a, derive_seed(1, 0, Stream::kPlume));
}

}  // namespace
}  // namespace plumetrace
