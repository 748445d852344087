#include "plumetrace/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>

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
