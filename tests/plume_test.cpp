#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "env/plume_loops.hpp"
#include "env/vector_math.hpp"
#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/simd.hpp"
#include "plumetrace/env/environment.hpp"
#include "plumetrace/env/filament_plume.hpp"
#include "plumetrace/env/wind.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/world.hpp"
#include "support/loop_checks.hpp"
#include "support/stepped_wind.hpp"

namespace plumetrace {
namespace {

constexpr double kDt = 0.032;
// rate * dt = 100 * 0.032 = 16 / 5 filaments per step
constexpr std::int64_t kPerStepNum = 16, kPerStepDen = 5;

// Filaments released in the first n steps at 100/s and dt = 0.032: floor(3.2 n), exactly.
std::int64_t released_after(std::int64_t n) { return n * kPerStepNum / kPerStepDen; }

// The step (1-based) in which filament number j (1-based) is released: ceil(j / 3.2).
std::int64_t release_step(std::int64_t j) {
  return (j * kPerStepDen + kPerStepNum - 1) / kPerStepNum;
}

// A plume parameter set without random walk or width growth.
PlumeParams noiseless(PlumeParams p) {
  p.sigma_p = 0.0;
  p.gamma = 0.0;
  return p;
}

// Sample mean and variance about a known mean of zero, with 4-sigma checks.
void expect_zero_mean_normal(const std::vector<double>& samples, double stddev) {
  const double n = static_cast<double>(samples.size());
  double s1 = 0.0, s2 = 0.0;
  for (double v : samples) {
    s1 += v;
    s2 += v * v;
  }
  const double var = stddev * stddev;
  EXPECT_NEAR(s1 / n, 0.0, 4.0 * stddev / std::sqrt(n));
  // standard error of the variance estimate about a known mean: sqrt(2 / n) var
  EXPECT_NEAR(s2 / n, var, 4.0 * std::sqrt(2.0 / n) * var);
}

// Per-axis second moment of the release offsets: E[d^2] = m2, Var(d^2) = m4 - m2^2, 4 sigma.
void expect_second_moment(const std::vector<Vec3>& offsets, double Vec3::*axis, double m2,
                          double m4) {
  const double n = static_cast<double>(offsets.size());
  double s = 0.0;
  for (const Vec3& d : offsets) s += (d.*axis) * (d.*axis);
  EXPECT_NEAR(s / n, m2, 4.0 * std::sqrt((m4 - m2 * m2) / n));
}

// Binomial fraction check: k successes in n trials with probability p, 4 sigma.
void expect_fraction(std::int64_t k, std::int64_t n, double p) {
  const double nn = static_cast<double>(n);
  EXPECT_NEAR(static_cast<double>(k) / nn, p, 4.0 * std::sqrt(p * (1.0 - p) / nn));
}

TEST(Plume, ZeroNoiseAdvectionIsExact) {
  const Vec3 a{0.7, -0.3, 0.1};
  const ConstantWind wind(a);
  PlumeParams params = noiseless(plume_preset(PlumePreset::kLochmatter2008));
  params.capacity = 100000;  // no overwrites: index i is the i-th filament released
  FilamentPlume plume(params, SourceParams{}, 16.0, 11);

  // record each filament's release position and release step
  std::vector<Vec3> released;
  std::vector<int> step_of;
  const int n = 300;
  for (int k = 1; k <= n; ++k) {
    plume.step(wind, kDt);
    for (std::size_t i = released.size(); i < plume.size(); ++i) {
      released.push_back({plume.x()[i], plume.y()[i], plume.z()[i]});
      step_of.push_back(k);
    }
  }
  ASSERT_EQ(plume.size(), released.size());
  for (std::size_t i = 0; i < plume.size(); ++i) {
    // a filament released at step k has been advected in steps k+1 .. n
    const double t = (n - step_of[i]) * kDt;
    EXPECT_NEAR(plume.x()[i], released[i].x + a.x * t, 1e-12);
    EXPECT_NEAR(plume.y()[i], released[i].y + a.y * t, 1e-12);
    EXPECT_NEAR(plume.z()[i], released[i].z + a.z * t, 1e-12);
    EXPECT_EQ(plume.w()[i], params.initial_width);
  }
}

TEST(Plume, ZeroNoiseAlongWindMovesOnlyDownwind) {
  const ConstantWind wind({1.0, 0.0, 0.0});
  PlumeParams params = noiseless(PlumeParams{});
  params.capacity = 100000;
  FilamentPlume plume(params, SourceParams{}, 16.0, 5);
  std::vector<Vec3> released;
  std::vector<int> step_of;
  const int n = 200;
  for (int k = 1; k <= n; ++k) {
    plume.step(wind, kDt);
    for (std::size_t i = released.size(); i < plume.size(); ++i) {
      released.push_back({plume.x()[i], plume.y()[i], plume.z()[i]});
      step_of.push_back(k);
    }
  }
  for (std::size_t i = 0; i < plume.size(); ++i) {
    EXPECT_NEAR(plume.x()[i], released[i].x + (n - step_of[i]) * kDt, 1e-12);
    EXPECT_EQ(plume.y()[i], released[i].y);
    EXPECT_EQ(plume.z()[i], released[i].z);
  }
}

// One-step displacements minus advection over many filaments and steps, for one noise mode.
std::vector<double> walk_increments(const PlumeParams& params, const Vec3& a) {
  const ConstantWind wind(a);
  // why: no filament may be overwritten or removed between the copy and the step
  FilamentPlume plume(params, SourceParams{}, 1e12, 2024);
  for (int k = 0; k < 200; ++k) plume.step(wind, kDt);
  std::vector<double> d;
  for (int k = 200; k < 300; ++k) {
    const std::vector<double> x(plume.x().begin(), plume.x().end());
    const std::vector<double> y(plume.y().begin(), plume.y().end());
    const std::vector<double> z(plume.z().begin(), plume.z().end());
    plume.step(wind, kDt);
    for (std::size_t i = 0; i < x.size(); ++i) {
      d.push_back(plume.x()[i] - x[i] - a.x * kDt);
      d.push_back(plume.y()[i] - y[i] - a.y * kDt);
      d.push_back(plume.z()[i] - z[i] - a.z * kDt);
    }
  }
  return d;
}

TEST(Plume, VelocityNoiseStepStdIsSigmaTimesDt) {
  PlumeParams params = plume_preset(PlumePreset::kLochmatter2008);
  params.capacity = 100000;
  params.sigma_p = 0.1;
  ASSERT_EQ(params.noise_mode, NoiseMode::kVelocity);
  EXPECT_DOUBLE_EQ(walk_stddev(params, kDt), 0.1 * kDt);
  expect_zero_mean_normal(walk_increments(params, {1.0, 0.0, 0.0}), 0.1 * kDt);
}

TEST(Plume, PerStepNoiseStepStdIsSigma) {
  const PlumeParams params = plume_preset(PlumePreset::kPaperLiteral);
  ASSERT_EQ(params.noise_mode, NoiseMode::kPerStep);
  EXPECT_DOUBLE_EQ(walk_stddev(params, kDt), 0.1);
  expect_zero_mean_normal(walk_increments(params, {1.0, 0.0, 0.0}), 0.1);
}

TEST(Plume, WienerNoiseStepStdIsSigmaTimesSqrtDt) {
  PlumeParams params = plume_preset(PlumePreset::kLochmatter2008);
  params.capacity = 100000;
  params.noise_mode = NoiseMode::kWiener;
  params.sigma_p = 0.1;
  EXPECT_DOUBLE_EQ(walk_stddev(params, kDt), 0.1 * std::sqrt(kDt));
  expect_zero_mean_normal(walk_increments(params, {0.5, 0.2, -0.1}), 0.1 * std::sqrt(kDt));
}

TEST(Plume, WidthFollowsGrowthRecurrence) {
  const ConstantWind wind({1.0, 0.0, 0.0});
  for (const double gamma : {4e-7, 1e-3}) {
    PlumeParams params;
    params.gamma = gamma;
    params.capacity = 100000;
    FilamentPlume plume(params, SourceParams{}, 16.0, 3);
    plume.step(wind, kDt);  // releases filaments 0..2 with w0
    const int n = 500;
    double w = params.initial_width;
    for (int k = 1; k <= n; ++k) {
      plume.step(wind, kDt);
      w += (gamma / 2.0) * (1.0 / w);  // gamma / (2 w), as the plume computes it
      EXPECT_EQ(plume.w()[0], w) << "gamma " << gamma << " step " << k;
    }
    // w^2 grows by gamma + gamma^2 / (4 w^2) per step: between w0^2 + n gamma and that plus
    // n gamma^2 / (4 w0^2)
    const double w0 = params.initial_width;
    const double lo = w0 * w0 + n * gamma;
    EXPECT_GE(plume.w()[0] * plume.w()[0], lo * (1.0 - 1e-12));
    EXPECT_LE(plume.w()[0] * plume.w()[0], lo + n * gamma * gamma / (4.0 * w0 * w0) + 1e-15);
  }
}

TEST(Plume, ReleasesThreeOrFourPerStepAndExactlyHundredPerSecond) {
  const ConstantWind wind({1.0, 0.0, 0.0});
  PlumeParams params;
  params.capacity = 16;  // storage is irrelevant to the count
  FilamentPlume plume(params, SourceParams{}, 16.0, 9);
  std::uint64_t before = 0;
  for (std::int64_t n = 1; n <= 20000; ++n) {
    plume.step(wind, kDt);
    const std::uint64_t now = plume.released();
    EXPECT_TRUE(now - before == 3 || now - before == 4) << "step " << n;
    ASSERT_EQ(static_cast<std::int64_t>(now), released_after(n)) << "step " << n;
    before = now;
    if (n == 100) {
      EXPECT_EQ(now, 320u);
    }
    // whole seconds that are whole steps: every 4 s = 125 steps
    if (n % 125 == 0) {
      EXPECT_EQ(now, static_cast<std::uint64_t>(100 * (n / 125) * 4));
    }
  }
}

// Positions of the filaments released in `steps` steps, relative to the source centre.
std::vector<Vec3> release_offsets(const PlumeParams& params, const SourceParams& source,
                                  int steps) {
  const ConstantWind wind({1.0, 0.0, 0.0});
  PlumeParams p = params;
  p.lifetime = Lifetime::kLeaveArena;
  // why: removal_x far upwind removes every filament at the next move, so after each step the
  // plume holds exactly the filaments just released, at their release positions
  FilamentPlume plume(p, source, -1e9, 77);
  std::vector<Vec3> out;
  for (int k = 0; k < steps; ++k) {
    plume.step(wind, kDt);
    EXPECT_TRUE(plume.size() == 3 || plume.size() == 4);
    for (std::size_t i = 0; i < plume.size(); ++i) {
      out.push_back({plume.x()[i] - source.center.x, plume.y()[i] - source.center.y,
                     plume.z()[i] - source.center.z});
    }
  }
  return out;
}

TEST(Plume, BallReleaseIsUniformInThreeDimensionalBall) {
  SourceParams source;
  source.center = {2.0, -0.5, 0.3};
  const double r = source.radius;
  ASSERT_EQ(PlumeParams{}.release_shape, ReleaseShape::kBall);
  const auto offsets = release_offsets(PlumeParams{}, source, 10000);
  std::int64_t inner = 0, front = 0, above = 0;
  bool off_plane = false;
  for (const Vec3& d : offsets) {
    const double r2 = d.x * d.x + d.y * d.y + d.z * d.z;
    EXPECT_LE(r2, r * r);
    if (r2 < r * r / 4.0) ++inner;
    if (d.x > 0.0) ++front;
    if (d.z > 0.0) ++above;
    if (d.z != 0.0) off_plane = true;
  }
  const auto n = static_cast<std::int64_t>(offsets.size());
  EXPECT_TRUE(off_plane);
  expect_fraction(inner, n, 1.0 / 8.0);  // volume fraction of the half-radius ball
  expect_fraction(front, n, 0.5);
  expect_fraction(above, n, 0.5);
  // uniform ball: E[x^2] = R^2 / 5 and E[x^4] = 3 R^4 / 35 on each axis
  const double rr = r * r;
  for (double Vec3::*axis : {&Vec3::x, &Vec3::y, &Vec3::z}) {
    expect_second_moment(offsets, axis, rr / 5.0, 3.0 * rr * rr / 35.0);
  }
}

TEST(Plume, DiscReleaseIsUniformInHorizontalDiscAtSourceHeight) {
  SourceParams source;
  source.center = {2.0, -0.5, 0.3};
  const double r = source.radius;
  const PlumeParams params = plume_preset(PlumePreset::kPaperLiteral);
  ASSERT_EQ(params.release_shape, ReleaseShape::kDisc);
  const auto offsets = release_offsets(params, source, 10000);
  std::int64_t inner = 0, front = 0, left = 0;
  for (const Vec3& d : offsets) {
    const double r2 = d.x * d.x + d.y * d.y;
    EXPECT_LE(r2, r * r);
    EXPECT_EQ(d.z, 0.0);
    if (r2 < r * r / 4.0) ++inner;
    if (d.x > 0.0) ++front;
    if (d.y > 0.0) ++left;
  }
  const auto n = static_cast<std::int64_t>(offsets.size());
  expect_fraction(inner, n, 1.0 / 4.0);  // area fraction of the half-radius disc
  expect_fraction(front, n, 0.5);
  expect_fraction(left, n, 0.5);
  // uniform disc: E[x^2] = R^2 / 4 and E[x^4] = R^4 / 8 on each horizontal axis
  const double rr = r * r;
  for (double Vec3::*axis : {&Vec3::x, &Vec3::y}) {
    expect_second_moment(offsets, axis, rr / 4.0, rr * rr / 8.0);
  }
}

// Expected x positions after n steps of a point source at x = 1 in wind (1, 0, 0) without noise,
// when exactly the filaments numbered first..last (1-based) are alive.
std::vector<double> expected_x(std::int64_t n, std::int64_t first, std::int64_t last) {
  std::vector<double> xs;
  for (std::int64_t j = first; j <= last; ++j) xs.push_back(1.0 + (n - release_step(j)) * kDt);
  std::sort(xs.begin(), xs.end());
  return xs;
}

TEST(Plume, RingBufferSaturatesAtCapacityAndOverwritesOldest) {
  const ConstantWind wind({1.0, 0.0, 0.0});
  const PlumeParams params = noiseless(plume_preset(PlumePreset::kLochmatter2008));
  ASSERT_EQ(params.lifetime, Lifetime::kRing);
  ASSERT_EQ(params.capacity, 1600);
  SourceParams source;
  source.radius = 0.0;  // a point source: every filament starts at x = 1
  FilamentPlume plume(params, source, 16.0, 1);
  for (std::int64_t n = 1; n <= 1000; ++n) {
    plume.step(wind, kDt);
    const std::int64_t released = released_after(n);
    ASSERT_EQ(static_cast<std::int64_t>(plume.released()), released);
    ASSERT_EQ(static_cast<std::int64_t>(plume.size()), std::min<std::int64_t>(released, 1600));
    if (n % 100 != 0) continue;
    // the live filaments are exactly the newest min(released, 1600)
    std::vector<double> xs(plume.x().begin(), plume.x().end());
    std::sort(xs.begin(), xs.end());
    const auto want = expected_x(n, std::max<std::int64_t>(1, released - 1599), released);
    ASSERT_EQ(xs.size(), want.size());
    for (std::size_t i = 0; i < xs.size(); ++i) EXPECT_NEAR(xs[i], want[i], 1e-9) << n;
    // without growth an overwritten slot holds a fresh filament of the initial width
    for (double w : plume.w()) EXPECT_EQ(w, params.initial_width);
  }
  // after 32 s the oldest is 16 s old: 1600 filaments at 100/s, minus less than one step
  const double oldest = *std::max_element(plume.x().begin(), plume.x().end()) - 1.0;
  EXPECT_LE(oldest, 16.0 + 1e-9);
  EXPECT_GE(oldest, 16.0 - kDt - 1e-9);
  EXPECT_EQ(plume.released(), 3200u);
}

TEST(Plume, LeaveArenaRemovesFilamentsDownwindOfRemovalX) {
  const ConstantWind wind({1.0, 0.0, 0.0});
  const PlumeParams params = noiseless(plume_preset(PlumePreset::kPaperLiteral));
  ASSERT_EQ(params.lifetime, Lifetime::kLeaveArena);
  SourceParams source;
  source.radius = 0.0;
  const double x_max = 16.0;
  FilamentPlume plume(params, source, x_max, 1);
  // a filament survives m moves while 1 + m dt <= 16, i.e. m <= 468
  const std::int64_t max_moves = 468;
  for (std::int64_t n = 1; n <= 1500; ++n) {
    plume.step(wind, kDt);
    for (double x : plume.x()) ASSERT_LE(x, x_max);
    const std::int64_t released = released_after(n);
    const std::int64_t gone = n > max_moves ? released_after(n - max_moves - 1) : 0;
    ASSERT_EQ(static_cast<std::int64_t>(plume.size()), released - gone) << n;
    if (n > 600) {
      // steady state: rate * (x_max - source.x) / wind speed, within one step's release
      EXPECT_NEAR(static_cast<double>(plume.size()), 100.0 * (x_max - 1.0) / 1.0, 4.0);
    }
  }
  EXPECT_EQ(plume.released(), static_cast<std::uint64_t>(released_after(1500)));
}

TEST(Plume, LeaveArenaWithNoiseKeepsOnlyFilamentsUpwindOfRemovalX) {
  const ConstantWind wind({1.0, 0.0, 0.0});
  const PlumeParams params = plume_preset(PlumePreset::kPaperLiteral);
  FilamentPlume plume(params, SourceParams{}, 6.0, 8);
  for (int n = 0; n < 400; ++n) {
    plume.step(wind, kDt);
    for (double x : plume.x()) ASSERT_LE(x, 6.0);
  }
  EXPECT_LT(plume.size(), plume.released());
}

TEST(Plume, GaussianKernelMatchesFormulaAndCutsAtOneMetre) {
  PlumeParams params = plume_preset(PlumePreset::kLochmatter2008);
  params.kernel = Kernel::kGaussian;
  params.amount = 8.3e9;
  ASSERT_EQ(params.cutoff, 1.0);
  const double s = 8.3e9;
  for (const double w : {0.1, 0.25, 0.5}) {
    for (const double d : {0.0, 0.05, 0.1, 0.3, 0.6, 0.999}) {
      const double want =
          s / (std::sqrt(8.0 * std::pow(kPi, 3)) * w * w * w) * std::exp(-d * d / (w * w));
      EXPECT_NEAR(kernel_value(params, w, d * d), want, 1e-12 * want) << w << " " << d;
    }
    for (const double d : {1.0, 1.001, 2.0, 10.0}) EXPECT_EQ(kernel_value(params, w, d * d), 0.0);
  }
  // just inside the cut-off a wide filament still contributes clearly
  EXPECT_GT(kernel_value(params, 0.5, 0.999 * 0.999), 1e6);
  // peak of a filament with the printed amount: 8.3e9 / (sqrt(8 pi^3) 0.1^3) = 5.26997e11
  EXPECT_NEAR(kernel_value(params, 0.1, 0.0), 5.26997e11, 0.00001e11);
}

TEST(Plume, PrintedKernelMatchesFormulaWithoutCutoff) {
  const PlumeParams params = plume_preset(PlumePreset::kPaperLiteral);
  ASSERT_EQ(params.kernel, Kernel::kPrinted);
  const double s = 8.3e9;
  for (const double w : {0.1, 0.25, 0.5}) {
    for (const double d : {0.0, 0.05, 0.1, 0.3, 0.999, 1.0, 2.0, 5.0}) {
      const double want = s / (w * w * w) * std::exp(-d / (w * w));
      EXPECT_NEAR(kernel_value(params, w, d * d), want, 1e-12 * want) << w << " " << d;
    }
  }
  // infinite cut-off: far filaments still count
  EXPECT_GT(kernel_value(params, 0.5, 5.0 * 5.0), 0.0);
  EXPECT_GT(kernel_value(params, 0.5, 1.5 * 1.5), 1e6);
}

TEST(Plume, ConcentrationOfSingleFilamentEqualsKernel) {
  for (const PlumePreset preset : {PlumePreset::kLochmatter2008, PlumePreset::kPaperLiteral}) {
    PlumeParams params = plume_preset(preset);
    params.release_rate = 2.0;  // with dt = 0.5: exactly one filament per step
    params.sigma_p = 0.0;       // filaments stay where they were released
    SourceParams source;
    source.center = {3.0, 0.5, 0.0};
    source.radius = 0.0;
    const ConstantWind wind({0.0, 0.0, 0.0});
    FilamentPlume plume(params, source, 16.0, 4);
    plume.step(wind, 0.5);
    ASSERT_EQ(plume.size(), 1u);
    const double w = params.initial_width;
    for (const Vec3& u : {Vec3{3.0, 0.5, 0.0}, Vec3{3.1, 0.4, 0.05}, Vec3{3.0, 1.2, 0.0},
                          Vec3{2.0, 0.5, 0.0}, Vec3{5.0, 0.5, 0.0}}) {
      const double d2 = distance_squared(u, source.center);
      EXPECT_DOUBLE_EQ(plume.concentration(u), kernel_value(params, w, d2));
    }
    // two filaments superpose
    plume.step(wind, 0.5);
    ASSERT_EQ(plume.size(), 2u);
    const Vec3 u{3.05, 0.45, 0.0};
    const double d2 = distance_squared(u, source.center);
    EXPECT_DOUBLE_EQ(plume.concentration(u),
                     kernel_value(params, plume.w()[0], d2) + kernel_value(params, w, d2));
  }
}

TEST(Plume, Lochmatter2008PresetMatchesSpecTable) {
  const PlumeParams p = plume_preset(PlumePreset::kLochmatter2008);
  EXPECT_EQ(p.preset, PlumePreset::kLochmatter2008);
  EXPECT_EQ(p.release_rate, 100.0);
  EXPECT_EQ(p.release_shape, ReleaseShape::kBall);
  EXPECT_EQ(p.initial_width, 0.10);
  EXPECT_EQ(p.amount, 1.0);  // the default reading (docs/fidelity.md), not the printed 8.3e9
  EXPECT_EQ(p.noise_mode, NoiseMode::kVelocity);
  EXPECT_EQ(p.sigma_p, 0.02);
  EXPECT_EQ(p.gamma, 4e-7);
  EXPECT_EQ(p.lifetime, Lifetime::kRing);
  EXPECT_EQ(p.capacity, 1600);
  EXPECT_EQ(p.kernel, Kernel::kPrinted);
  EXPECT_EQ(p.cutoff, 1.0);
  // the default-constructed parameters are this preset
  const PlumeParams d;
  EXPECT_EQ(d.preset, p.preset);
  EXPECT_EQ(d.release_shape, p.release_shape);
  EXPECT_EQ(d.noise_mode, p.noise_mode);
  EXPECT_EQ(d.lifetime, p.lifetime);
  EXPECT_EQ(d.kernel, p.kernel);
  EXPECT_EQ(d.cutoff, p.cutoff);
  // the source of docs/model.md section 1
  const SourceParams source;
  EXPECT_EQ(source.center.x, 1.0);
  EXPECT_EQ(source.center.y, 0.0);
  EXPECT_EQ(source.center.z, 0.0);
  EXPECT_EQ(source.radius, 0.12);
}

TEST(Plume, PaperLiteralPresetMatchesSpecTable) {
  const PlumeParams p = plume_preset(PlumePreset::kPaperLiteral);
  EXPECT_EQ(p.preset, PlumePreset::kPaperLiteral);
  EXPECT_EQ(p.release_shape, ReleaseShape::kDisc);
  EXPECT_EQ(p.noise_mode, NoiseMode::kPerStep);
  EXPECT_EQ(p.lifetime, Lifetime::kLeaveArena);
  EXPECT_EQ(p.kernel, Kernel::kPrinted);
  EXPECT_TRUE(std::isinf(p.cutoff));
  EXPECT_GT(p.cutoff, 0.0);
  // rows the presets share
  EXPECT_EQ(p.release_rate, 100.0);
  EXPECT_EQ(p.initial_width, 0.10);
  EXPECT_EQ(p.amount, 8.3e9);
  EXPECT_EQ(p.sigma_p, 0.1);
  EXPECT_EQ(p.gamma, 4e-7);
}

// Farrell et al. (2002)'s relative dispersion (plume.dispersion = "farrell"): a centre with a
// white-noise velocity of diffusivity D wanders with variance 2 D t per axis, and the squared
// width grows as w0^2 + rate t, whatever the time step. 4000 filaments released together at the
// origin, no wind, 1 s at two time steps; the variance of x, y and z within 4 sigma (the sample
// variance of n normals has a standard error of var sqrt(2 / (n - 1))).
TEST(Plume, FarrellDispersionSpreadsCentresAs2DtAndSquaredWidthsAsRateT) {
  PlumeParams p;
  p.dispersion = Dispersion::kFarrell;
  p.relative_diffusivity = 0.01;
  p.spread_rate = 0.002;
  const std::int64_t n = 4000;
  for (const double dt : {0.032, 0.008}) {
    const auto steps = static_cast<int>(std::lround(1.024 / dt));
    const double t = steps * dt;
    std::vector<double> x(n, 0.0), y(n, 0.0), z(n, 0.0), w(n, 0.1), h(n, 10.0);
    Rng rng(2002);
    for (int k = 0; k < steps; ++k) {
      loops::drift_walk_grow(simd::active(), x.data(), y.data(), z.data(), w.data(), h.data(), n,
                             {}, rng.next_u64(), walk_stddev(p, dt), width_growth(p, dt), true);
    }
    const double expected = 2.0 * p.relative_diffusivity * t;
    for (const auto* axis : {&x, &y, &z}) {
      double sum = 0.0;
      for (double v : *axis) sum += v * v;
      const double variance = sum / static_cast<double>(n);
      EXPECT_NEAR(variance, expected, 4.0 * expected * std::sqrt(2.0 / (n - 1.0))) << "dt " << dt;
    }
    for (std::int64_t i = 0; i < n; ++i) {
      ASSERT_NEAR(w[i] * w[i], 0.01 + p.spread_rate * t, 1e-14) << "dt " << dt;
      ASSERT_EQ(h[i], 1.0 / w[i]);
    }
  }
  // the paper's rows do not apply to Farrell's dispersion, and the other way round
  PlumeParams paper;
  paper.relative_diffusivity = 1.0;
  EXPECT_EQ(walk_stddev(paper, 0.032), 0.02 * 0.032);
  EXPECT_EQ(width_growth(paper, 0.032), paper.gamma);
  p.sigma_p = 5.0;
  p.gamma = 1.0;
  EXPECT_EQ(walk_stddev(p, 0.032), std::sqrt(2.0 * 0.01 * 0.032));
  EXPECT_EQ(width_growth(p, 0.032), 0.002 * 0.032);
}

// The Farrell defaults are the paper rows' walk and growth at the default time step, so that
// switching plume.dispersion changes only how they scale with sim.dt.
TEST(Plume, FarrellDefaultsEqualThePaperRowsAtTheDefaultTimeStep) {
  PlumeParams paper, farrell;
  farrell.dispersion = Dispersion::kFarrell;
  EXPECT_NEAR(walk_stddev(farrell, kDt), walk_stddev(paper, kDt), 1e-15);
  EXPECT_NEAR(width_growth(farrell, kDt), width_growth(paper, kDt), 1e-20);
  EXPECT_NEAR(walk_stddev(farrell, kDt / 4), walk_stddev(paper, kDt / 4) * 2.0, 1e-15);
}

TEST(Plume, SameSeedSamePlume) {
  const ConstantWind wind({1.0, 0.0, 0.0});
  FilamentPlume a(PlumeParams{}, SourceParams{}, 16.0, 42),
      b(PlumeParams{}, SourceParams{}, 16.0, 42);
  for (int k = 0; k < 300; ++k) {
    a.step(wind, kDt);
    b.step(wind, kDt);
  }
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.x()[i], b.x()[i]);
    EXPECT_EQ(a.y()[i], b.y()[i]);
    EXPECT_EQ(a.z()[i], b.z()[i]);
    EXPECT_EQ(a.w()[i], b.w()[i]);
  }
}

// Every path this machine runs (simd::available(): scalar, the baseline, AVX2, AVX-512) against
// the scalar formulas (tests/support/loop_checks.hpp; the 64-bit ARM build runs the same check,
// tests/bits)
TEST(Plume, VectorisedLoopsGiveTheScalarFormulasBitForBit) {
  std::string tested;
  EXPECT_EQ(testing::plume_loops_mismatch(&tested), "");
  std::printf("[ measured ] plume loop paths compared on this machine:%s\n", tested.c_str());
}

// A plume stepped and queried under each available path (simd::select, as PLUMETRACE_SIMD
// does) is the same plume, to the bit, as under the scalar path: positions, widths and the
// answers to concentration and threshold queries, in the laminar and the meandering wind.
TEST(Plume, EverySimdPathStepsAndQueriesTheSamePlume) {
  const simd::Path before = simd::active();
  for (const bool meander : {false, true}) {
    Scenario s;
    if (meander) s.wind.model = WindModel::kMeander;
    const auto run = [&](simd::Path path) {
      simd::select(path);
      Environment env = make_environment(s, 5, 0);
      std::vector<double> answers;
      for (int k = 0; k < 400; ++k) {
        step(env, s.sim.dt);
        if (k % 40 != 39) continue;
        for (const Vec3 u : {Vec3{2.0, 0.1, 0.0}, Vec3{8.0, -0.3, 0.0}, Vec3{1.0, 0.0, 0.0}}) {
          answers.push_back(env.odor->concentration(u));
          answers.push_back(env.odor->reaches(u, s.odor.threshold) ? 1.0 : 0.0);
        }
      }
      const OdorSnapshot snap = env.odor->snapshot();
      for (const auto* v :
           {&snap.filaments.x, &snap.filaments.y, &snap.filaments.z, &snap.filaments.w}) {
        answers.insert(answers.end(), v->begin(), v->end());
      }
      return answers;
    };
    const std::vector<double> scalar = run(simd::Path::kScalar);
    for (const simd::Path path : simd::available()) {
      const std::vector<double> got = run(path);
      ASSERT_EQ(got.size(), scalar.size()) << simd::name(path);
      for (std::size_t i = 0; i < got.size(); ++i) {
        ASSERT_EQ(got[i], scalar[i]) << simd::name(path) << " meander " << meander << " " << i;
      }
    }
  }
  simd::select(before);
}

using testing::SteppedWind;

// An odor model of one uniform concentration that records the wind and dt of each step.
class RecordingOdor final : public OdorField {
 public:
  void step(const WindField& wind, double dt) override {
    winds.push_back(wind.velocity({0.0, 0.0, 0.0}).x);
    dts.push_back(dt);
  }
  double concentration(const Vec3&) const override { return 100.0; }
  OdorSnapshot snapshot() const override { return {}; }
  std::vector<double> winds, dts;
};

TEST(Environment, StepAdvancesTheWindThenTheOdorThenTheClockOncePerCall) {
  Environment env;
  auto wind = std::make_unique<SteppedWind>();
  auto odor = std::make_unique<RecordingOdor>();
  const SteppedWind& w = *wind;
  const RecordingOdor& o = *odor;
  env.wind = std::move(wind);
  env.odor = std::move(odor);
  EXPECT_EQ(env.time, 0.0);
  for (int k = 1; k <= 5; ++k) {
    step(env, 0.25);
    EXPECT_EQ(w.steps, k);
    EXPECT_EQ(env.time, 0.25 * k);  // exact: quarters add exactly
    ASSERT_EQ(o.winds.size(), static_cast<std::size_t>(k));
    // the odor moved in the wind already advanced to this step
    EXPECT_EQ(o.winds.back(), 0.5 + 0.1 * k);
    EXPECT_EQ(o.dts.back(), 0.25);
  }
}

TEST(Environment, AnOdorModelAnswersReachesByItsConcentration) {
  const RecordingOdor odor;
  EXPECT_TRUE(odor.reaches({1.0, 2.0, 3.0}, 100.0));
  EXPECT_TRUE(odor.reaches({1.0, 2.0, 3.0}, std::nextafter(100.0, 0.0)));
  EXPECT_FALSE(odor.reaches({1.0, 2.0, 3.0}, std::nextafter(100.0, INFINITY)));
}

TEST(Plume, SnapshotIsTheFilamentArrays) {
  const ConstantWind wind({1.0, 0.0, 0.0});
  FilamentPlume plume(PlumeParams{}, SourceParams{}, 16.0, 3);
  for (int k = 0; k < 50; ++k) plume.step(wind, kDt);
  const OdorSnapshot s = plume.snapshot();
  EXPECT_EQ(s.kind, OdorSnapshotKind::kFilaments);
  ASSERT_EQ(s.filaments.size(), plume.size());
  EXPECT_EQ(s.filaments.x.data(), plume.x().data());
  EXPECT_EQ(s.filaments.y.data(), plume.y().data());
  EXPECT_EQ(s.filaments.z.data(), plume.z().data());
  EXPECT_EQ(s.filaments.w.data(), plume.w().data());
}

TEST(Plume, ReachesAnswersExactlyAsTheFullSum) {
  // why: reaches() sums the nearby blocks largest bound first and settles the answer by a
  // margin; the thresholds here sit at, next to, within and beyond the margin of the full sum,
  // for the default plume (printed kernel cut off at 1 m), with the Gaussian kernel, and the
  // paper's as printed (no cut-off)
  PlumeParams gaussian;
  gaussian.kernel = Kernel::kGaussian;
  const PlumeParams plumes[] = {PlumeParams{}, gaussian, plume_preset(PlumePreset::kPaperLiteral)};
  for (std::size_t preset = 0; preset < 3; ++preset) {
    Scenario s;
    s.plume = plumes[preset];
    const auto wind = make_wind_field(s.wind, wind_context(s), Rng(99));
    FilamentPlume plume(s.plume, s.source, s.arena.x_max, 99);
    for (int i = 0; i < 700; ++i) plume.step(*wind, s.sim.dt);
    Rng rng(5);
    int agree = 0, odor = 0;
    for (int k = 0; k < 4000; ++k) {
      // the default plume perceived at threshold 100 is about 0.4 m wide: sample across its
      // edges, and a quarter of the points farther out, up to 1.5 m from the axis
      const double half = k % 4 == 0 ? 1.5 : 0.3;
      const Vec3 u{1.0 + 15.0 * rng.uniform(), half * (2.0 * rng.uniform() - 1.0),
                   0.1 * rng.uniform()};
      const double c = plume.concentration(u);
      for (const double t : {c, std::nextafter(c, 0.0), std::nextafter(c, INFINITY),
                             c * (1.0 - 1e-12), c * (1.0 + 1e-12), c * (1.0 - 1e-9),
                             c * (1.0 + 1e-9), c * (1.0 + 2e-9), c * 0.5, c * 2.0, 100.0}) {
        if (t <= 0.0) continue;
        EXPECT_EQ(plume.reaches(u, t), c >= t)
            << "at " << u.x << ", " << u.y << " threshold " << t << " plume " << preset;
        ++agree;
      }
      odor += c >= 100.0;
    }
    EXPECT_GT(agree, 30000);
    if (preset == 0) {
      EXPECT_GT(odor, 100);  // the points cover both sides of the plume's edge
      EXPECT_LT(odor, 3900);
    }
  }
}

TEST(Plume, KernelReachIsWhereTheKernelFallsToTheFloor) {
  for (const Kernel kernel : {Kernel::kPrinted, Kernel::kGaussian}) {
    PlumeParams p;
    p.kernel = kernel;
    p.amount = kernel == Kernel::kGaussian ? 8.3e9 : 1.0;
    p.cutoff = INFINITY;
    for (const double w : {0.05, 0.1, 0.3}) {
      for (const double floor : {1e-7, 1.0, 50.0}) {
        const double r = kernel_reach(p, w, floor);
        if (kernel_value(p, w, 0.0) < floor) {
          EXPECT_EQ(r, 0.0);
          continue;
        }
        ASSERT_GT(r, 0.0);
        EXPECT_GE(kernel_value(p, w, r * r * (1 - 1e-9)), floor) << w << " " << floor;
        EXPECT_LT(kernel_value(p, w, r * r * (1 + 1e-9)), floor) << w << " " << floor;
      }
    }
    // never beyond the cut-off, where the kernel is 0
    p.cutoff = 0.01;
    EXPECT_EQ(kernel_reach(p, 0.1, 1e-12), 0.01);
  }
}

}  // namespace
}  // namespace plumetrace
