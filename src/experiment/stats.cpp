#include "plumetrace/experiment/stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/rng.hpp"

namespace plumetrace {

namespace {

// Continued fraction of the incomplete beta function (modified Lentz; Numerical Recipes 6.4).
double beta_continued_fraction(double x, double a, double b) {
  constexpr double kTiny = 1e-300;
  constexpr double kEps = 1e-16;
  const double qab = a + b, qap = a + 1.0, qam = a - 1.0;
  double c = 1.0;
  double d = 1.0 - qab * x / qap;
  if (std::fabs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double h = d;
  // why: the fraction needs O(sqrt(max(a, b))) terms; the cap only guards against NaN input
  for (int m = 1; m <= 100000; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
    d = 1.0 + aa * d;
    if (std::fabs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
    d = 1.0 + aa * d;
    if (std::fabs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::fabs(del - 1.0) < kEps) break;
  }
  return h;
}

// I_x(a, b) given both x and y = 1 - x, so that callers can pass a y free of cancellation.
double incomplete_beta(double x, double y, double a, double b) {
  if (x <= 0.0) return 0.0;
  if (y <= 0.0) return 1.0;
  const double log_front =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log(y);
  const double front = std::exp(log_front);
  // the fraction converges fast on the side of the mean; use the symmetry on the other
  if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_continued_fraction(x, a, b) / a;
  return 1.0 - front * beta_continued_fraction(y, b, a) / b;
}

// P(T > t) for t >= 0.
double student_t_upper_tail(double t, double dof) {
  const double t2 = t * t;
  return 0.5 * incomplete_beta(dof / (dof + t2), t2 / (dof + t2), 0.5 * dof, 0.5);
}

double student_t_pdf(double t, double dof) {
  return std::exp(std::lgamma(0.5 * (dof + 1.0)) - std::lgamma(0.5 * dof) -
                  0.5 * std::log(dof * kPi) - 0.5 * (dof + 1.0) * std::log1p(t * t / dof));
}

// Quantile for p < 0.5 (Acklam's rational approximation, then one Halley step on erfc).
double normal_lower_quantile(double p) {
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                 -2.759285104469687e+02, 1.383577518672690e+02,
                                 -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                 -1.556989798598866e+02, 6.680131188771972e+01,
                                 -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                 -2.400758277161838e+00, -2.549732539343734e+00,
                                 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                 2.445134137142996e+00, 3.754408661907416e+00};
  double x;
  if (p < 0.02425) {
    const double q = std::sqrt(-2.0 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else {
    const double q = p - 0.5;
    const double r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  }
  // why: the approximation has a relative error of 1.2e-9; one Halley step on the exact CDF
  // brings it to double precision
  const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - p;
  const double u = e * std::sqrt(2.0 * kPi) * std::exp(0.5 * x * x);
  return x - u / (1.0 + 0.5 * x * u);
}

// t quantile for large dof: the Cornish-Fisher expansion (Abramowitz & Stegun 26.7.5).
double student_t_quantile_expansion(double p, double dof) {
  const double z = normal_quantile(p);
  const double z2 = z * z;
  const double g1 = (z2 + 1.0) * z / 4.0;
  const double g2 = ((5.0 * z2 + 16.0) * z2 + 3.0) * z / 96.0;
  const double g3 = (((3.0 * z2 + 19.0) * z2 + 17.0) * z2 - 15.0) * z / 384.0;
  const double g4 =
      ((((79.0 * z2 + 776.0) * z2 + 1482.0) * z2 - 1920.0) * z2 - 945.0) * z / 92160.0;
  return z + (g1 + (g2 + (g3 + g4 / dof) / dof) / dof) / dof;
}

// why: above this the expansion's first omitted term is below 1e-15 for |z| < 8, while the
// incomplete beta's log-gamma prefactor loses digits to cancellation (1e-10 at 6e4 dof)
constexpr double kExpansionDof = 1e4;

}  // namespace

double regularized_beta(double x, double a, double b) {
  if (!(x >= 0.0 && x <= 1.0 && a > 0.0 && b > 0.0)) return NAN;
  return incomplete_beta(x, 1.0 - x, a, b);
}

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) return NAN;
  if (p > 0.5) return -normal_lower_quantile(1.0 - p);  // 1 - p is exact for p in [0.5, 1]
  return normal_lower_quantile(p);
}

double student_t_cdf(double t, double dof) {
  if (!(dof > 0.0) || std::isnan(t)) return NAN;
  if (std::isinf(t)) return t > 0 ? 1.0 : 0.0;
  const double tail = student_t_upper_tail(std::fabs(t), dof);
  return t > 0.0 ? 1.0 - tail : tail;
}

double student_t_quantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0) || !(dof > 0.0)) return NAN;
  if (p == 0.5) return 0.0;
  if (dof > kExpansionDof) return student_t_quantile_expansion(p, dof);

  // solve P(T > t) = q for t > 0 and give it the sign of p - 1/2
  const double q = p < 0.5 ? p : 1.0 - p;
  const double sign = p < 0.5 ? -1.0 : 1.0;

  // bracket [lo, hi] with tail(lo) > q >= tail(hi)
  double lo = 0.0;
  double hi = std::max(1.0, -2.0 * normal_lower_quantile(q));
  while (student_t_upper_tail(hi, dof) > q) {
    lo = hi;
    hi *= 2.0;
    if (!std::isfinite(hi)) return sign * std::numeric_limits<double>::infinity();
  }

  // Newton on the tail, kept inside the bracket (bisection when a step leaves it)
  const double z = -normal_lower_quantile(q);
  double t = std::clamp(z + (z * z + 1.0) * z / (4.0 * dof), lo, hi);
  for (int i = 0; i < 400; ++i) {
    const double f = student_t_upper_tail(t, dof) - q;
    if (f == 0.0) break;
    if (f > 0.0) {
      lo = t;
    } else {
      hi = t;
    }
    double next = t + f / student_t_pdf(t, dof);
    if (!(next > lo && next < hi)) {
      // why: with one degree of freedom the bracket can span hundreds of octaves; halve it in
      // the logarithm then
      next = (lo > 0.0 && hi > 16.0 * lo) ? std::sqrt(lo * hi) : 0.5 * (lo + hi);
    }
    if (std::fabs(next - t) <= 4.0 * std::numeric_limits<double>::epsilon() * next) {
      t = next;
      break;
    }
    t = next;
  }
  return sign * t;
}

Interval wilson_interval(std::int64_t successes, std::int64_t n, double z) {
  if (n <= 0) return {0.0, 1.0};
  const double nn = static_cast<double>(n);
  const double p = static_cast<double>(successes) / nn;
  const double z2 = z * z;
  const double denom = 1.0 + z2 / nn;
  const double centre = (p + z2 / (2.0 * nn)) / denom;
  const double half = z * std::sqrt(p * (1.0 - p) / nn + z2 / (4.0 * nn * nn)) / denom;
  // why: at 0 or n the interval touches the boundary exactly; rounding must not move it off
  const double lo = successes <= 0 ? 0.0 : std::max(0.0, centre - half);
  const double hi = successes >= n ? 1.0 : std::min(1.0, centre + half);
  return {lo, hi};
}

Interval newcombe_difference(std::int64_t successes1, std::int64_t n1, std::int64_t successes2,
                             std::int64_t n2, double z) {
  if (n1 <= 0 || n2 <= 0) return {};
  const double p1 = static_cast<double>(successes1) / static_cast<double>(n1);
  const double p2 = static_cast<double>(successes2) / static_cast<double>(n2);
  const Interval w1 = wilson_interval(successes1, n1, z);
  const Interval w2 = wilson_interval(successes2, n2, z);
  const double delta = p1 - p2;
  const double lo = delta - std::hypot(p1 - w1.lo, w2.hi - p2);
  const double hi = delta + std::hypot(w1.hi - p1, p2 - w2.lo);
  return {std::max(-1.0, lo), std::min(1.0, hi)};
}

namespace {

// fills the standard deviation and the t interval from the sum of squared deviations
MeanCi with_t_interval(MeanCi out, double ss, double level) {
  out.stddev = std::sqrt(ss / static_cast<double>(out.n - 1));
  const double t = student_t_quantile(0.5 * (1.0 + level), static_cast<double>(out.n - 1));
  const double half = t * out.stddev / std::sqrt(static_cast<double>(out.n));
  out.lo = out.mean - half;
  out.hi = out.mean + half;
  return out;
}

}  // namespace

MeanCi mean_ci(std::span<const double> values, double level) {
  MeanCi out;
  double sum = 0.0;
  for (double v : values) {
    if (std::isnan(v)) continue;
    sum += v;
    ++out.n;
  }
  if (out.n == 0) return out;
  out.mean = sum / static_cast<double>(out.n);
  if (out.n == 1) return out;
  double ss = 0.0;
  for (double v : values) {
    if (!std::isnan(v)) ss += (v - out.mean) * (v - out.mean);
  }
  return with_t_interval(out, ss, level);
}

MeanCi pooled_mean_ci(std::span<const MeanCi> parts, double level) {
  MeanCi out;
  double sum = 0.0;
  for (const MeanCi& part : parts) {
    if (part.n <= 0 || std::isnan(part.mean)) continue;
    out.n += part.n;
    sum += static_cast<double>(part.n) * part.mean;
  }
  if (out.n == 0) return out;
  out.mean = sum / static_cast<double>(out.n);
  if (out.n == 1) return out;
  // total sum of squares = within parts + between parts
  double ss = 0.0;
  for (const MeanCi& part : parts) {
    if (part.n <= 0 || std::isnan(part.mean)) continue;
    const double nn = static_cast<double>(part.n);
    if (part.n >= 2) ss += (nn - 1.0) * part.stddev * part.stddev;
    ss += nn * (part.mean - out.mean) * (part.mean - out.mean);
  }
  return with_t_interval(out, ss, level);
}

Interval welch_difference(const MeanCi& a, const MeanCi& b, double level) {
  if (a.n < 2 || b.n < 2 || std::isnan(a.stddev) || std::isnan(b.stddev)) return {};
  const double va = a.stddev * a.stddev / static_cast<double>(a.n);
  const double vb = b.stddev * b.stddev / static_cast<double>(b.n);
  const double diff = a.mean - b.mean;
  const double se2 = va + vb;
  if (se2 == 0.0) return {diff, diff};
  // Welch-Satterthwaite degrees of freedom
  const double dof =
      se2 * se2 / (va * va / static_cast<double>(a.n - 1) + vb * vb / static_cast<double>(b.n - 1));
  const double half = student_t_quantile(0.5 * (1.0 + level), dof) * std::sqrt(se2);
  return {diff - half, diff + half};
}

Quartiles quartiles(std::vector<double> values) {
  std::erase_if(values, [](double v) { return std::isnan(v); });
  if (values.empty()) return {};
  std::sort(values.begin(), values.end());
  const auto at = [&values](double q) {
    const double h = q * static_cast<double>(values.size() - 1);
    const auto i = static_cast<std::size_t>(std::floor(h));
    if (i + 1 >= values.size()) return values.back();
    return values[i] + (h - static_cast<double>(i)) * (values[i + 1] - values[i]);
  };
  return {at(0.25), at(0.5), at(0.75)};
}

Interval bootstrap_mean_interval(std::span<const double> values, double level, int resamples,
                                 std::uint64_t seed) {
  std::vector<double> sample;
  for (const double v : values) {
    if (!std::isnan(v)) sample.push_back(v);
  }
  if (sample.size() < 2 || resamples < 1) return {};
  Rng rng(seed);
  const auto n = static_cast<std::uint64_t>(sample.size());
  std::vector<double> means(static_cast<std::size_t>(resamples));
  for (double& mean : means) {
    double sum = 0.0;
    for (std::uint64_t k = 0; k < n; ++k) {
      // why: 53 uniform bits scaled to [0, n): a bias of n / 2^53, far below anything visible
      const auto pick = static_cast<std::size_t>(rng.uniform() * static_cast<double>(n));
      sum += sample[std::min(pick, sample.size() - 1)];
    }
    mean = sum / static_cast<double>(n);
  }
  std::sort(means.begin(), means.end());
  const auto at = [&means](double q) {
    const double h = q * static_cast<double>(means.size() - 1);
    const auto i = static_cast<std::size_t>(std::floor(h));
    if (i + 1 >= means.size()) return means.back();
    return means[i] + (h - static_cast<double>(i)) * (means[i + 1] - means[i]);
  };
  return {at((1.0 - level) / 2.0), at((1.0 + level) / 2.0)};
}

PointStats summarize(std::span<const RunResult> runs) {
  PointStats out;
  out.runs = static_cast<std::int64_t>(runs.size());
  std::vector<double> overheads;
  double time_all = 0.0, time_success = 0.0, losses = 0.0;
  for (const RunResult& r : runs) {
    switch (r.outcome) {
      case Outcome::kSuccess:
        ++out.successes;
        time_success += r.time;
        overheads.push_back(r.overhead);
        break;
      case Outcome::kWall:
        ++out.walls;
        break;
      case Outcome::kTimeout:
        ++out.timeouts;
        break;
      case Outcome::kGaveUp:
        ++out.gave_up;
        break;
      case Outcome::kWrongDeclaration:
        ++out.wrong_declarations;
        break;
      case Outcome::kRunning:
        break;
    }
    time_all += r.time;
    losses += r.losses;
  }
  out.success_ci = wilson_interval(out.successes, out.runs);
  if (out.runs > 0) {
    const double n = static_cast<double>(out.runs);
    out.success_rate = static_cast<double>(out.successes) / n;
    out.mean_time = time_all / n;
    out.mean_losses = losses / n;
  }
  if (out.successes > 0) out.mean_time_success = time_success / static_cast<double>(out.successes);
  out.overhead = mean_ci(overheads);
  out.overhead_bootstrap = bootstrap_mean_interval(overheads);
  out.overhead_quartiles = quartiles(std::move(overheads));
  return out;
}

}  // namespace plumetrace
