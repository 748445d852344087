#pragma once

// The arithmetic of the plume's inner loops, written so that the compiler can vectorise it and
// every lane gives the same bits as a scalar call: integer operations and IEEE +, -, *, /, sqrt
// only (each correctly rounded), no library calls, no fused multiply-adds (-ffp-contract=off),
// no branches. So results do not depend on the machine, the vector width or the thread count.

#include <bit>
#include <cmath>
#include <cstdint>

namespace plumetrace::vmath {

/// The SplitMix64 output function: a bijection of 64-bit values that mixes every bit.
/// a c mod 2^64 from 32-bit halves: a widening multiply for the low product, 32-bit ones for the
/// cross terms (their high halves drop out of the result).
inline std::uint64_t times_by_halves(std::uint64_t a, std::uint64_t c) {
  const auto a_lo = static_cast<std::uint32_t>(a), a_hi = static_cast<std::uint32_t>(a >> 32);
  const auto c_lo = static_cast<std::uint32_t>(c), c_hi = static_cast<std::uint32_t>(c >> 32);
  const std::uint32_t cross = a_lo * c_hi + a_hi * c_lo;
  return static_cast<std::uint64_t>(a_lo) * c_lo + (static_cast<std::uint64_t>(cross) << 32);
}

/// a c mod 2^64.
inline std::uint64_t times(std::uint64_t a, std::uint64_t c) {
#if defined(__aarch64__)
  // why: NEON has no 64-bit lane multiply, so GCC left the loops that hash (the plume's walk)
  // scalar; by halves it vectorises them
  return times_by_halves(a, c);
#else
  return a * c;
#endif
}

inline std::uint64_t mix64(std::uint64_t z) {
  z = times(z ^ (z >> 30), 0xbf58476d1ce4e5b9ULL);
  z = times(z ^ (z >> 27), 0x94d049bb133111ebULL);
  return z ^ (z >> 31);
}

/// Weyl increment of the SplitMix64 sequence.
inline constexpr std::uint64_t kGamma = 0x9e3779b97f4a7c15ULL;

/// The random bits of counter c of the stream `key`: SplitMix64 at position c.
inline std::uint64_t counter_bits(std::uint64_t key, std::uint64_t c) {
  return mix64(key + c * kGamma);
}

/// Natural logarithm of a normal float u > 0 (relative error below 2e-7).
inline float log_f(float u) {
  // u = 2^e m with m in [sqrt(1/2), sqrt(2)), by integer arithmetic on the bits (no branch)
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(u) - 0x3f3504f3u;
  const int e = static_cast<std::int32_t>(bits) >> 23;
  const float m = std::bit_cast<float>((bits & 0x007fffffu) + 0x3f3504f3u);
  // log m = 2 atanh(s) = 2 (s + s^3/3 + s^5/5 + ...), |s| <= 0.172
  const float s = (m - 1.0f) / (m + 1.0f);
  const float s2 = s * s;
  const float p = 1.0f + s2 * (1.0f / 3 + s2 * (1.0f / 5 + s2 * (1.0f / 7 + s2 * (1.0f / 9))));
  return static_cast<float>(e) * 0.693147181f + 2.0f * s * p;
}

/// Two independent standard normal samples from 64 random bits (Box-Muller), in single
/// precision (relative error below 3e-7).
///
/// The upper 31 bits give the radius, u in [2^-32, 1] (samples up to 6.66 standard deviations),
/// the lower 24 the angle: 2 bits of quadrant and 22 bits within it.
inline void normal_pair(std::uint64_t bits, float& a, float& b) {
  const auto hi = static_cast<std::int32_t>(bits >> 33);
  const float u = (static_cast<float>(hi) + 0.5f) * 0x1.0p-31f;
  const float r = std::sqrt(-2.0f * log_f(u));
  // angle (q + f) pi/2 with f in [-1/2, 1/2): cos and sin of x = f pi/2 by the minimax
  // polynomials of Cephes' single-precision sinf and cosf on [-pi/4, pi/4]
  const auto lo = static_cast<std::uint32_t>(bits);
  const std::uint32_t q = lo & 3u;
  const float f =
      static_cast<float>(static_cast<std::int32_t>((lo >> 2) & 0x3fffffu)) * 0x1.0p-22f - 0.5f;
  const float x = f * 1.57079633f, x2 = x * x;
  const float sin_x =
      x + x * x2 * (-1.6666654611e-1f + x2 * (8.3321608736e-3f + x2 * -1.9515295891e-4f));
  const float cos_x =
      1.0f - 0.5f * x2 +
      x2 * x2 *
          (4.166664568298827e-2f + x2 * (-1.388731625493765e-3f + x2 * 2.443315711809948e-5f));
  // rotate by q quarter turns
  const float c = (q & 1u) ? -sin_x : cos_x;
  const float s = (q & 1u) ? cos_x : sin_x;
  const float sign = (q & 2u) ? -r : r;
  a = sign * c;
  b = sign * s;
}

/// e^x for x <= 0 (relative error below 1e-14); 0 below -708.
inline double exp_neg(double x) {
  // x = k ln2 + r, |r| <= ln2 / 2; k rounded to nearest by the 1.5 * 2^52 shift
  constexpr double kShift = 0x1.8p52;
  const double t = x * 1.4426950408889634 + kShift;
  const double k = t - kShift;
  // why: ln2 split so that k * kLn2Hi is exact (Cody and Waite)
  const double r = (x - k * 0x1.62e42fee00000p-1) - k * 0x1.a39ef35793c76p-33;
  const double p =
      1.0 +
      r * (1.0 +
           r * (1.0 / 2 +
                r * (1.0 / 6 +
                     r * (1.0 / 24 +
                          r * (1.0 / 120 +
                               r * (1.0 / 720 +
                                    r * (1.0 / 5040 +
                                         r * (1.0 / 40320 + r * (1.0 / 362880 +
                                                                 r * (1.0 / 3628800 +
                                                                      r * (1.0 / 39916800 +
                                                                           r / 479001600)))))))))));
  // 2^k from its exponent bits (meaningful for k >= -1022, that is x >= -708)
  const std::int64_t ki = std::bit_cast<std::int64_t>(t) - std::bit_cast<std::int64_t>(kShift);
  const double scale = std::bit_cast<double>((ki + 1023) << 52);
  return x < -708.0 ? 0.0 : p * scale;
}

}  // namespace plumetrace::vmath
