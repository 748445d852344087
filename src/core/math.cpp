#include "plumetrace/core/math.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "math_tables.hpp"

// why: every function here is a fixed sequence of IEEE +, -, *, / and sqrt (correctly rounded,
// so the same on every machine) and integer operations: range reduction by exactly
// representable parts of ln 2 and pi / 2 (Cody and Waite), then a truncated Taylor series on
// the reduced argument, evaluated by Horner's rule. std::sqrt, std::fabs, std::copysign and
// std::signbit are exact operations, not approximations. The constants are the decimal or
// hexadecimal values of the named numbers, rounded to double.

namespace plumetrace::math {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ln 2 = kLn2Hi + kLn2Lo, kLn2Hi with 32 significant bits (k kLn2Hi exact for |k| < 2^21)
constexpr double kLn2Hi = 0x1.62e42ff000000p-1;
constexpr double kLn2Lo = -0x1.718432a1b0e26p-35;
constexpr double kInvLn2 = 0x1.71547652b82fep+0;
// pi / 2 = kPio2A + kPio2B + kPio2C, the first two with 33 significant bits each (n kPio2A and
// n kPio2B exact for |n| < 2^20)
constexpr double kPio2A = 0x1.921fb54400000p+0;
constexpr double kPio2B = 0x1.0b4611a600000p-34;
constexpr double kPio2C = 0x1.3198a2e037073p-69;
constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
// pi and pi / 2 as a double and the rest
constexpr double kPiHi = 0x1.921fb54442d18p+1, kPiLo = 0x1.1a62633145c07p-53;
constexpr double kPio2Hi = 0x1.921fb54442d18p+0, kPio2Lo = 0x1.1a62633145c07p-54;
// atan(k / 8) for k = 0..8, as a double and the rest
constexpr double kAtanHi[9] = {0.0,
                               0x1.fd5ba9aac2f6ep-4,
                               0x1.f5b75f92c80ddp-3,
                               0x1.6f61941e4def1p-2,
                               0x1.dac670561bb4fp-2,
                               0x1.1e00babdefeb4p-1,
                               0x1.4978fa3269ee1p-1,
                               0x1.700a7c5784634p-1,
                               0x1.921fb54442d18p-1};
constexpr double kAtanLo[9] = {0.0,
                               -0x1.cd37686760c17p-59,
                               0x1.8ab6e3cf7afbdp-57,
                               -0x1.c63aae6f6e918p-56,
                               0x1.a2b7f222f65e2p-56,
                               -0x1.928df287a668fp-58,
                               0x1.2419a87f2a458p-56,
                               -0x1.8c34d25aadef6p-56,
                               0x1.1a62633145c07p-55};

// exp: above this e^x overflows, below the other it rounds to 0
constexpr double kExpMax = 0x1.62e42fefa39efp+9;   // ln(DBL_MAX), 709.78
constexpr double kExpMin = -0x1.74910d52d3052p+9;  // ln(2^-1075), -745.13

// the nearest integer to x (|x| < 2^51), ties to even, as a double
double nearest(double x) {
  constexpr double kShift = 0x1.8p52;
  return (x + kShift) - kShift;
}

// c[0] + z (c[1] + z (c[2] + ...)): a polynomial by Horner's rule
template <std::size_t N>
double horner(double z, const std::array<double, N>& c) {
  double p = c[N - 1];
  for (std::size_t i = N - 1; i-- > 0;) p = c[i] + z * p;
  return p;
}

// the same polynomial of 8 coefficients in halves (Estrin's scheme): a shorter chain of
// dependent operations, other roundings than Horner's but the same on every machine
double estrin(double z, const std::array<double, 8>& c) {
  const double z2 = z * z, z4 = z2 * z2;
  return ((c[0] + z * c[1]) + z2 * (c[2] + z * c[3])) +
         z4 * ((c[4] + z * c[5]) + z2 * (c[6] + z * c[7]));
}

// 1 / n! for n = 0..22
constexpr std::array<double, 23> kInvFactorial = [] {
  std::array<double, 23> v{};
  double f = 1.0;  // n!, exact to 22! in a double
  for (int n = 0; n <= 22; ++n) {
    if (n > 0) f *= n;
    v[n] = 1.0 / f;
  }
  return v;
}();

// c[i] = sign^i / (first + step i)!
template <std::size_t N>
constexpr std::array<double, N> series(int first, int step, double sign) {
  std::array<double, N> c{};
  double sg = 1.0;
  for (std::size_t i = 0; i < N; ++i) {
    c[i] = sg * kInvFactorial[first + step * static_cast<int>(i)];
    sg *= sign;
  }
  return c;
}

// p 2^k for an integer k: exact unless the result is subnormal (one rounding) or overflows
double scale2(double p, int k) {
  const auto power = [](int e) {  // 2^e for e in [-1022, 1023]
    return std::bit_cast<double>(static_cast<std::uint64_t>(e + 1023) << 52);
  };
  while (k > 1023) {
    p *= power(1023);
    k -= 1023;
  }
  if (k < -1022) {
    // why: scaled up first, the product stays normal; the last multiply rounds once
    p *= power(k + 600);
    return p * power(-600);
  }
  return p * power(k);
}

// x = n pi / 2 + r + rl, |r| <= pi / 4, rl below r's last bit (for |x| < 2^30); returns n mod 4
int reduce_pio2(double x, double& r, double& rl) {
  if (std::fabs(x) <= 0x1.921fb54442d18p-1) {  // pi / 4
    r = x;
    rl = 0.0;
    return 0;
  }
  if (!(std::fabs(x) < 0x1p30)) {
    // why: beyond 2^30 the rest of 2/pi's digits would be needed for accuracy; x is taken modulo
    // 2 pi rounded to double instead (exactly), so results are bounded and the same on every
    // machine, but not accurate
    x = std::fmod(x, 2.0 * kPiHi);
  }
  const double n = nearest(x * kTwoOverPi);
  // x - n kPio2A is exact, and so is n kPio2B (for |n| < 2^20); their difference in two parts
  const double t = x - n * kPio2A, w = n * kPio2B;
  r = t - w;
  rl = ((t - r) - w) - n * kPio2C;
  const double r2 = r + rl;  // renormalised
  rl -= r2 - r;
  r = r2;
  return static_cast<int>(static_cast<std::int64_t>(n) & 3);  // |n| < 2^31 here
}

// sin(r + rl) and cos(r + rl) for |r| <= pi / 4, rl below r's last bit: Taylor series to r^17
// and r^18 (rests below 2^-57), rl to first order
double sin_kernel(double r, double rl) {
  static constexpr auto c = series<8>(3, 2, -1.0);  // 1 / 3!, -1 / 5!, ..., -1 / 17!
  const double z = r * r;
  return r + (r * z * -estrin(z, c) + rl * (1.0 - 0.5 * z));
}

double cos_kernel(double r, double rl) {
  static constexpr auto c = series<8>(4, 2, -1.0);  // 1 / 4!, -1 / 6!, ..., -1 / 18!
  const double z = r * r;
  const double p = estrin(z, c);
  // why: 1 - z / 2 as w plus what rounding w lost, exactly (w is within a factor 2 of 1)
  const double hz = 0.5 * z;
  const double w = 1.0 - hz;
  return w + (((1.0 - w) - hz) + (z * z * p - r * rl));
}

// atan t for 0 <= t <= 1: below 3/16 its Taylor series to t^25 (rest below 2^-62 t); above,
// atan(k / 8) + atan(u), u = (t - k / 8) / (1 + t k / 8), |u| <= 1/16, k >= 2, by the series to
// u^17 (why: k = 1 would take a larger number from a smaller one and lose a bit)
double atan_unit(double t) {
  // atan u = u + u z (c1 + z (c2 + ...)), z = u^2, c_n = (-1)^n / (2n + 1), to term n = `terms`
  constexpr auto coef = [] {
    std::array<double, 13> v{};
    for (int n = 1; n <= 12; ++n) v[n] = (n % 2 ? -1.0 : 1.0) / (2 * n + 1);
    return v;
  }();
  const auto series = [&coef](double u, int terms) {
    const double z = u * u;
    double q = coef[terms];
    for (int n = terms - 1; n >= 1; --n) q = coef[n] + z * q;
    return u + u * z * q;
  };
  if (t < 0.1875) return series(t, 12);
  const int k = static_cast<int>(nearest(8.0 * t));
  const double c = 0.125 * k;
  const double u = (t - c) / (1.0 + t * c);  // t - c is exact
  return kAtanHi[k] + (series(u, 8) + kAtanLo[k]);
}

// a * b = hi + lo exactly (Dekker's product: Veltkamp's split of each factor in 26 bits)
void exact_product(double a, double b, double& hi, double& lo) {
  const auto split = [](double v, double& h, double& l) {
    const double c = 134217729.0 * v;  // 2^27 + 1
    h = c - (c - v);
    l = v - h;
  };
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  hi = a * b;
  lo = ((ah * bh - hi) + ah * bl + al * bh) + al * bl;
}

// a + b = s + err exactly (Knuth's TwoSum)
void two_sum(double a, double b, double& s, double& err) {
  s = a + b;
  const double bb = s - a;
  err = (a - (s - bb)) + (b - bb);
}

// the same for |a| >= |b| or a = 0, in 3 operations instead of 6 (Dekker's Fast2Sum); both give
// a + b's rounding and its exact error, so the same s and err
void fast_two_sum(double a, double b, double& s, double& err) {
  s = a + b;
  err = b - (s - a);
}

// 1 / (1 + (i + 1/2) / 128), the midpoints of the table of logarithms
constexpr std::array<double, 128> kInvMid = [] {
  std::array<double, 128> v{};
  for (int i = 0; i < 128; ++i) v[i] = 1.0 / (1.0 + (2 * i + 1) / 256.0);
  return v;
}();

// log x = hi + lo to about 2^-60 |hi| for finite x > 0.
// Near 1 (15/16 < x < 17/16): f = x - 1 (exact), s = f / (2 + f) = sh + sl (sl what the division
// lost), log x = 2 atanh s = 2 s + s R with R = 2 (s^2/3 + s^4/5 + ... + s^12/13).
// Elsewhere: x = 2^e m, m in [1, 2), c the midpoint of m's 1/128 of [1, 2),
// log x = e ln 2 + ln c + log1p(r), r = (m - c) / c (|r| <= 2^-8, m - c exact), log1p r by its
// Taylor series to r^7, ln c from the table (scripts/math_tables.py)
// why: inlined into its callers (log, log1p, pow), which then wait on no memory round trip for
// hi and lo (the same operations)
[[gnu::always_inline]] inline void log_parts(double x, double& hi, double& lo) {
  if (x > 0.9375 && x < 1.0625) {
    const double f = x - 1.0;
    const double d = 2.0 + f, dl = f - (d - 2.0);  // 2 + f = d + dl exactly
    const double sh = f / d;
    // sl = (f - sh (d + dl)) / d, with sh d = p + pl exactly and f - p exact (p is near f)
    double p, pl;
    exact_product(sh, d, p, pl);
    const double sl = (((f - p) - pl) - sh * dl) / d;
    static constexpr auto c = [] {  // 2/3, 2/5, ..., 2/13
      std::array<double, 6> v{};
      for (int n = 1; n <= 6; ++n) v[n - 1] = 2.0 / (2 * n + 1);
      return v;
    }();
    const double z = sh * sh;
    hi = 2.0 * sh;
    lo = 2.0 * sl + sh * (z * horner(z, c));
    return;
  }
  int e = 0;
  if (x < 0x1p-1022) {  // subnormal: scaled to normal, exactly
    x *= 0x1p54;
    e = -54;
  }
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
  e += static_cast<int>(bits >> 52) - 1023;
  const double m = std::bit_cast<double>((bits & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL);
  const int i = static_cast<int>((bits >> 45) & 127);
  // c = 1 + (2 i + 1) / 256: m's top 7 bits of mantissa and a 1 after them, exactly
  const double c = std::bit_cast<double>((bits & 0x000fe00000000000ULL) | 0x3ff0100000000000ULL);
  const double r = (m - c) * kInvMid[i];
  static constexpr std::array<double, 6> kLog1p = {-1.0 / 2, 1.0 / 3,  -1.0 / 4,
                                                   1.0 / 5,  -1.0 / 6, 1.0 / 7};
  const double rest = r * r * horner(r, kLog1p);  // log1p r - r
  const double de = static_cast<double>(e);
  // (e ln2_hi + ln c_hi) + r, each sum split exactly, and the small terms. why Fast2Sum holds:
  // |ln c_hi| < ln 2 <= |e ln2_hi| unless e = 0; and |r| <= 1 / (256 c) < |ln c| for e = 0, or
  // |r| <= 2^-8 < 0.06 < |e ln2_hi + ln c_hi| otherwise (x in (15/16, 17/16) went above)
  double s1, e1, e2;
  fast_two_sum(de * kLn2Hi, tables::kLogMid[i][0], s1, e1);
  fast_two_sum(s1, r, hi, e2);
  lo = (e1 + e2) + (rest + (de * kLn2Lo + tables::kLogMid[i][1]));
}

// e^x = 2^k (hi + tail) for |x| < 746, returning k: x = n ln2 / 128 + r + rl with
// n = 128 k + j, 0 <= j < 128 and |r| <= ln2 / 256 (x - n ln2_hi / 128 is exact, |n| < 2^18; r + rl
// is its difference with n ln2_lo / 128, exactly); hi = 2^(j/128) from the table and
// tail = its rest + hi (e^(r + rl) - 1), that by its Taylor series to r^5 (rest below 2^-61 r)
int exp_reduce(double x, double& hi, double& tail) {
  const double n = nearest(x * (128.0 * kInvLn2));
  const double t = x - n * (kLn2Hi / 128), w = n * (kLn2Lo / 128);
  const double r = t - w, rl = (t - r) - w;
  const int ni = static_cast<int>(n);
  // why: the polynomial in two halves (Estrin's scheme), a shorter chain of dependent operations
  const double r2 = r * r;
  const double p = r + (r2 * ((0.5 + r * (1.0 / 6)) + r2 * (1.0 / 24 + r * (1.0 / 120))) + rl);
  hi = tables::kExp2[ni & 127][0];
  tail = tables::kExp2[ni & 127][1] + hi * p;
  return ni >> 7;
}

// x is an integer (finite)
bool is_integer(double x) { return std::floor(x) == x; }
// x is an odd integer (finite)
bool is_odd(double x) { return is_integer(x) && std::fabs(x) < 0x1p53 && std::fmod(x, 2.0) != 0.0; }

// e^x and log(1 + x), inlined into exp and log1p and into the functions that call them (pow,
// asinh), which then wait on no call or memory round trip (the same operations)
[[gnu::always_inline]] inline double exp_inline(double x) {
  if (x != x) return x + x;
  if (x > kExpMax) return kInf;
  if (x < kExpMin) return 0.0;
  if (std::fabs(x) < 0x1p-54) return 1.0 + x;
  double hi, tail;
  const int k = exp_reduce(x, hi, tail);
  return scale2(hi + tail, k);
}

[[gnu::always_inline]] inline double log1p_inline(double x) {
  if (x != x) return x + x;
  if (x < -1.0) return kNaN;
  if (x == -1.0) return -kInf;
  if (x == kInf || std::fabs(x) < 0x1p-54) return x;
  // why: u = 1 + x rounds; log u + (x - (u - 1)) / u puts back what the rounding lost (u - 1 is
  // exact), to first order
  const double u = 1.0 + x;
  double hi, lo;
  log_parts(u, hi, lo);
  return hi + (lo + (x - (u - 1.0)) / u);
}

}  // namespace

double exp(double x) { return exp_inline(x); }

double expm1(double x) {
  if (x != x) return x + x;
  if (x > kExpMax) return kInf;
  if (x < -40.0) return -1.0;  // e^x < 2^-57: -1 to the bit
  if (std::fabs(x) < 0x1p-54) return x;
  if (std::fabs(x) < 0x1p-5) {
    // the Taylor series to x^10 (its rest is below 2^-60 x)
    static constexpr auto c = series<9>(2, 1, 1.0);  // 1/2!, ..., 1/10!
    return x + x * x * horner(x, c);
  }
  double hi, tail;
  const int k = exp_reduce(x, hi, tail);
  if (k > 56) return scale2(hi + tail, k) - 1.0;  // the 1 is below the last bit
  // 2^k hi - 1 + 2^k tail: both products exact (k >= -58), the difference split exactly
  double s, err;
  two_sum(scale2(hi, k), -1.0, s, err);
  return s + (err + scale2(tail, k));
}

double log(double x) {
  if (!(x > 0.0 && x < kInf)) {
    if (x != x) return x + x;
    if (x < 0.0) return kNaN;
    return x == 0.0 ? -kInf : x;
  }
  double hi, lo;
  log_parts(x, hi, lo);
  return hi + lo;
}

double log1p(double x) { return log1p_inline(x); }

double pow(double x, double y) {
  if (y == 0.0 || x == 1.0) return 1.0;
  if (x != x || y != y) return x + y;
  const double ax = std::fabs(x);
  if (std::fabs(y) == kInf) {
    if (ax == 1.0) return 1.0;
    return (ax < 1.0) == (y < 0.0) ? kInf : 0.0;
  }
  if (x == 0.0 || ax == kInf) {
    // 0^y and inf^y: 0 or inf, with x's sign for an odd integer y
    const bool big = (x == 0.0) == (y < 0.0);
    const double v = big ? kInf : 0.0;
    return std::signbit(x) && is_odd(y) ? -v : v;
  }
  if (x < 0.0 && !is_integer(y)) return kNaN;
  // the powers that are one operation, correctly rounded
  if (y == 1.0) return x;
  if (y == -1.0) return 1.0 / x;
  if (y == 2.0) return x * x;
  if (y == 0.5) return std::sqrt(x);
  // |x|^y = e^(y log |x|), with log |x| and its product by y carried in two parts
  double lh, ll;
  log_parts(ax, lh, ll);
  double ph = y * lh, pl = 0.0;
  if (std::fabs(ph) < 0x1p11) {  // else the result overflows or underflows whatever pl
    exact_product(y, lh, ph, pl);
    pl += y * ll;
  }
  const double z = ph + pl;
  double v;
  if (z > kExpMax) {
    v = kInf;
  } else if (z < kExpMin) {
    v = 0.0;
  } else {
    const double zl = pl - (z - ph);  // what z lost of ph + pl
    const double e = exp_inline(z);
    v = e + e * zl;  // e^(z + zl) = e^z (1 + zl), |zl| < 2^-52 |z|
  }
  // why: y's parity only for x < 0 (floor and fmod are calls on the baseline x86-64)
  return x < 0.0 && is_odd(y) ? -v : v;
}

double sin(double x) {
  if (!(std::fabs(x) < kInf)) return x - x;  // NaN for NaN and infinities
  if (std::fabs(x) < 0x1p-27) return x;      // x^3 / 6 is below x's last bit; keeps -0
  double r, rl;
  switch (reduce_pio2(x, r, rl)) {
    case 0:
      return sin_kernel(r, rl);
    case 1:
      return cos_kernel(r, rl);
    case 2:
      return -sin_kernel(r, rl);
    default:
      return -cos_kernel(r, rl);
  }
}

double cos(double x) {
  if (!(std::fabs(x) < kInf)) return x - x;  // NaN for NaN and infinities
  double r, rl;
  switch (reduce_pio2(x, r, rl)) {
    case 0:
      return cos_kernel(r, rl);
    case 1:
      return -sin_kernel(r, rl);
    case 2:
      return -cos_kernel(r, rl);
    default:
      return sin_kernel(r, rl);
  }
}

double tan(double x) {
  if (!(std::fabs(x) < kInf)) return x - x;  // NaN for NaN and infinities
  if (std::fabs(x) < 0x1p-27) return x;      // x^3 / 3 is below x's last bit; keeps -0
  double r, rl;
  const int n = reduce_pio2(x, r, rl);
  const double s = sin_kernel(r, rl), c = cos_kernel(r, rl);
  return n % 2 == 0 ? s / c : -c / s;
}

double atan(double x) {
  if (x != x) return x + x;
  const double ax = std::fabs(x);
  // why: for |x| > 1, atan x = pi/2 - atan(1/x), pi/2 in two parts
  const double a = ax <= 1.0 ? atan_unit(ax) : kPio2Hi - (atan_unit(1.0 / ax) - kPio2Lo);
  return std::copysign(a, x);
}

double atan2(double y, double x) {
  if (x != x || y != y) return x + y;
  const double ax = std::fabs(x), ay = std::fabs(y);
  const bool left = std::signbit(x);  // x < 0 or x = -0
  double a;                           // the angle for |y|
  if (ay == 0.0) {
    a = left ? kPiHi : 0.0;
  } else if (ax == kInf && ay == kInf) {
    a = left ? 3.0 * (0.5 * kPio2Hi) : 0.5 * kPio2Hi;
  } else if (ax == 0.0 || ay == kInf) {
    a = kPio2Hi;
  } else if (ax == kInf) {
    a = left ? kPiHi : 0.0;
  } else {
    // the angle of (|x|, |y|) in [0, pi/2], then reflected for x < 0
    const double b = ay <= ax ? atan_unit(ay / ax) : kPio2Hi - (atan_unit(ax / ay) - kPio2Lo);
    a = left ? kPiHi - (b - kPiLo) : b;
  }
  return std::copysign(a, y);
}

double asin(double x) {
  if (x != x) return x + x;
  if (std::fabs(x) > 1.0) return kNaN;
  return atan2(x, std::sqrt((1.0 - x) * (1.0 + x)));
}

double hypot(double x, double y) {
  const double ax = std::fabs(x), ay = std::fabs(y);
  if (ax == kInf || ay == kInf) return kInf;
  if (x != x || y != y) return x + y;
  const double big = ax >= ay ? ax : ay, small = ax >= ay ? ay : ax;
  if (small == 0.0) return big;
  // why: scaled by a power of 2 (exactly) where a square would overflow or underflow
  double scale = 1.0;
  if (big > 0x1p500) {
    scale = 0x1p600;
  } else if (big < 0x1p-450) {
    scale = 0x1p-600;
  }
  const double a = big / scale, b = small / scale;
  double h = std::sqrt(a * a + b * b);
  // one Newton step on h^2 = a^2 + b^2 with the squares' rounding errors counted exactly
  // (Borges 2021, "An improved algorithm for hypot(a, b)", without fused multiply-adds)
  double hh, hl, aa, al, bb, bl;
  exact_product(h, h, hh, hl);
  exact_product(a, a, aa, al);
  exact_product(b, b, bb, bl);
  const double excess = (((hh - aa) - bb) + ((hl - al) - bl));  // hh - aa is exact
  h -= excess / (2.0 * h);
  return h * scale;
}

double sinh(double x) {
  if (x != x) return x + x;
  const double ax = std::fabs(x);
  double v;
  if (ax < 1.0) {
    // the Taylor series to a^21 (rest below 2^-60 a): a + a z (1/3! + z (1/5! + ...)), z = a^2
    static constexpr auto c = series<10>(3, 2, 1.0);  // 1 / 3!, 1 / 5!, ..., 1 / 21!
    const double z = ax * ax;
    const double p = horner(z, c);
    v = ax + ax * z * p;
  } else if (ax < 22.0) {
    // (e^a - e^-a) / 2 = (E + E / (E + 1)) / 2 with E = e^a - 1, no cancellation
    const double e = expm1(ax);
    v = 0.5 * (e + e / (e + 1.0));
  } else if (ax < kExpMax) {
    v = 0.5 * exp(ax);
  } else {
    const double h = exp(0.5 * ax);  // e^a / 2 = (e^(a/2) / 2) e^(a/2), overflow only at the end
    v = (0.5 * h) * h;
  }
  return std::copysign(v, x);
}

double asinh(double x) {
  if (x != x || std::fabs(x) == kInf) return x + x;
  const double a = std::fabs(x);
  double v;
  if (a < 0x1p-28) {
    v = a;  // asinh a = a - a^3/6 + ...: a to the last bit
  } else if (a > 0x1p28) {
    v = log(a) + kLn2Hi + kLn2Lo;  // log(2 a): sqrt(a^2 + 1) = a to the last bit
  } else {
    // log(a + sqrt(a^2 + 1)) = log1p(a + a^2 / (1 + sqrt(a^2 + 1))), no cancellation
    const double a2 = a * a;
    v = log1p_inline(a + a2 / (1.0 + std::sqrt(a2 + 1.0)));
  }
  return std::copysign(v, x);
}

}  // namespace plumetrace::math
