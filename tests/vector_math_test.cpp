// The branch-free arithmetic of the plume's vector loops against libm and the normal law, and
// the choice of their vector path (plumetrace/core/simd.hpp).
#include "env/vector_math.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/simd.hpp"

namespace plumetrace::vmath {
namespace {

TEST(VectorMath, LogMatchesLibmAcrossTheUnitInterval) {
  // every binade the Box-Muller radius can meet, 2^-32 .. 1, at many mantissas
  double worst = 0.0;
  for (int e = -32; e <= 0; ++e) {
    for (int k = 0; k < 4096; ++k) {
      const float u = std::ldexp(1.0f + static_cast<float>(k) / 4096.0f, e - 1);
      const double want = std::log(static_cast<double>(u));
      const double err = std::abs(log_f(u) - want) / std::max(1.0, std::abs(want));
      worst = std::max(worst, err);
    }
  }
  EXPECT_LT(worst, 3e-7);
  EXPECT_EQ(log_f(1.0f), 0.0f);
}

TEST(VectorMath, ProductsByHalvesAreTheProductsMod2To64) {
  // the hash's product as aarch64 builds it (vmath::times), checked on every machine: the
  // mixer's two constants and the Weyl increment against a SplitMix64 sequence of factors, and
  // the extremes
  std::uint64_t state = 42;
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t a = counter_bits(7, static_cast<std::uint64_t>(i));
    const std::uint64_t factors[] = {0xbf58476d1ce4e5b9ULL, 0x94d049bb133111ebULL, kGamma,
                                     counter_bits(state, 1)};
    for (const std::uint64_t c : factors) {
      ASSERT_EQ(times_by_halves(a, c), a * c) << a << " " << c;
      ASSERT_EQ(times(a, c), a * c);
    }
    state += 1;
  }
  const std::uint64_t extremes[] = {0, 1, 0xffffffff, 0x100000000, ~std::uint64_t{0}};
  for (const std::uint64_t a : extremes) {
    for (const std::uint64_t c : extremes) {
      EXPECT_EQ(times_by_halves(a, c), a * c) << a << " " << c;
    }
  }
}

TEST(VectorMath, NormalPairLiesOnItsCircleAtItsAngle) {
  for (std::uint64_t c = 0; c < 200000; ++c) {
    const std::uint64_t bits = counter_bits(12345, c);
    float a, b;
    normal_pair(bits, a, b);
    // the radius and angle the bits stand for (u as the sampler rounds it to single precision),
    // in double precision with libm
    const double u =
        (static_cast<float>(static_cast<std::int32_t>(bits >> 33)) + 0.5f) * 0x1.0p-31f;
    const double r = std::sqrt(-2.0 * std::log(u));
    const auto lo = static_cast<std::uint32_t>(bits);
    const double theta = ((lo & 3u) + ((lo >> 2) & 0x3fffffu) * 0x1.0p-22 - 0.5) * (kPi / 2.0);
    ASSERT_NEAR(a, r * std::cos(theta), 1e-6 * (1.0 + r)) << "counter " << c;
    ASSERT_NEAR(b, r * std::sin(theta), 1e-6 * (1.0 + r)) << "counter " << c;
  }
}

TEST(VectorMath, ExpNegMatchesLibmDownToItsFloor) {
  double worst = 0.0;
  for (int k = 0; k <= 708000; ++k) {
    const double x = -k * 0.9999987e-3;
    worst = std::max(worst, std::abs(exp_neg(x) - std::exp(x)) / std::exp(x));
  }
  EXPECT_LT(worst, 1e-14);
  EXPECT_EQ(exp_neg(0.0), 1.0);
  EXPECT_EQ(exp_neg(-708.5), 0.0);
  EXPECT_EQ(exp_neg(-1e6), 0.0);
  EXPECT_EQ(exp_neg(-INFINITY), 0.0);
}

// standard normal CDF
double phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

TEST(VectorMath, NormalPairsFollowTheNormalLawIndependently) {
  const double edges[] = {-INFINITY, -5.0, -4.0, -3.0, -2.0, -1.0, -0.5,    0.0,
                          0.5,       1.0,  2.0,  3.0,  4.0,  5.0,  INFINITY};
  const int bins = static_cast<int>(std::size(edges)) - 1;
  std::vector<long> counts(bins, 0);
  const long pairs = 2'000'000;
  double within = 0.0, across = 0.0, largest = 0.0;  // sums of a b, and of b with the next a
  float previous_b = 0.0f;
  for (long c = 0; c < pairs; ++c) {
    float a, b;
    normal_pair(counter_bits(0x5eed, static_cast<std::uint64_t>(c)), a, b);
    for (const double x : {static_cast<double>(a), static_cast<double>(b)}) {
      int bin = 0;
      while (x >= edges[bin + 1]) ++bin;
      ++counts[bin];
      largest = std::max(largest, std::abs(x));
    }
    within += static_cast<double>(a) * b;
    across += static_cast<double>(previous_b) * a;
    previous_b = b;
  }
  const double n = 2.0 * pairs;
  for (int bin = 0; bin < bins; ++bin) {
    const double p = phi(edges[bin + 1]) - phi(edges[bin]);
    EXPECT_NEAR(counts[bin], p * n, 4.0 * std::sqrt(n * p * (1.0 - p)) + 1.0) << "bin " << bin;
  }
  // correlation of independent unit normals: mean 0, standard error 1 / sqrt(pairs)
  EXPECT_NEAR(within / pairs, 0.0, 4.0 / std::sqrt(pairs));
  EXPECT_NEAR(across / pairs, 0.0, 4.0 / std::sqrt(pairs));
  EXPECT_LE(largest, 6.67);  // u >= 2^-32: r <= sqrt(64 ln 2)
}

}  // namespace
}  // namespace plumetrace::vmath

namespace plumetrace::simd {
namespace {

// the message of the std::invalid_argument that parse(text) throws ("" when it throws none)
std::string refusal(const std::string& text) {
  try {
    parse(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(Simd, EveryAvailablePathIsNamedAndAutoIsTheWidest) {
  const std::vector<Path> paths = available();
  ASSERT_GE(paths.size(), 2u);
  EXPECT_EQ(paths[0], Path::kScalar);
  EXPECT_EQ(paths[1], Path::kBaseline);
  EXPECT_EQ(best(), paths.back());
  EXPECT_EQ(parse("auto"), best());
  for (const Path p : paths) {
    EXPECT_TRUE(available(p));
    EXPECT_EQ(parse(name(p)), p) << name(p);
  }
#if defined(__x86_64__)
  EXPECT_EQ(names(), (std::vector<std::string_view>{"auto", "scalar", "sse2", "avx2", "avx512"}));
#endif
  // the one line for people names the active path first
  EXPECT_EQ(describe().rfind(std::string(name(active())) + " (available: scalar, ", 0), 0u)
      << describe();
}

TEST(Simd, AnUnknownNameIsRefusedNamingTheVariableAndTheChoices) {
  for (const std::string bad : {"fast", "", "AVX2", "avx2 "}) {
    const std::string message = refusal(bad);
    EXPECT_NE(message.find("PLUMETRACE_SIMD"), std::string::npos) << message;
    EXPECT_NE(message.find("unknown path \"" + bad + "\""), std::string::npos) << message;
    for (const std::string_view n : names()) {
      EXPECT_NE(message.find(n), std::string::npos) << n << ": " << message;
    }
  }
}

// This machine's processor lacks AVX-512, so the refusal is tested for real; on one that has it
// (and a build with the AVX-512 path) there is nothing to refuse.
TEST(Simd, APathTheProcessorLacksIsRefusedNamingThoseItRuns) {
#if !defined(__x86_64__)
  GTEST_SKIP() << "avx512 is not a path of this architecture (the unknown-name test covers it)";
#endif
  if (available(Path::kAvx512)) {
    GTEST_SKIP() << "this machine runs the AVX-512 path: nothing to refuse";
  }
  const std::string message = refusal("avx512");
  EXPECT_NE(message.find("PLUMETRACE_SIMD: \"avx512\""), std::string::npos) << message;
  EXPECT_NE(message.find("AVX-512"), std::string::npos) << message;
  EXPECT_NE(message.find("this machine runs auto, scalar"), std::string::npos) << message;
  // select() refuses it too and keeps the path in use
  const Path before = active();
  EXPECT_THROW(select("avx512"), std::invalid_argument);
  EXPECT_THROW(select(Path::kAvx512), std::invalid_argument);
  EXPECT_EQ(active(), before);
}

TEST(Simd, SelectChangesTheActivePathForEveryLaterCall) {
  const Path before = active();
  for (const Path p : available()) {
    select(name(p));
    EXPECT_EQ(active(), p);
  }
  select("scalar");
  EXPECT_EQ(active(), Path::kScalar);
  select(before);
  EXPECT_EQ(active(), before);
}

}  // namespace
}  // namespace plumetrace::simd
