// The wind fields: the meandering wind of Farrell et al. (2002) (MeanderWind), its coloured
// boundary noise, its grid and interpolation, and how the plume and the sensors read it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "env/wind_loops.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/simd.hpp"
#include "plumetrace/env/environment.hpp"
#include "plumetrace/env/filament_plume.hpp"
#include "plumetrace/env/meander_wind.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/trace.hpp"
#include "plumetrace/sim/world.hpp"
#include "support/loop_checks.hpp"
#include "support/shared_runs.hpp"

namespace plumetrace {
namespace {

constexpr double kDt = 0.032;  // the default sim.dt

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

// the mean and the standard error of the mean of independent estimates
struct Estimate {
  double mean, error;
};

Estimate estimate(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m += x;
  m /= static_cast<double>(v.size());
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  const double sd = std::sqrt(s / static_cast<double>(v.size() - 1));
  return {m, sd / std::sqrt(static_cast<double>(v.size()))};
}

// expects an estimate within 4 standard errors of the expected value, and prints both
void expect_within_4_sigma(const Estimate& e, double expected, const char* what) {
  std::printf("[ measured ] %s: %.6g +- %.2g (expected %.6g, %.2f sigma)\n", what, e.mean, e.error,
              expected, (e.mean - expected) / e.error);
  EXPECT_LE(std::abs(e.mean - expected), 4.0 * e.error) << what;
}

// the default scenario in the meandering wind
Scenario meander_scenario() {
  Scenario s;
  s.wind.model = WindModel::kMeander;
  validate(s);
  return s;
}

MeanderWind make_meander(const Scenario& s, std::uint64_t seed) {
  return MeanderWind(s.wind.get<MeanderParams>(), s.wind.velocity, wind_region(s.arena), Rng(seed));
}

// --- the boundary noise -----------------------------------------------------------------------

const ColouredNoiseParams kRegimes[] = {
    {1.0, 0.5, 2.0},     // underdamped
    {1.0, 1.0, 2.0},     // critically damped
    {1.0, 3.0, 2.0},     // overdamped
    {1.0, 0.071, 0.71},  // Farrell et al.'s small-amplitude meander
    {1.0, 0.1, 0.2},     // Farrell et al.'s large-amplitude meander
};

using Matrix = std::array<std::array<double, 2>, 2>;

Matrix product(const Matrix& a, const Matrix& b) {
  Matrix c{};
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j];
  }
  return c;
}

Matrix transpose(const Matrix& a) { return {{{a[0][0], a[1][0]}, {a[0][1], a[1][1]}}}; }

Matrix phi_of(const ColouredNoiseTransition& t) {
  return {{{t.phi[0][0], t.phi[0][1]}, {t.phi[1][0], t.phi[1][1]}}};
}

// the covariance a step adds, L L^T
Matrix added_of(const ColouredNoiseTransition& t) {
  return {{{t.l11 * t.l11, t.l11 * t.l21}, {t.l11 * t.l21, t.l21 * t.l21 + t.l22 * t.l22}}};
}

TEST(ColouredNoise, TheStepIsTheExactSolutionOfTheFilter) {
  for (const ColouredNoiseParams& p : kRegimes) {
    const double p11 = coloured_noise_variance(p), p22 = coloured_noise_rate_variance(p);
    for (const double dt : {kDt, 0.5, 3.0}) {
      const auto one = coloured_noise_transition(p, dt), two = coloured_noise_transition(p, 2 * dt);
      const Matrix phi = phi_of(one), q = added_of(one);
      // two steps of dt are one of 2 dt: phi(2 dt) = phi^2, Q(2 dt) = phi Q phi^T + Q
      const Matrix phi2 = product(phi, phi);
      const Matrix q2 = product(product(phi, q), transpose(phi));
      for (int i = 0; i < 2; ++i) {
        for (int j = 0; j < 2; ++j) {
          EXPECT_NEAR(phi_of(two)[i][j], phi2[i][j], 1e-12 * (1.0 + std::abs(phi2[i][j])));
          const double scale = i + j == 0 ? p11 : i + j == 1 ? std::sqrt(p11 * p22) : p22;
          EXPECT_NEAR(added_of(two)[i][j], q2[i][j] + q[i][j], 1e-10 * scale)
              << "zeta " << p.damping << " dt " << dt;
        }
      }
      // the stationary law is kept: P = phi P phi^T + Q
      const Matrix kept = product(product(phi, Matrix{{{p11, 0.0}, {0.0, p22}}}), transpose(phi));
      EXPECT_NEAR(kept[0][0] + q[0][0], p11, 1e-10 * p11);
      EXPECT_NEAR(kept[0][1] + q[0][1], 0.0, 1e-10 * std::sqrt(p11 * p22));
      EXPECT_NEAR(kept[1][1] + q[1][1], p22, 1e-10 * p22);
    }
    // phi(0) = I, so the autocorrelation starts at 1; the time scale is its integral
    EXPECT_DOUBLE_EQ(coloured_noise_correlation(p, 0.0), 1.0);
    // over 40 times the slowest decay time: 1 / (zeta omega), or the overdamped slow mode's
    const double slowest = p.damping > 1.0
                               ? p.bandwidth * (p.damping - std::sqrt(p.damping * p.damping - 1.0))
                               : p.damping * p.bandwidth;
    double integral = 0.0;
    const double h = 1e-3;
    for (double t = 0.0; t < 40.0 / slowest; t += h) {
      integral +=
          0.5 * h * (coloured_noise_correlation(p, t) + coloured_noise_correlation(p, t + h));
    }
    EXPECT_NEAR(integral, coloured_noise_time_scale(p), 1e-4 * coloured_noise_time_scale(p) + 1e-6);
  }
}

TEST(ColouredNoise, ZeroGainStaysExactlyZero) {
  const ColouredNoiseParams p{0.0, 0.1, 0.2};
  Rng rng(3);
  ColouredNoiseState s = stationary_coloured_noise(p, rng);
  const auto t = coloured_noise_transition(p, kDt);
  for (int i = 0; i < 1000; ++i) step(t, s, rng);
  EXPECT_EQ(s.value, 0.0);
  EXPECT_EQ(s.rate, 0.0);
}

// The stationary variance G^2 omega / (4 zeta) and the integral time scale 2 zeta / omega, from
// 16 independent series of 3200 s each; the standard error is that of the 16 estimates.
TEST(ColouredNoise, VarianceAndTimeScaleMatchTheAnalyticValuesWithin4Sigma) {
  const ColouredNoiseParams p{1.3, 0.5, 2.0};
  const auto t = coloured_noise_transition(p, kDt);
  const std::size_t n = 100000;
  // lags up to 12 decay times of the envelope, e^-12
  const auto lags = static_cast<std::size_t>(std::ceil(12.0 / (p.damping * p.bandwidth * kDt)));
  // the time scale as estimated (trapezoid rule over the lags) for the exact autocorrelation
  double expected_scale = 0.5 * kDt;
  for (std::size_t k = 1; k <= lags; ++k) {
    expected_scale += kDt * coloured_noise_correlation(p, static_cast<double>(k) * kDt);
  }
  EXPECT_NEAR(expected_scale, coloured_noise_time_scale(p), 1e-4);
  std::vector<double> means, variances, scales;
  for (std::uint64_t seed = 1; seed <= 16; ++seed) {
    Rng rng(seed);
    ColouredNoiseState s = stationary_coloured_noise(p, rng);
    std::vector<double> x(n);
    for (double& v : x) {
      step(t, s, rng);
      v = s.value;
    }
    double sum = 0.0, c0 = 0.0;
    for (double v : x) {
      sum += v;
      c0 += v * v;
    }
    c0 /= static_cast<double>(n);
    double scale = 0.5 * kDt;
    for (std::size_t k = 1; k <= lags; ++k) {
      double c = 0.0;
      for (std::size_t i = 0; i + k < n; ++i) c += x[i] * x[i + k];
      scale += kDt * c / static_cast<double>(n - k) / c0;
    }
    means.push_back(sum / static_cast<double>(n));
    variances.push_back(c0);
    scales.push_back(scale);
  }
  expect_within_4_sigma(estimate(means), 0.0, "coloured noise mean (m/s)");
  expect_within_4_sigma(estimate(variances), coloured_noise_variance(p),
                        "coloured noise variance G^2 omega / (4 zeta) ((m/s)^2)");
  expect_within_4_sigma(estimate(scales), expected_scale,
                        "coloured noise integral time scale 2 zeta / omega (s)");
}

// --- the meandering wind ----------------------------------------------------------------------

// The grid's corners are the mean wind plus the boundary noise: its variance and its
// autocorrelation at three lags, from 24 independent series of 1500 s each, in the
// small-amplitude meander of Farrell et al. (damping 0.071, bandwidth 0.71 rad/s).
TEST(MeanderWind, CornersHaveTheNoisesVarianceAndCorrelationWithin4Sigma) {
  Scenario s = meander_scenario();
  s.wind.get<MeanderParams>() = {.gain = 0.2, .damping = 0.071, .bandwidth = 0.71};
  const ColouredNoiseParams p{0.2, 0.071, 0.71};
  const std::size_t n = 46875;
  const std::size_t lags[] = {31, 94, 156};  // 1, 3 and 5 s
  const Vec3 corner{s.arena.x_min, s.arena.y_min, 0.0}, far{s.arena.x_max, s.arena.y_max, 0.0};
  std::vector<double> variances, far_variances, correlations[3];
  for (std::uint64_t seed = 1; seed <= 24; ++seed) {
    MeanderWind wind = make_meander(s, seed);
    std::vector<double> v(n);
    double far_c0 = 0.0;
    for (double& x : v) {
      wind.step(kDt);
      x = wind.velocity(corner).y - s.wind.velocity.y;
      const double w = wind.velocity(far).x - s.wind.velocity.x;
      far_c0 += w * w;
    }
    double c0 = 0.0;
    for (double x : v) c0 += x * x;
    c0 /= static_cast<double>(n);
    variances.push_back(c0);
    far_variances.push_back(far_c0 / static_cast<double>(n));
    for (int l = 0; l < 3; ++l) {
      double c = 0.0;
      for (std::size_t i = 0; i + lags[l] < n; ++i) c += v[i] * v[i + lags[l]];
      correlations[l].push_back(c / static_cast<double>(n - lags[l]) / c0);
    }
  }
  expect_within_4_sigma(estimate(variances), coloured_noise_variance(p),
                        "corner (x_min, y_min) v variance ((m/s)^2)");
  expect_within_4_sigma(estimate(far_variances), coloured_noise_variance(p),
                        "corner (x_max, y_max) u variance ((m/s)^2)");
  const char* names[] = {"corner v autocorrelation at 0.992 s",
                         "corner v autocorrelation at 3.008 s",
                         "corner v autocorrelation at 4.992 s"};
  for (int l = 0; l < 3; ++l) {
    expect_within_4_sigma(estimate(correlations[l]),
                          coloured_noise_correlation(p, static_cast<double>(lags[l]) * kDt),
                          names[l]);
  }
}

// The time mean of the grid is the mean wind: u and v averaged over the inside nodes and at the
// robot's start, 48 independent series of 1000 s each, in the default (large-amplitude) meander.
// (The standard error of one series' mean is about G / sqrt(T) per corner, the noise's spectrum
// at zero frequency: 0.14 / sqrt(1000 s) = 4.4 mm/s.)
TEST(MeanderWind, TheGridsTimeMeanIsTheMeanWindWithin4Sigma) {
  Scenario s = meander_scenario();
  s.wind.velocity = {0.9, 0.05, 0.0};
  const std::size_t n = 31250;
  const Vec3 start{s.robot.start.x, s.robot.start.y, 0.0};
  std::vector<double> us, vs, start_us, start_vs;
  for (std::uint64_t seed = 1; seed <= 48; ++seed) {
    MeanderWind wind = make_meander(s, seed);
    double u = 0.0, v = 0.0, su = 0.0, sv = 0.0;
    long nodes = 0;
    for (std::size_t k = 0; k < n; ++k) {
      wind.step(kDt);
      for (int j = 1; j + 1 < wind.ny(); ++j) {
        for (int i = 1; i + 1 < wind.nx(); ++i) {
          u += wind.u(i, j);
          v += wind.v(i, j);
          ++nodes;
        }
      }
      const Vec3 a = wind.velocity(start);
      su += a.x;
      sv += a.y;
    }
    us.push_back(u / static_cast<double>(nodes));
    vs.push_back(v / static_cast<double>(nodes));
    start_us.push_back(su / static_cast<double>(n));
    start_vs.push_back(sv / static_cast<double>(n));
  }
  expect_within_4_sigma(estimate(us), s.wind.velocity.x, "inside nodes' time-mean u (m/s)");
  expect_within_4_sigma(estimate(vs), s.wind.velocity.y, "inside nodes' time-mean v (m/s)");
  expect_within_4_sigma(estimate(start_us), s.wind.velocity.x, "time-mean u at the start (m/s)");
  expect_within_4_sigma(estimate(start_vs), s.wind.velocity.y, "time-mean v at the start (m/s)");
}

// Taylor (1921): a passive tracer whose lateral velocity v(t) has variance sigma_v^2 and
// autocorrelation R(tau) spreads as sigma_y^2(t) = 2 sigma_v^2 int_0^t (t - tau) R(tau) dtau, which
// grows as sigma_v^2 t^2 at first and as 2 sigma_v^2 T_L t once t >> T_L = int_0^inf R. Tracers
// are moved by the field's own advect() (the filaments' path) and their velocity sampled along
// the way: 2000 tracers, 5 in each of 400 independent fields (one every 19 s, after 30 s of
// spin-up), each released at x = 4 m on the centreline and followed for 8 m (8.9 s) through the
// middle of the arena. The boundary noise is made short (damping 1, bandwidth 2 rad/s: its own
// time scale 1 s) so that the path spans several T_L.
// The field is not homogeneous, as the theorem assumes: the variance of v is larger near the
// arena's edges, and varies by about +-10 % along the path, so the prediction takes the variance
// where the tracer is, with one stationary R. Tolerance: 10 % on sigma_y^2 at every time and on
// the long-time slope against 2 sigma_v^2 T_L (the 2000 tracers give sigma_y^2 to about 3 %, one
// standard error).
TEST(MeanderWind, ATracersSpreadGrowsAsTaylorsTheoremPredicts) {
  Scenario s = meander_scenario();
  MeanderParams& m = s.wind.get<MeanderParams>();
  m.gain = 0.3;
  m.damping = 1.0;
  m.bandwidth = 2.0;
  validate(s);
  const double x0 = s.arena.x_min + 4.0;
  const auto n = static_cast<std::size_t>(8.0 / s.wind.velocity.x / kDt);
  std::vector<std::vector<double>> paths;  // v along each tracer's path (m/s)
  std::vector<double> spread(n, 0.0);      // sum of y^2 over tracers, per step (m^2)
  for (std::uint64_t seed = 1; seed <= 400; ++seed) {
    MeanderWind wind = make_meander(s, seed);
    for (int k = 0; k < static_cast<int>(30.0 / kDt); ++k) wind.step(kDt);
    for (int tracer = 0; tracer < 5; ++tracer) {
      std::array<double, 1> x{x0}, y{0.0}, z{0.0};
      std::vector<double> v(n);
      for (std::size_t k = 0; k < n; ++k) {
        wind.step(kDt);
        v[k] = wind.velocity({x[0], y[0], z[0]}).y;
        wind.advect(x, y, z, kDt);
        spread[k] += y[0] * y[0];
      }
      paths.push_back(std::move(v));
      for (int k = 0; k < static_cast<int>(10.0 / kDt); ++k) wind.step(kDt);
    }
  }
  // the variance of v at each step along the path, and the Lagrangian autocorrelation R(lag) of
  // v normalised by it, averaged over the path and the tracers
  const double tracers = static_cast<double>(paths.size());
  std::vector<double> sd(n, 0.0), r(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    for (const auto& v : paths) sd[k] += v[k] * v[k];
    sd[k] = std::sqrt(sd[k] / tracers);
  }
  for (std::size_t lag = 0; lag < n; ++lag) {
    double sum = 0.0;
    for (const auto& v : paths) {
      for (std::size_t i = 0; i + lag < n; ++i) sum += v[i] * v[i + lag] / (sd[i] * sd[i + lag]);
    }
    r[lag] = sum / (tracers * static_cast<double>(n - lag));
  }
  double variance = 0.0, lowest = sd[0], highest = sd[0];
  for (double x : sd) {
    variance += x * x / static_cast<double>(n);
    lowest = std::min(lowest, x);
    highest = std::max(highest, x);
  }
  double time_scale = 0.5 * kDt;  // T_L, trapezoid rule over the path
  for (std::size_t lag = 1; lag < n; ++lag) time_scale += kDt * r[lag];
  std::printf(
      "[ measured ] tracer v: variance %.5g (m/s)^2 (from %.4g to %.4g along the path), integral "
      "time scale T_L %.3f s\n",
      variance, lowest * lowest, highest * highest, time_scale);
  // Taylor's theorem in steps: y_k = dt sum_{i<=k} v_i, so
  // sigma_y^2 = dt^2 sum_{i,j<=k} sigma_i sigma_j R(|i - j|), with the variance where the tracer is
  // (it varies along the path by +-10 %: the field is not homogeneous, which the theorem assumes)
  auto taylor = [&](std::size_t m) {
    double sum = 0.0;
    for (std::size_t i = 0; i < m; ++i) {
      for (std::size_t j = 0; j < m; ++j) sum += sd[i] * sd[j] * r[i > j ? i - j : j - i];
    }
    return kDt * kDt * sum;
  };
  for (std::size_t k = 15; k < n; k += 31) {
    const double measured = spread[k] / tracers, predicted = taylor(k + 1);
    std::printf("[ measured ] t = %5.2f s: sigma_y^2 %.4g m^2, Taylor %.4g m^2 (ratio %.3f)\n",
                static_cast<double>(k + 1) * kDt, measured, predicted, measured / predicted);
    EXPECT_NEAR(measured / predicted, 1.0, 0.10) << "t = " << static_cast<double>(k + 1) * kDt;
  }
  // once t >> T_L the spread grows linearly, at 2 sigma_v^2 T_L
  const std::size_t late = n - 1, early = n - 1 - static_cast<std::size_t>(3.0 / kDt);
  const double slope =
      (spread[late] - spread[early]) / tracers / (static_cast<double>(late - early) * kDt);
  std::printf("[ measured ] late slope of sigma_y^2 %.4g m^2/s, 2 sigma_v^2 T_L %.4g m^2/s\n",
              slope, 2.0 * variance * time_scale);
  EXPECT_GT((late - early) * kDt, 2.0 * time_scale);
  EXPECT_NEAR(slope / (2.0 * variance * time_scale), 1.0, 0.10);
}

TEST(MeanderWind, ZeroGainIsTheMeanWindBitForBit) {
  Scenario s = meander_scenario();
  s.wind.get<MeanderParams>().gain = 0.0;
  s.wind.velocity = {0.9, -0.1, 0.01};
  MeanderWind wind = make_meander(s, 5);
  EXPECT_TRUE(wind.uniform_in_space());
  Rng rng(1);
  for (int k = 0; k < 300; ++k) {
    wind.step(kDt);
    const Vec3 p{-1.0 + 18.0 * rng.uniform(), -3.0 + 6.0 * rng.uniform(), rng.uniform()};
    const Vec3 a = wind.velocity(p);
    ASSERT_EQ(bits(a.x), bits(0.9));
    ASSERT_EQ(bits(a.y), bits(-0.1));
    ASSERT_EQ(bits(a.z), bits(0.01));
  }
  s.wind.get<MeanderParams>().gain = 1e-9;
  EXPECT_FALSE(make_meander(s, 5).uniform_in_space());
}

// what a run records, every step and every filament snapshot, as bits
std::vector<std::uint64_t> run_bits(const Scenario& s, std::uint64_t trial) {
  Trace trace;
  TraceRecorder recorder(trace, 2.0, s.sim.dt);
  const RunResult r = run_once(s, 20080101, trial, [&](const World& w) { recorder(w); });
  std::vector<std::uint64_t> out;
  RunResult::fields(r, [&](const ResultField&, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    if constexpr (std::is_floating_point_v<T>) {
      out.push_back(bits(static_cast<double>(value)));
    } else {
      out.push_back(static_cast<std::uint64_t>(value));
    }
  });
  for (const TraceStep& t : trace.agents.front().steps) {
    for (double v : {t.time, t.pose.x, t.pose.y, t.pose.heading, t.odometer, t.concentration,
                     t.wind_body.x, t.wind_body.y, t.wind_body.z}) {
      out.push_back(bits(v));
    }
    out.push_back(std::hash<std::string>{}(t.state));
    out.push_back(static_cast<std::uint64_t>(t.odor) +
                  2 * static_cast<std::uint64_t>(t.wind_samples));
  }
  for (const FilamentSnapshot& f : trace.snapshots) {
    for (const auto* v : {&f.x, &f.y, &f.z, &f.w}) {
      for (double x : *v) out.push_back(bits(x));
    }
  }
  return out;
}

TEST(MeanderWind, ZeroGainRunsAreTheConstantWindsBitForBit) {
  for (Algorithm algorithm : all_algorithms()) {
    Scenario laminar;
    laminar.controller.algorithm = algorithm;
    laminar.supervisor.timeout = 150.0;
    Scenario meander = laminar;
    meander.wind.model = WindModel::kMeander;
    meander.wind.get<MeanderParams>().gain = 0.0;
    validate(meander);
    for (std::uint64_t trial : {0u, 1u}) {
      const auto a = run_bits(laminar, trial), b = run_bits(meander, trial);
      ASSERT_GT(a.size(), 1000u);
      EXPECT_TRUE(a == b) << algorithm_name(algorithm) << " trial " << trial;
    }
  }
}

// runs of points in one cell, across an edge, in several cells, on nodes and edges, outside the
// arena, and a NaN, in blocks of every alignment (tests/support/loop_checks.hpp; the 64-bit ARM
// build runs the same check, tests/bits)
TEST(MeanderWind, AdvectMovesEveryPointByVelocityTimesDtToTheBit) {
  EXPECT_EQ(testing::wind_advect_mismatch(), "");
}

// every path of the interpolation this machine runs (simd::available(): scalar, the baseline,
// AVX2, AVX-512) against the scalar formulas, point by point, on a random grid
TEST(MeanderWind, EveryInterpolationPathGivesTheScalarBits) {
  const int nx = 17, ny = 4;
  Rng rng(9);
  std::vector<double> coef(8 * (nx - 1) * (ny - 1));
  for (double& c : coef) c = rng.normal();
  const wind_loops::CellView g{0.0,      -2.0,   1.0,    0.75,   nx - 1.0,
                               ny - 1.0, nx - 1, nx - 2, ny - 2, coef.data()};
  std::vector<double> x, y, z;
  for (int k = 0; k < 4099; ++k) {
    const bool run = (k / 64) % 2 == 0;  // alternating runs of plume-like and scattered points
    x.push_back(run ? 1.0 + 14.0 * k / 4099.0 + 0.2 * rng.uniform() : -1.0 + 18.0 * rng.uniform());
    y.push_back(run ? -0.9 + 0.3 * rng.uniform() : -2.5 + 5.0 * rng.uniform());
    z.push_back(rng.uniform());
  }
  x[7] = std::numeric_limits<double>::quiet_NaN();
  y[100] = -0.0;
  x[101] = 16.0;
  y[102] = 1.0;
  std::vector<double> sx = x, sy = y, sz = z;
  for (std::size_t i = 0; i < x.size(); ++i) {
    int k;
    double tx, ty, u, v;
    wind_loops::locate(g, x[i], y[i], k, tx, ty);
    wind_loops::evaluate(wind_loops::cell_coef(g, k), tx, ty, u, v);
    sx[i] += u * kDt;
    sy[i] += v * kDt;
    sz[i] += 0.001;
  }
  std::string tested;
  for (const simd::Path path : simd::available()) {
    tested += ' ';
    tested += simd::name(path);
    for (std::int64_t first : {0, 1, 3}) {
      std::vector<double> vx = x, vy = y, vz = z;
      wind_loops::advect(path, g, vx.data(), vy.data(), vz.data(), first,
                         static_cast<std::int64_t>(x.size()), kDt, 0.001);
      for (std::size_t i = 0; i < x.size(); ++i) {
        const bool moved = static_cast<std::int64_t>(i) >= first;
        ASSERT_EQ(bits(vx[i]), bits(moved ? sx[i] : x[i])) << simd::name(path) << " " << i;
        ASSERT_EQ(bits(vy[i]), bits(moved ? sy[i] : y[i])) << simd::name(path) << " " << i;
        ASSERT_EQ(bits(vz[i]), bits(moved ? sz[i] : z[i])) << simd::name(path) << " " << i;
      }
    }
  }
  std::printf("[ measured ] interpolation paths compared on this machine:%s\n", tested.c_str());
}

TEST(MeanderWind, ARunIsAPureFunctionOfScenarioSeedAndTrial) {
  const Scenario s = meander_scenario();
  // the same seed twice: the same field, step after step
  MeanderWind a = make_meander(s, 42), b = make_meander(s, 42), c = make_meander(s, 43);
  bool differ = false;
  for (int k = 0; k < 500; ++k) {
    a.step(kDt);
    b.step(kDt);
    c.step(kDt);
    for (const Vec3& p : {Vec3{0.0, -2.0, 0.0}, Vec3{8.3, 0.4, 0.0}, Vec3{15.5, 0.0, 0.0}}) {
      ASSERT_EQ(bits(a.velocity(p).x), bits(b.velocity(p).x));
      ASSERT_EQ(bits(a.velocity(p).y), bits(b.velocity(p).y));
      differ = differ || bits(a.velocity(p).y) != bits(c.velocity(p).y);
    }
  }
  EXPECT_TRUE(differ);
  // the run's field is the one of its own stream, Stream::kWind
  Environment env = make_environment(s, 7, 3);
  MeanderWind own = make_meander(s, derive_seed(7, 3, Stream::kWind));
  for (int k = 0; k < 50; ++k) {
    step(env, kDt);
    own.step(kDt);
  }
  EXPECT_EQ(bits(env.wind->velocity({4.0, 0.3, 0.0}).y), bits(own.velocity({4.0, 0.3, 0.0}).y));
  // and the same run twice is the same run
  Scenario quick = s;
  quick.supervisor.timeout = 100.0;
  EXPECT_TRUE(run_bits(quick, 2) == run_bits(quick, 2));
}

TEST(MeanderWind, TheWindDrawsOnlyFromItsOwnStream) {
  Scenario s = meander_scenario();
  const auto plume_after = [&](std::unique_ptr<WindField> wind, int steps) {
    Environment env;
    env.wind = std::move(wind);
    env.odor = std::make_unique<FilamentPlume>(s.plume, s.source, s.arena.x_max, 77);
    for (int k = 0; k < steps; ++k) step(env, kDt);
    const FilamentSpans f = env.odor->snapshot().filaments;
    std::vector<std::uint64_t> out;
    for (const auto span : {f.x, f.y, f.z, f.w}) {
      for (double v : span) out.push_back(bits(v));
    }
    return out;
  };
  // zero gain: the filaments are those of the constant wind, whatever the wind's seed
  s.wind.get<MeanderParams>().gain = 0.0;
  const auto laminar = plume_after(std::make_unique<ConstantWind>(s.wind.velocity), 700);
  for (std::uint64_t seed : {1u, 2u, 999u}) {
    EXPECT_TRUE(plume_after(make_wind_field(s.wind, wind_context(s), Rng(seed)), 700) == laminar)
        << seed;
  }
  // with a gain the filaments move with the wind, but the plume's own draws (the release
  // positions, appended last) are the same whatever the wind's seed
  s.wind.get<MeanderParams>().gain = 0.3;
  const auto first = plume_after(make_wind_field(s.wind, wind_context(s), Rng(1)), 100);
  const auto second = plume_after(make_wind_field(s.wind, wind_context(s), Rng(2)), 100);
  ASSERT_EQ(first.size(), second.size());
  const std::size_t n = first.size() / 4;  // filaments; the last 4 were released in step 100
  EXPECT_NE(first[0], second[0]);          // the oldest moved in different winds
  for (std::size_t i = n - 3; i < n; ++i) {
    EXPECT_EQ(first[i], second[i]);          // x of a fresh release
    EXPECT_EQ(first[n + i], second[n + i]);  // y
  }
}

// Stands still and takes one wind sample per step (body frame).
class WindLogger final : public Controller {
 public:
  explicit WindLogger(std::vector<Vec2>& log) : log_(log) {}
  Command step(const Observation&, WindProbe& wind) override {
    log_.push_back(wind.measure_wind_body());
    return Command::stop();
  }
  std::string_view state() const override { return "logging"; }
  int losses() const override { return 0; }

 private:
  std::vector<Vec2>& log_;
};

TEST(MeanderWind, TheWindSensorReadsTheFieldThePlumeMovesIn) {
  Scenario s = meander_scenario();
  s.wind.get<MeanderParams>().gain = 0.3;  // a strong meander, so that neighbouring points differ
  s.sim.warmup = 1.0;
  s.plume.sigma_p = 0.0;  // filaments move by the wind alone
  s.plume.gamma = 0.0;
  s.wind_sensor.sigma_a = 0.0;  // the sensor reads the wind itself
  s.robot.start.heading = 0.0;  // body frame = world frame
  std::vector<Vec2> sensed;
  World world(s, 20080101, 0, std::make_unique<WindLogger>(sensed));
  const WindField& field = *world.environment().wind;
  EXPECT_FALSE(field.uniform_in_space());
  for (int k = 1; k <= 30; ++k) {
    const FilamentSpans before = world.environment().odor->snapshot().filaments;
    const std::vector<double> x(before.x.begin(), before.x.end()),
        y(before.y.begin(), before.y.end()), z(before.z.begin(), before.z.end());
    world.step();
    ASSERT_EQ(sensed.size(), static_cast<std::size_t>(k));
    // the sensor read the field as it is after this step's advance, at the robot ...
    const Pose& pose = world.robot().pose;
    const Vec3 here = field.velocity({pose.x, pose.y, 0.0});
    EXPECT_EQ(bits(sensed.back().x), bits(here.x));
    EXPECT_EQ(bits(sensed.back().y), bits(here.y));
    // ... and every filament moved in that same field, at its own place
    const FilamentSpans after = world.environment().odor->snapshot().filaments;
    ASSERT_GE(after.size(), x.size());  // the ring is not full yet: none overwritten
    for (std::size_t i = 0; i < x.size(); ++i) {
      const Vec3 a = field.velocity({x[i], y[i], z[i]});
      ASSERT_EQ(bits(after.x[i]), bits(x[i] + a.x * s.sim.dt)) << "step " << k << " filament " << i;
      ASSERT_EQ(bits(after.y[i]), bits(y[i] + a.y * s.sim.dt)) << "step " << k << " filament " << i;
    }
  }
}

TEST(MeanderWind, AgentsSharingTheMeanderingPlumeEqualSeparateRuns) {
  std::vector<Scenario> scenarios;
  for (Algorithm algorithm : all_algorithms()) {
    Scenario s = meander_scenario();
    s.controller.algorithm = algorithm;
    s.supervisor.timeout = 120.0;
    scenarios.push_back(s);
  }
  scenarios[1].wind_sensor.sigma_a = 0.4;
  testing::expect_shared_plume_equals_runs_alone(scenarios, 20080101, 1);
}

TEST(MeanderWind, TheInsideStaysStableWithSubsteps) {
  Scenario s = meander_scenario();
  s.wind.get<MeanderParams>().gain = 0.3;
  const double dt = 0.4;  // longer than one stable substep of the default grid
  MeanderWind wind = make_meander(s, 4);
  double largest = 0.0;
  for (int k = 0; k < 3000; ++k) {
    wind.step(dt);
    double u_max = 0.0, v_max = 0.0;
    for (int j = 0; j < wind.ny(); ++j) {
      for (int i = 0; i < wind.nx(); ++i) {
        u_max = std::max(u_max, std::abs(wind.u(i, j)));
        v_max = std::max(v_max, std::abs(wind.v(i, j)));
      }
    }
    largest = std::max({largest, u_max, v_max});
    ASSERT_GE(wind.substeps(), 2);
  }
  // the corners' noise has a standard deviation of 0.21 m/s: nothing grew without bound
  EXPECT_LT(largest, 0.9 + 8.0 * std::sqrt(coloured_noise_variance({0.3, 0.1, 0.2})));
}

// issue 22, G1: gain 10, bandwidth 100 and damping 10, each inside its range, made the wind NaN
TEST(MeanderWind, UnstableCombinationsAreRefusedNamingTheKeys) {
  Scenario s = meander_scenario();
  MeanderParams& m = s.wind.get<MeanderParams>();
  m.gain = 10.0;
  m.bandwidth = 100.0;
  m.damping = 10.0;
  try {
    validate(s);
    ADD_FAILURE() << "a meander that overshoots its grid was accepted";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    for (const char* key :
         {"meander.gain", "meander.bandwidth", "meander.damping", "meander.kx", "meander.nx"}) {
      EXPECT_NE(what.find(key), std::string::npos) << key << ": " << what;
    }
  }
}

// every combination validate() accepts, drawn log-uniformly over the keys' whole ranges, keeps
// a finite field bounded by the noise that drives it (the cell Peclet and step bounds of
// docs/model.md section 3.1)
TEST(MeanderWind, EveryAcceptedCombinationStaysFinite) {
  Rng draw(22);
  const auto log_uniform = [&](double lo, double hi) {
    return std::exp(std::log(lo) + draw.uniform() * (std::log(hi) - std::log(lo)));
  };
  int accepted = 0;
  for (int trial = 0; trial < 400 && accepted < 60; ++trial) {
    Scenario s = meander_scenario();
    MeanderParams& m = s.wind.get<MeanderParams>();
    m.gain = log_uniform(1e-3, 10.0);
    m.damping = log_uniform(1e-3, 10.0);
    m.bandwidth = log_uniform(1e-3, 100.0);
    m.kx = log_uniform(1e-2, 1000.0);
    m.ky = log_uniform(1e-2, 1000.0);
    m.nx = 3 + static_cast<int>(draw.uniform() * 40.0);
    m.ny = 3 + static_cast<int>(draw.uniform() * 40.0);
    s.wind.velocity.x = log_uniform(0.05, 5.0);
    s.sim.dt = log_uniform(0.01, 0.5);
    try {
      validate(s);
    } catch (const ConfigError&) {
      continue;
    }
    ++accepted;
    MeanderWind wind = make_meander(s, static_cast<std::uint64_t>(trial));
    const double scale =
        s.wind.velocity.x + std::sqrt(coloured_noise_variance({m.gain, m.damping, m.bandwidth}));
    double cost = 0.0, largest = 0.0;
    for (int k = 0; k < 2000 && cost < 2e6; ++k) {
      wind.step(s.sim.dt);
      cost += static_cast<double>(m.nx * m.ny) * wind.substeps();
      for (int j = 0; j < wind.ny(); ++j) {
        for (int i = 0; i < wind.nx(); ++i) {
          ASSERT_TRUE(std::isfinite(wind.u(i, j)) && std::isfinite(wind.v(i, j)))
              << "gain " << m.gain << " damping " << m.damping << " bandwidth " << m.bandwidth
              << " kx " << m.kx << " ky " << m.ky << " nx " << m.nx << " ny " << m.ny << " dt "
              << s.sim.dt << " at step " << k;
          largest = std::max({largest, std::abs(wind.u(i, j)), std::abs(wind.v(i, j))});
        }
      }
    }
    // the edges reach 7 standard deviations about once in 10^11 draws
    EXPECT_LT(largest, 8.0 * scale) << "gain " << m.gain << " bandwidth " << m.bandwidth;
  }
  EXPECT_GE(accepted, 30);
}

TEST(MeanderWind, BadKeysAreRefusedNamingThem) {
  Scenario s;
  const auto message = [&](const char* key, double value) {
    try {
      set_field(s, key, value);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("meander.kx", 0.0).find("meander.kx"), std::string::npos);
  EXPECT_NE(message("meander.damping", -1.0).find("meander.damping"), std::string::npos);
  EXPECT_NE(message("meander.gain", 11.0).find("meander.gain"), std::string::npos);
  EXPECT_NE(message("meander.bandwidth", 0.0).find("meander.bandwidth"), std::string::npos);
  EXPECT_NE(message("meander.nx", 1.0).find("meander.nx"), std::string::npos);
  // a grid too fine for the step: more than kMaxWindSubsteps substeps
  Scenario fine = meander_scenario();
  MeanderParams& m = fine.wind.get<MeanderParams>();
  m.nx = m.ny = 201;
  m.kx = m.ky = 1000.0;
  try {
    validate(fine);
    ADD_FAILURE() << "a grid needing thousands of substeps was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("meander.kx"), std::string::npos) << e.what();
  }
}

// the wind fields' registrations say what scenario, sweep and trace code ask of them (issue 24)
TEST(WindRegistry, EachFieldSaysThroughItsHooksWhatItIs) {
  const WindRegion arena{0.0, 16.0, -2.0, 2.0}, wider{0.0, 16.0, -3.0, 3.0};
  WindParams wind;
  const WindContext context{
      wind.velocity, arena,
      0.032};  // the constant wind: steady, the same over any region, never refused
  EXPECT_TRUE(wind_is_steady(wind));
  EXPECT_EQ(wind_identity(wind, arena), "");
  MeanderParams& m = wind.get<MeanderParams>();
  m.gain = 10.0;
  m.bandwidth = 100.0;
  EXPECT_NO_THROW(check_wind_field(wind, context));
  // the meander: steady at gain 0 alone, its grid's region part of its identity, its
  // stability checked
  wind.model = WindModel::kMeander;
  EXPECT_FALSE(wind_is_steady(wind));
  EXPECT_THROW(check_wind_field(wind, context), ConfigError);
  m = MeanderParams{};
  EXPECT_NO_THROW(check_wind_field(wind, context));
  EXPECT_NE(wind_identity(wind, arena), wind_identity(wind, wider));
  m.gain = 0.0;
  EXPECT_TRUE(wind_is_steady(wind));
  // the keys live in the field's own table
  EXPECT_EQ(wind_field_registry()[static_cast<std::size_t>(WindModel::kMeander)].table, "meander");
}

TEST(WindRegistry, EveryFactoryThrowsOnAModelItDoesNotKnow) {
  WindParams wind;
  wind.model = static_cast<WindModel>(wind_field_registry().size());
  EXPECT_THROW(make_wind_field(wind, {wind.velocity, {0.0, 16.0, -2.0, 2.0}, 0.032}, Rng(1)),
               std::invalid_argument);
  EXPECT_THROW(wind_is_steady(wind), std::invalid_argument);
  EXPECT_THROW(make_odor_field("no-such-odor", PlumeParams{}, SourceParams{}, 16.0, 1),
               std::invalid_argument);
}

}  // namespace
}  // namespace plumetrace
