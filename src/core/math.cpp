#include "plumetrace/core/math.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

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

// x = k ln 2 + r with k the nearest integer to x / ln 2 and |r| <= ln 2 / 2 (to a few ulps)
double reduce_ln2(double x, double& k) {
  k = nearest(x * kInvLn2);
  return (x - k * kLn2Hi) - k * kLn2Lo;
}

// e^r - 1 - r for |r| <= 0.75: the Taylor series to r^18 (its rest is below 2^-60 r^2)
double expm1_rest(double r) {
  static constexpr auto c = series<17>(2, 1, 1.0);  // 1 / 2!, ..., 1 / 18!
  return r * r * horner(r, c);
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
  const double quarter = std::fmod(n, 4.0);  // exact
  return static_cast<int>(quarter < 0.0 ? quarter + 4.0 : quarter);
}

// sin(r + rl) and cos(r + rl) for |r| <= pi / 4, rl below r's last bit: Taylor series to r^17
// and r^18 (rests below 2^-57), rl to first order
double sin_kernel(double r, double rl) {
  static constexpr auto c = series<8>(3, 2, -1.0);  // 1 / 3!, -1 / 5!, ..., -1 / 17!
  const double z = r * r;
  return r + (r * z * -horner(z, c) + rl * (1.0 - 0.5 * z));
}

double cos_kernel(double r, double rl) {
  static constexpr auto c = series<8>(4, 2, -1.0);  // 1 / 4!, -1 / 6!, ..., -1 / 18!
  const double z = r * r;
  const double p = horner(z, c);
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

// log x = hi + lo to about 2^-60 |hi| for finite x > 0: x = 2^e m, m in [sqrt(1/2), sqrt(2)),
// f = m - 1 (exact), s = f / (2 + f) = sh + sl (sl what the division lost), log m = 2 atanh s
// = 2 s + s R with R = 2 (s^2/3 + s^4/5 + ... + s^22/23)
void log_parts(double x, double& hi, double& lo) {
  int e = 0;
  if (x < 0x1p-1022) {  // subnormal: scaled to normal, exactly
    x *= 0x1p54;
    e = -54;
  }
  constexpr std::uint64_t kSqrtHalf = 0x3fe6a09e667f3bcdULL;  // the bits of sqrt(1/2)
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(x) - kSqrtHalf;
  e += static_cast<int>(static_cast<std::int64_t>(bits) >> 52);
  const double m = std::bit_cast<double>((bits & 0x000fffffffffffffULL) + kSqrtHalf);
  const double f = m - 1.0;
  const double d = 2.0 + f, dl = f - (d - 2.0);  // 2 + f = d + dl exactly
  const double sh = f / d;
  // sl = (f - sh (d + dl)) / d, with sh d = p + pl exactly and f - p exact (p is near f)
  double p, pl;
  exact_product(sh, d, p, pl);
  const double sl = (((f - p) - pl) - sh * dl) / d;
  const double z = sh * sh;
  static constexpr auto c = [] {  // 2/3, 2/5, ..., 2/23
    std::array<double, 11> v{};
    for (int n = 1; n <= 11; ++n) v[n - 1] = 2.0 / (2 * n + 1);
    return v;
  }();
  const double r = z * horner(z, c);
  const double de = static_cast<double>(e);
  // hi + lo = (de ln2_hi + 2 sh) + (2 sl + sh R + de ln2_lo); the first two are exact, and
  // their sum is split exactly (Fast2Sum, larger first)
  const double a = de * kLn2Hi, b = 2.0 * sh;
  hi = a + b;
  const double lost = std::fabs(a) >= std::fabs(b) ? (a - hi) + b : (b - hi) + a;
  lo = lost + ((2.0 * sl + sh * r) + de * kLn2Lo);
}

// x is an integer (finite)
bool is_integer(double x) { return std::floor(x) == x; }
// x is an odd integer (finite)
bool is_odd(double x) { return is_integer(x) && std::fabs(x) < 0x1p53 && std::fmod(x, 2.0) != 0.0; }

}  // namespace

double exp(double x) {
  if (x != x) return x + x;
  if (x > kExpMax) return kInf;
  if (x < kExpMin) return 0.0;
  if (std::fabs(x) < 0x1p-54) return 1.0 + x;
  // x = k ln 2 + r + rl: x - k ln2_hi is exact, r + rl its difference with k ln2_lo exactly
  const double k = nearest(x * kInvLn2);
  const double t = x - k * kLn2Hi, w = k * kLn2Lo;
  const double r = t - w, rl = (t - r) - w;
  // e^(r + rl) = 1 + r + (e^r - 1 - r) + rl e^r, with 1 + r = s + sl exactly
  const double s = 1.0 + r, sl = (1.0 - s) + r;
  return scale2(s + (sl + (expm1_rest(r) + (rl + r * rl))), static_cast<int>(k));
}

double expm1(double x) {
  if (x != x) return x + x;
  if (x > kExpMax) return kInf;
  if (x < -40.0) return -1.0;  // e^x < 2^-57: -1 to the bit
  if (std::fabs(x) < 0x1p-54) return x;
  // why: below 0.75 the series alone; reduced by k ln 2 there, e^x - 1 would be a difference of
  // two numbers of nearly equal size, and lose bits
  double k = 0.0;
  const double r = std::fabs(x) < 0.75 ? x : reduce_ln2(x, k);
  const double em1 = r + expm1_rest(r);  // e^r - 1
  if (k == 0.0) return em1;
  const int ki = static_cast<int>(k);
  if (ki > 56) return scale2(1.0 + em1, ki) - 1.0;  // the 1 is below the last bit
  // e^x - 1 = 2^k (e^r - 1) + (2^k - 1), both terms exact
  return scale2(em1, ki) + (scale2(1.0, ki) - 1.0);
}

double log(double x) {
  if (x != x) return x + x;
  if (x < 0.0) return kNaN;
  if (x == 0.0) return -kInf;
  if (x == kInf) return x;
  double hi, lo;
  log_parts(x, hi, lo);
  return hi + lo;
}

double log1p(double x) {
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

double pow(double x, double y) {
  if (y == 0.0 || x == 1.0) return 1.0;
  if (x != x || y != y) return x + y;
  const double ax = std::fabs(x);
  if (std::fabs(y) == kInf) {
    if (ax == 1.0) return 1.0;
    return (ax < 1.0) == (y < 0.0) ? kInf : 0.0;
  }
  const bool odd = is_odd(y);
  if (x == 0.0 || ax == kInf) {
    // 0^y and inf^y: 0 or inf, with x's sign for an odd integer y
    const bool big = (x == 0.0) == (y < 0.0);
    const double v = big ? kInf : 0.0;
    return odd && std::signbit(x) ? -v : v;
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
    const double e = exp(z);
    v = e + e * zl;  // e^(z + zl) = e^z (1 + zl), |zl| < 2^-52 |z|
  }
  return x < 0.0 && odd ? -v : v;
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
    v = log1p(a + a2 / (1.0 + std::sqrt(a2 + 1.0)));
  }
  return std::copysign(v, x);
}

}  // namespace plumetrace::math
