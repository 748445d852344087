// src/core/math.cpp: the model's elementary functions, measured against the C library's long
// double versions (64 significant bits on x86-64, 113 on 64-bit ARM) and checked on C's special
// values. That they give the same bits on every machine is checked by tests/bits (aarch64_golden).
#include "plumetrace/core/math.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>

#include "plumetrace/core/rng.hpp"

namespace plumetrace {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

// |got - want| in units in the last place of want rounded to double
double ulps(double got, long double want) {
  const double w = static_cast<double>(want);
  if (got == w) return 0.0;
  const double ulp = std::nextafter(std::fabs(w), kInf) - std::fabs(w);
  return static_cast<double>(std::fabs(static_cast<long double>(got) - want)) / ulp;
}

// the largest error over n arguments drawn by `draw`, printed; expected within `bound` ulps
void expect_within(const char* name, double bound, int n, const std::function<double(Rng&)>& draw,
                   const std::function<double(double)>& f,
                   const std::function<long double(long double)>& reference) {
  Rng rng(17);
  double worst = 0.0, at = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = draw(rng);
    const double e = ulps(f(x), reference(x));
    if (e > worst) {
      worst = e;
      at = x;
    }
  }
  std::printf("[ measured ] %s: at most %.3f ulp (at %a)\n", name, worst, at);
  EXPECT_LE(worst, bound) << name << " at " << at;
}

std::function<double(Rng&)> uniform(double lo, double hi) {
  return [lo, hi](Rng& r) { return lo + (hi - lo) * r.uniform(); };
}

// 2^e m with e uniform in [lo, hi) and m uniform in [1, 2), either sign when `sign`
std::function<double(Rng&)> log_uniform(int lo, int hi, bool sign = false) {
  return [lo, hi, sign](Rng& r) {
    const double v = std::ldexp(1.0 + r.uniform(), lo + static_cast<int>((hi - lo) * r.uniform()));
    return sign && r.uniform() < 0.5 ? -v : v;
  };
}

constexpr int kN = 100000;

TEST(Math, ExpAndExpm1AreWithinAnUlp) {
  expect_within("exp", 1.0, kN, uniform(-745.0, 709.7), math::exp,
                [](long double x) { return std::exp(x); });
  expect_within("exp near 0", 0.55, kN, uniform(-1.0, 1.0), math::exp,
                [](long double x) { return std::exp(x); });
  expect_within("expm1", 0.75, kN, uniform(-40.0, 40.0), math::expm1,
                [](long double x) { return std::expm1(x); });
  expect_within("expm1 near 0", 0.75, kN, log_uniform(-60, 0, true), math::expm1,
                [](long double x) { return std::expm1(x); });
}

TEST(Math, LogAndLog1pAreWithinAnUlp) {
  expect_within("log", 0.55, kN, log_uniform(-1074, 1024), math::log,
                [](long double x) { return std::log(x); });
  expect_within("log near 1", 0.55, kN, uniform(0.5, 2.0), math::log,
                [](long double x) { return std::log(x); });
  expect_within(
      "log1p", 0.7, kN, log_uniform(-60, 10, true),
      [](double x) { return math::log1p(x < -1.0 ? -x : x); },
      [](long double x) { return std::log1p(x < -1.0L ? -x : x); });
}

TEST(Math, SinCosWithinAnUlpAndTanWithinTwoUpToAMillionRadians) {
  for (const auto& [lo, hi] : {std::pair{-7.0, 7.0}, std::pair{-1e6, 1e6}}) {
    expect_within("sin", 0.8, kN, uniform(lo, hi), math::sin,
                  [](long double x) { return std::sin(x); });
    expect_within("cos", 0.8, kN, uniform(lo, hi), math::cos,
                  [](long double x) { return std::cos(x); });
    expect_within("tan", 2.1, kN, uniform(lo, hi), math::tan,
                  [](long double x) { return std::tan(x); });
  }
}

TEST(Math, ArcTangentsAndArcSinesAreWithinTwoUlps) {
  expect_within("atan", 1.25, kN, log_uniform(-30, 30, true), math::atan,
                [](long double x) { return std::atan(x); });
  // atan2 of (1, x) and (x, 1) and (-1, x): every octant
  for (const double y : {1.0, -1.0}) {
    expect_within(
        "atan2(y, x)", 1.5, kN, uniform(-20.0, 20.0), [y](double x) { return math::atan2(y, x); },
        [y](long double x) { return std::atan2(y, x); });
    expect_within(
        "atan2(x, y)", 1.5, kN, uniform(-20.0, 20.0), [y](double x) { return math::atan2(x, y); },
        [y](long double x) { return std::atan2(x, y); });
  }
  expect_within("asin", 2.0, kN, uniform(-1.0, 1.0), math::asin,
                [](long double x) { return std::asin(x); });
  expect_within("asinh", 1.5, kN, log_uniform(-40, 40, true), math::asinh,
                [](long double x) { return std::asinh(x); });
}

TEST(Math, HypotSinhAndPowAreWithinAnUlpOrSoForModestExponents) {
  for (const double y : {0.3, 3.0, 1e-200}) {
    expect_within(
        "hypot", 0.55, kN, log_uniform(-40, 40, true), [y](double x) { return math::hypot(x, y); },
        [y](long double x) { return std::hypot(x, static_cast<long double>(y)); });
  }
  expect_within(
      "hypot of large numbers", 0.9, kN, log_uniform(900, 1000, true),
      [](double x) { return math::hypot(x, 1e300); },
      [](long double x) { return std::hypot(x, 1e300L); });
  expect_within("sinh", 1.2, kN, uniform(-700.0, 700.0), math::sinh,
                [](long double x) { return std::sinh(x); });
  expect_within("sinh near 0", 1.2, kN, log_uniform(-40, 1, true), math::sinh,
                [](long double x) { return std::sinh(x); });
  // the powers the random walks and the spiral take: lengths to exponents in [-2, 0), their
  // inverses, 1.5, and small numbers to whole exponents
  for (const double y : {-2.0, -1.3, -0.5, -1.0 / 1.3, 1.5, 3.0, 17.0}) {
    expect_within(
        "pow", 1.05, kN, uniform(0.01, 20.0), [y](double x) { return math::pow(x, y); },
        [y](long double x) { return std::pow(x, static_cast<long double>(y)); });
  }
  // why: log x is carried to about 2^-60 of itself, so the error grows with |y log x|
  expect_within(
      "pow of large exponents", 3.5, kN, uniform(0.5, 2.0),
      [](double x) { return math::pow(x, 700.0); },
      [](long double x) { return std::pow(x, 700.0L); });
}

TEST(Math, ExactCasesAreExact) {
  EXPECT_EQ(math::exp(0.0), 1.0);
  EXPECT_EQ(math::expm1(0.0), 0.0);
  EXPECT_EQ(math::log(1.0), 0.0);
  EXPECT_EQ(math::log(8.0), 3.0 * std::numbers::ln2);
  EXPECT_EQ(math::sin(0.0), 0.0);
  EXPECT_EQ(math::cos(0.0), 1.0);
  EXPECT_EQ(math::atan2(0.0, -1.0), std::numbers::pi);
  EXPECT_EQ(math::atan2(1.0, 0.0), std::numbers::pi / 2);
  EXPECT_EQ(math::atan(1.0), std::numbers::pi / 4);
  EXPECT_EQ(math::asin(1.0), std::numbers::pi / 2);
  EXPECT_EQ(math::hypot(3.0, 4.0), 5.0);
  EXPECT_EQ(math::hypot(-2.5, 0.0), 2.5);
  EXPECT_EQ(math::pow(2.0, 10.0), 1024.0);
  EXPECT_EQ(math::pow(9.0, 0.5), 3.0);
  EXPECT_EQ(math::pow(0.3, 1.0), 0.3);
  EXPECT_EQ(math::pow(4.0, 1.5), 8.0);
}

TEST(Math, SpecialValuesFollowC) {
  const auto same = [](double a, double b) {
    return (std::isnan(a) && std::isnan(b)) || bits(a) == bits(b);
  };
  // zeros, infinities and NaN, alone and against ordinary numbers; C fixes every result
  const double specials[] = {0.0, -0.0, kInf, -kInf, kNaN};
  const double others[] = {1.0, -1.0, 0.5, -2.0, 1e-310, 1e300};
  for (const double x : specials) {
    EXPECT_TRUE(same(math::exp(x), std::exp(x))) << "exp " << x;
    EXPECT_TRUE(same(math::expm1(x), std::expm1(x))) << "expm1 " << x;
    EXPECT_TRUE(same(math::log(x), std::log(x))) << "log " << x;
    EXPECT_TRUE(same(math::log1p(x), std::log1p(x))) << "log1p " << x;
    EXPECT_TRUE(same(math::sin(x), std::sin(x))) << "sin " << x;
    EXPECT_TRUE(same(math::cos(x), std::cos(x))) << "cos " << x;
    EXPECT_TRUE(same(math::tan(x), std::tan(x))) << "tan " << x;
    EXPECT_TRUE(same(math::atan(x), std::atan(x))) << "atan " << x;
    EXPECT_TRUE(same(math::asin(x), std::asin(x))) << "asin " << x;
    EXPECT_TRUE(same(math::sinh(x), std::sinh(x))) << "sinh " << x;
    EXPECT_TRUE(same(math::asinh(x), std::asinh(x))) << "asinh " << x;
    for (const double y : specials) {
      EXPECT_TRUE(same(math::atan2(y, x), std::atan2(y, x))) << "atan2 " << y << " " << x;
      EXPECT_TRUE(same(math::hypot(x, y), std::hypot(x, y))) << "hypot " << x << " " << y;
      EXPECT_TRUE(same(math::pow(x, y), std::pow(x, y))) << "pow " << x << " " << y;
    }
    for (const double y : others) {
      EXPECT_TRUE(same(math::atan2(y, x), std::atan2(y, x))) << "atan2 " << y << " " << x;
      EXPECT_TRUE(same(math::atan2(x, y), std::atan2(x, y))) << "atan2 " << x << " " << y;
      EXPECT_TRUE(same(math::hypot(x, y), std::hypot(x, y))) << "hypot " << x << " " << y;
      EXPECT_TRUE(same(math::pow(x, y), std::pow(x, y))) << "pow " << x << " " << y;
      EXPECT_TRUE(same(math::pow(y, x), std::pow(y, x))) << "pow " << y << " " << x;
    }
  }
  // outside the domains: NaN
  for (const double x : {-1e-300, -1.0, -kInf}) {
    EXPECT_TRUE(std::isnan(math::log(x))) << x;
    EXPECT_TRUE(std::isnan(math::log1p(x - 1.5))) << x;
    EXPECT_TRUE(std::isnan(math::asin(x - 1.5))) << x;
  }
  // far out, sin, cos and tan are still numbers, bounded
  for (const double x : {0x1p30, -1e300, 1.7e308}) {
    EXPECT_LE(std::fabs(math::sin(x)), 1.0) << x;
    EXPECT_LE(std::fabs(math::cos(x)), 1.0) << x;
    EXPECT_FALSE(std::isnan(math::tan(x))) << x;
  }
  // the signs of zeros and of the angles at infinity
  EXPECT_EQ(bits(math::sin(-0.0)), bits(-0.0));
  EXPECT_EQ(bits(math::atan2(-0.0, 1.0)), bits(-0.0));
  EXPECT_EQ(math::atan2(-0.0, -1.0), -std::numbers::pi);
  EXPECT_EQ(math::atan2(kInf, -kInf), std::atan2(kInf, -kInf));
  EXPECT_EQ(math::atan2(-kInf, kInf), std::atan2(-kInf, kInf));
  EXPECT_EQ(math::pow(-2.0, 3.0), -8.0);
  EXPECT_EQ(bits(math::pow(-0.0, 3.0)), bits(-0.0));
  EXPECT_EQ(math::pow(-0.0, -3.0), -kInf);
  EXPECT_TRUE(std::isnan(math::pow(-2.0, 0.5)));
  EXPECT_EQ(math::hypot(kNaN, kInf), kInf);
  EXPECT_EQ(math::exp(710.0), kInf);
  EXPECT_EQ(math::exp(-746.0), 0.0);
  EXPECT_GT(math::exp(-740.0), 0.0);  // a subnormal
}

}  // namespace
}  // namespace plumetrace
